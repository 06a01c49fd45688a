#!/usr/bin/env bash
# Pictures of the seed figures the shipped scenes reproduce (docs/figures.md):
# each scene baked with --preview (the volcano in full: its preview lava cools
# before it overflows), then drawn with `bakesim render`; the pictures are
# copied to OUT/pictures/ under the names docs/images/ uses.
#
#   tools/figure_pictures.sh OUT [--threads N] [NAME ...]
#
# NAME picks figures by picture name (e.g. fig-3.3-dam-break); default: all.
# On 2 cores: about 10 minutes for the previews drawn on 2026-12-04, 13 for those
# added on 2026-12-05 (the sums of their runs), and about 10 for the volcano.
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
  cp "$(draw "$scene" "${render_opts[@]}")" "$OUT/pictures/$name.png"
}

# draw SCENE RENDER_OPTIONS: render the baked scene, print the picture the render names last.
draw() {
  local scene="$1"; shift
  local said
  said="$("$BAKESIM" render "$OUT/$scene" --threads "$THREADS" "$@" 2>&1 | tail -1)"
  echo "$said" >&2
  case "$said" in
    *", strip "*) echo "${said##*, strip }" ;;
    *) echo "${said##*: }" ;;
  esac
}

# side_by_side NAME SCENE... [-- RENDER_OPTIONS]: each scene's preview, last frame, in one row (ffmpeg's hstack).
side_by_side() {
  local name="$1"; shift
  wanted "$name" || return 0
  local scenes=() inputs=() scene
  while [ $# -gt 0 ] && [ "$1" != "--" ]; do scenes+=("$1"); shift; done
  [ $# -gt 0 ] && shift
  for scene in "${scenes[@]}"; do
    bake "$scene" --preview
    inputs+=(-i "$(draw "$scene" --width 640 --height 400 "$@")")
  done
  ffmpeg -loglevel error -y "${inputs[@]}" -filter_complex "hstack=inputs=${#scenes[@]}" "$OUT/pictures/$name.png"
  echo "== $name: $OUT/pictures/$name.png"
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
picture fig-4.3-4.4ab-4.8-bread-roll bread-roll --preview -- --cut z
picture fig-4.5-container-solidification container-solidification --preview -- --cut z --colour temperature
picture fig-4.11-angel-food-cake angel-food-cake --preview -- --cut z
picture fig-4.12-4.13-bread-of-the-dead bread-of-the-dead --preview --
# The thermomechanical MPM paper (seed 003)
picture paper-fig-6-dough-pull-twist dough-pull-twist --preview -- "${STRIP[@]}"
picture paper-fig-9-dehydrating-fruit dehydrating-fruit --preview --
picture paper-fig-10-bread-loaf-one-slit bread-loaf-one-slit --preview --
picture paper-fig-10-bread-loaf-two-slits bread-loaf-two-slits --preview --
picture paper-fig-10-bread-loaf-cut bread-loaf --preview -- --cut z --camera 0.16,0.15,0.2 --look-at 0,0.045,-0.02
side_by_side paper-fig-12-cookie-leavener cookie-leavener-low cookie-leavener-medium cookie-leavener-high \
  -- --camera 0.075,0.06,0.095 --look-at 0,0.004,0
picture paper-fig-13-pancake pancake --preview -- "${STRIP[@]}"
picture paper-fig-13-pancake-cut pancake --preview -- --cut z
picture paper-fig-14-muffin-tray muffin-tray --preview --
picture paper-fig-15-lava-cake lava-cake --preview -- "${STRIP[@]}"
picture paper-fig-15-lava-cake-cut lava-cake --preview -- --camera 0.11,0.09,0.15 --look-at 0,0.02,0
picture paper-fig-16-smore smore --preview -- "${STRIP[@]}"
picture paper-fig-18-bread-tear bread-tear --preview -- "${STRIP[@]}"
echo "pictures in $OUT/pictures/"
