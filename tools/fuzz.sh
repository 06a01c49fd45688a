#!/usr/bin/env bash
# Open-ended fuzzing with libFuzzer, AddressSanitizer and UBSan (clang from
# Debian: clang, libclang-rt-14-dev). Builds the fuzz targets into build-fuzz/
# and runs each for SECONDS (default 600) on a copy of its seed corpus.
#   tools/fuzz.sh [SECONDS] [fuzz_scene|fuzz_mesh_files|fuzz_solver|fuzz_checkpoint ...]   (default: all four)
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_EACH="${1:-600}"
shift || true
TARGETS=("${@:-fuzz_scene fuzz_mesh_files fuzz_solver fuzz_checkpoint}")
TARGETS=(${TARGETS[*]})
if [ ! -f build-fuzz/CMakeCache.txt ]; then
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBAKESIM_FUZZ=ON >/dev/null
fi
cmake --build build-fuzz --parallel "$(nproc)" --target "${TARGETS[@]}"
run() {
  local target="$1"; shift
  local corpus="build-fuzz/corpus-$target"
  mkdir -p "$corpus"
  for seed in "$@"; do find "$seed" -type f -exec cp {} "$corpus/" \; ; done
  echo "== $target for $SECONDS_EACH s"
  "build-fuzz/tests/fuzz/$target" "$corpus" -max_total_time="$SECONDS_EACH" -rss_limit_mb=4096 -timeout=60 \
    -print_final_stats=1 2>&1 | tail -15
}
for t in "${TARGETS[@]}"; do
  case "$t" in
    fuzz_scene) run fuzz_scene scenes tests/data tests/fuzz/seeds/scene ;;
    fuzz_mesh_files) run fuzz_mesh_files scenes/meshes tests/data/meshes tests/fuzz/seeds/ply ;;
    fuzz_solver) run fuzz_solver scenes tests/data ;;
    fuzz_checkpoint) run fuzz_checkpoint tests/fuzz/seeds/checkpoint ;;
    *) echo "unknown fuzz target: $t" >&2; exit 2 ;;
  esac
done
