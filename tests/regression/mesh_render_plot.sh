#!/usr/bin/env bash
# `bakesim mesh`, `render` and `plot` on short runs of both solvers, and the
# scene's output.mesh option: the promised files appear, meshes are PLY with
# colours and UVs and OBJ with a material and texture, pictures are PNG, and a
# directory that is not a run is refused with exit code 2.
source "$(dirname "$0")/common.sh"
png() { [ -s "$1" ] && head -c 8 "$1" | od -An -c | grep -q "P   N   G"; }

# SPH: run, then mesh (both methods), render (mesh and particles), plot.
"$BAKESIM" run "$ROOT/tests/data/good_small.json" --out "$OUT/sph" --quiet
"$BAKESIM" mesh "$OUT/sph" 2>"$OUT/mesh.txt"
check '[ $? -eq 0 ] && grep -q "meshed 3 frames" "$OUT/mesh.txt"' "sph: mesh meshes every frame"
check '[ -s "$OUT/sph/meshes/00002.ply" ] && [ -s "$OUT/sph/meshes/00002.obj" ]' "sph: PLY and OBJ per frame"
check 'head -c 400 "$OUT/sph/meshes/00002.ply" | grep -q "property uchar red" && head -c 400 "$OUT/sph/meshes/00002.ply" | grep -q "property float s"' "mesh PLY has vertex colours and UVs"
check 'grep -q "^mtllib bakesim_baking.mtl" "$OUT/sph/meshes/00002.obj" && grep -q "^vt " "$OUT/sph/meshes/00002.obj"' "OBJ has a material and UVs"
check 'grep -q "map_Kd gradient_baking.png" "$OUT/sph/meshes/bakesim_baking.mtl" && png "$OUT/sph/meshes/gradient_baking.png"' "material maps the gradient texture"
"$BAKESIM" mesh "$OUT/sph" --method wyvill --frame 1 --color temperature 2>/dev/null
check '[ $? -eq 0 ] && grep -q "bakesim_heat.mtl" "$OUT/sph/meshes/00001.obj"' "sph: wyvill method, temperature colours"
"$BAKESIM" render "$OUT/sph" --width 160 --height 90 2>/dev/null
check '[ $? -eq 0 ] && png "$OUT/sph/render/mesh-browning-00002.png"' "sph: render draws the last frame"
"$BAKESIM" render "$OUT/sph" --mode particles --color temperature --all --strip --width 160 --height 90 2>/dev/null
check '[ $? -eq 0 ] && png "$OUT/sph/render/particles-temperature-00000.png" && png "$OUT/sph/render/particles-temperature-strip.png"' "sph: particle pictures of every frame and a strip"
"$BAKESIM" plot "$OUT/sph" >"$OUT/plots.txt"
check '[ $? -eq 0 ] && png "$OUT/sph/plots/temperatures.png"' "sph: plot writes temperatures.png"

# MPM: a scene with meshing during the run.
sed -e 's/"type": "sph", "sph": {"spacing": 0.01}/"type": "mpm", "mpm": {"cell_size": 0.02}/' \
    -e 's/"time": {/"output": {"mesh": {"enabled": true}}, "time": {/' "$ROOT/tests/data/good_small.json" > "$OUT/mpm.json"
"$BAKESIM" run "$OUT/mpm.json" --out "$OUT/mpm" --quiet
check '[ $? -eq 0 ] && [ -s "$OUT/mpm/meshes/00002.ply" ] && [ -s "$OUT/mpm/meshes/00002.obj" ]' "mpm: output.mesh meshes during the run"
"$BAKESIM" render "$OUT/mpm" --width 160 --height 90 2>/dev/null
check '[ $? -eq 0 ] && png "$OUT/mpm/render/mesh-browning-00002.png"' "mpm: render"
"$BAKESIM" plot "$OUT/mpm" >/dev/null
check '[ $? -eq 0 ] && png "$OUT/mpm/plots/volume.png"' "mpm: plot writes volume.png"

# Bad input: not a run directory, unknown colour quantity.
"$BAKESIM" mesh "$OUT" 2>"$OUT/err.txt"
check '[ $? -eq 2 ] && grep -q "not a run directory" "$OUT/err.txt"' "mesh refuses a directory that is not a run (exit 2)"
"$BAKESIM" render "$OUT/sph" --color flavour 2>"$OUT/err.txt"
check '[ $? -eq 2 ] && grep -q "no quantity .flavour." "$OUT/err.txt"' "render names an unknown colour quantity (exit 2)"
check '[ -z "$(find "$OUT" -name "*.tmp*")" ]' "no temporary files left behind"
exit $fail
