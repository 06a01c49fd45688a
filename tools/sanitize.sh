#!/usr/bin/env bash
# Builds the unit and verification tests with AddressSanitizer and
# UndefinedBehaviorSanitizer into build-asan/ and runs the unit tests (and,
# with --all, every test). About 10 minutes of build on 2 cores, so it is not
# part of ./test.sh (docs/reliability.md).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -f build-asan/CMakeCache.txt ]; then
  cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBAKESIM_SANITIZE=ON >/dev/null
fi
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
if [ "${1:-}" = "--all" ]; then
  cmake --build build-asan --parallel "$(nproc)"
  cd build-asan && ctest --output-on-failure -j"$(nproc)"
else
  cmake --build build-asan --parallel "$(nproc)" --target unit_tests fuzz_scene fuzz_mesh_files fuzz_solver fuzz_checkpoint
  ./build-asan/tests/unit_tests
  ./build-asan/tests/fuzz/fuzz_scene 3000 scenes tests/data tests/fuzz/seeds/scene
  ./build-asan/tests/fuzz/fuzz_mesh_files 3000 scenes/meshes tests/data/meshes tests/fuzz/seeds/ply
  ./build-asan/tests/fuzz/fuzz_solver 100 scenes tests/data
  ./build-asan/tests/fuzz/fuzz_checkpoint 1000 tests/fuzz/seeds/checkpoint
fi
