#!/usr/bin/env bash
# Installs what is missing, builds Release, and bakes the default scene into out/:
# first a preview (about a minute on two cores, with a picture), then the full
# bake, drawing pictures of its frames as they are written.
set -euo pipefail
cd "$(dirname "$0")"
./scripts/install-deps.sh
./scripts/build.sh bakesim   # only the command line: the tests and benchmarks are built by ./test.sh
SCENE="${1:-scenes/bread-roll.json}"
NAME="$(basename "$SCENE" .json)"
B=./build/app/bakesim
OUT="out/$NAME"
$B run "$SCENE" --preview --out "$OUT-preview"  # 8x fewer particles, 10 frames, pictures in render/
echo "A first look: $(ls "$OUT-preview"/render/mesh-*.png | tail -1)"
$B run "$SCENE" --out "$OUT" --pictures         # the full bake; pictures in $OUT/render/ as it goes
$B mesh "$OUT"                                  # surface meshes of every frame: meshes/NNNNN.ply, .obj
$B render "$OUT" --all --width 640 --height 360 --strip --movie  # small pictures of every frame, a strip, an MP4 if ffmpeg is there
$B render "$OUT"                                # the final frame at full size
$B render "$OUT" --cut z                        # cut in half: the crumb's pores inside the crust
$B render "$OUT" --mode particles --color temperature
$B plot "$OUT" >/dev/null                       # plots/temperatures.png, volume.png, height.png
echo "In $OUT/: render/ (pictures, strip, movie), meshes/ (PLY, OBJ+MTL for Blender or Houdini),"
echo "plots/ (probe temperatures, volume, height), frames/ + particles.pvd (ParaView), stats.csv."
echo "The preview is in $OUT-preview/."
