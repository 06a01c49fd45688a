#!/usr/bin/env bash
# Pictures of the seed figures the shipped scenes reproduce (docs/figures.md):
# each scene baked with --preview (the volcano in full: its preview lava cools
# before it overflows), then drawn with `bakesim render`; the pictures are
# copied to OUT/pictures/ under the names docs/images/ uses.
#
#   tools/figure_pictures.sh OUT [--threads N] [NAME ...]
#
# NAME picks figures by picture name (e.g. fig-3.3-dam-break); default: all.
# About 10 minutes on 2 cores for the previews plus about 10 for the volcano.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
BAKESIM="${BAKESIM:-$ROOT/build/app/bakesim}"
[ -x "$BAKESIM" ] || BAKESIM="$(command -v bakesim)"
OUT="${1:?usage: tools/figure_pictures.sh OUT [--threads N] [NAME ...]}"
shift
THREADS=2
if [ "${1:-}" = "--threads" ]; then THREADS="$2"; shift 2; fi
WANTED=("$@")
mkdir -p "$OUT/pictures"

wanted() {
  [ ${#WANTED[@]} -eq 0 ] && return 0
  local w
  for w in "${WANTED[@]}"; do [ "$w" = "$1" ] && return 0; done
  return 1
}

# bake SCENE [run options...]: into OUT/SCENE unless already there.
bake() {
  local scene="$1"; shift
  grep -q "\] done: " "$OUT/$scene/log.txt" 2>/dev/null && return 0  # baked to its end before
  rm -rf "${OUT:?}/$scene"
  echo "== $scene: bakesim run scenes/$scene.json $*"
  "$BAKESIM" run "$ROOT/scenes/$scene.json" --out "$OUT/$scene" --threads "$THREADS" --quiet "$@"
}

# picture NAME SCENE RUN_OPTIONS -- RENDER_OPTIONS: bake, render, copy the picture the render names last.
picture() {
  local name="$1" scene="$2"; shift 2
  wanted "$name" || return 0
  local run_opts=() render_opts=()
  while [ $# -gt 0 ] && [ "$1" != "--" ]; do run_opts+=("$1"); shift; done
  [ $# -gt 0 ] && shift
  render_opts=("$@")
  bake "$scene" "${run_opts[@]}"
  echo "== $name: bakesim render $OUT/$scene ${render_opts[*]}"
  local said
  said="$("$BAKESIM" render "$OUT/$scene" --threads "$THREADS" "${render_opts[@]}" 2>&1 | tail -1)"
  echo "$said"
  local file
  case "$said" in
    *", strip "*) file="${said##*, strip }" ;;
    *) file="${said##*: }" ;;
  esac
  cp "$file" "$OUT/pictures/$name.png"
}

STRIP=(--all --strip --width 320 --height 300)
# The thesis (seed 000)
picture fig-3.3-dam-break dam-break --preview -- "${STRIP[@]}"
picture fig-3.4-3.5-3.13-elasticity elasticity-tests --preview --
picture fig-3.9-immiscible-collision immiscible-collision --preview --
picture fig-3.10-velocity-tuner velocity-tuner-tests --preview -- --frame 2
picture fig-3.14-melting-bunny melting-bunny --preview -- "${STRIP[@]}"
picture fig-3.15-viscous-funnel viscous-funnel --preview -- "${STRIP[@]}"
picture fig-3.16-viscous-funnel-thick viscous-funnel-thick --preview -- "${STRIP[@]}"
picture fig-3.17-volcano volcano -- "${STRIP[@]}"
picture fig-4.4cd-bread-roll-centred bread-roll-centred --preview -- --cut z
picture fig-4.5-container-solidification container-solidification --preview -- --cut z --colour temperature
picture fig-4.11-angel-food-cake angel-food-cake --preview -- --cut z
# The thermomechanical MPM paper (seed 003)
picture paper-fig-6-dough-pull-twist dough-pull-twist --preview -- "${STRIP[@]}"
picture paper-fig-13-pancake pancake --preview -- "${STRIP[@]}"
picture paper-fig-13-pancake-cut pancake --preview -- --cut z
picture paper-fig-16-smore smore --preview -- "${STRIP[@]}"
picture paper-fig-18-bread-tear bread-tear --preview -- "${STRIP[@]}"
echo "pictures in $OUT/pictures/"
