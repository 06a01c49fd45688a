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
png_width() { /usr/bin/python3 -c 'import struct, sys; print(struct.unpack(">I", open(sys.argv[1], "rb").read()[16:20])[0])' "$1"; }
check '[ "$(png_width "$OUT/sph/render/particles-temperature-strip.png")" -eq $((3 * 160 + 130)) ]' "the strip is its three frames and a 130-pixel panel for the colour bar"
# The scene's render section: its colour (and range) when --colour is not given, the domain drawn as a tank.
"$BAKESIM" run "$ROOT/tests/data/good_small.json" --out "$OUT/tank" --quiet \
  --set render.colour=speed --set 'render.range=[0,0.5]' --set render.domain_walls=metal
"$BAKESIM" render "$OUT/tank" --width 160 --height 90 2>/dev/null
check '[ $? -eq 0 ] && png "$OUT/tank/render/mesh-speed-00002.png"' "render uses the scene's render.colour"
"$BAKESIM" render "$OUT/tank" --colour browning --width 160 --height 90 2>/dev/null
check '[ $? -eq 0 ] && png "$OUT/tank/render/mesh-browning-00002.png" && ! cmp -s "$OUT/tank/render/mesh-browning-00002.png" "$OUT/sph/render/mesh-browning-00002.png"' "--colour wins over the scene's; the metal tank changes the picture"
sed -i 's/"domain_walls": "metal"/"domain_walls": "marble"/' "$OUT/tank/scene.json"
"$BAKESIM" render "$OUT/tank" 2>"$OUT/tank-err.txt"
check '[ $? -eq 2 ] && grep -q "render.domain_walls" "$OUT/tank-err.txt"' "an unknown tank look is refused naming render.domain_walls (exit 2)"
"$BAKESIM" plot "$OUT/sph" >"$OUT/plots.txt"
check '[ $? -eq 0 ] && png "$OUT/sph/plots/temperatures.png"' "sph: plot writes temperatures.png"

# Colliders: drawn in the pictures and exported beside the body meshes, a still one once, a moving one per frame.
mkdir -p "$OUT/scn"
cp "$ROOT/scenes/meshes/funnel.obj" "$OUT/scn/bowl.obj"
sed -e 's|"bodies": \[|"colliders": [{"name": "tray", "shape": {"type": "plane", "point": [0, 0.06, 0], "normal": [0, 1, 0]}}, {"name": "paddle", "look": "wood", "shape": {"type": "box", "min": [0.02, 0.02, 0.02], "max": [0.05, 0.05, 0.05]}, "motion": {"keyframes": [{"time": 0}, {"time": 0.02, "translation": [0.01, 0, 0]}]}}, {"name": "bowl", "look": "glass", "shape": {"type": "mesh", "file": "bowl.obj", "scale": 0.2, "translation": [0.15, 0.1, 0.15]}}, {"name": "ghost", "look": "hidden", "shape": {"type": "box", "min": [0.15, 0.0, 0.0], "max": [0.2, 0.05, 0.05]}}],\n  "bodies": [|' \
    "$ROOT/tests/data/good_small.json" > "$OUT/scn/colliders.json"
"$BAKESIM" run "$OUT/scn/colliders.json" --out "$OUT/col" --quiet
check '[ $? -eq 0 ]' "a scene with a plane, a moving box, a mesh and a hidden collider runs"
"$BAKESIM" mesh "$OUT/col" 2>"$OUT/col-mesh.txt"
check '[ $? -eq 0 ] && grep -q "5 collider meshes in meshes/colliders/" "$OUT/col-mesh.txt"' "mesh: colliders exported ($(cat "$OUT/col-mesh.txt"))"
check '[ -s "$OUT/col/meshes/colliders/tray.ply" ] && [ -s "$OUT/col/meshes/colliders/bowl.ply" ] && [ -s "$OUT/col/meshes/colliders/paddle-00000.ply" ] && [ -s "$OUT/col/meshes/colliders/paddle-00002.ply" ] && [ ! -e "$OUT/col/meshes/colliders/ghost.ply" ]' "still colliders once, the moving one per frame, the hidden one not"
check 'head -c 300 "$OUT/col/meshes/colliders/tray.ply" | grep -q "property uchar red"' "collider PLY carries its look's colour"
"$BAKESIM" mesh "$OUT/col" --vdb --frame 2 2>/dev/null
check '[ $? -eq 0 ] && [ -s "$OUT/col/meshes/00002.vdb" ]' "mesh --vdb writes NNNNN.vdb"
if command -v vdb_print >/dev/null; then
  vdb_print "$OUT/col/meshes/00002.vdb" >"$OUT/vdb.txt" 2>&1
  check '[ $? -eq 0 ] && grep -q "^surface " "$OUT/vdb.txt" && grep -q "^temperature " "$OUT/vdb.txt" && grep -q "^browning " "$OUT/vdb.txt"' "OpenVDB's vdb_print reads it: surface, temperature, browning"
else
  echo "note: vdb_print (Debian libopenvdb-tools) not installed: the .vdb was not opened with OpenVDB's tools"
fi
"$BAKESIM" render "$OUT/col" --width 160 --height 90 2>"$OUT/col-render.txt"
check '[ $? -eq 0 ] && png "$OUT/col/render/mesh-browning-00002.png" && ! grep -q "not drawn" "$OUT/col-render.txt"' "render draws the frame with its colliders"
"$BAKESIM" render "$OUT/col" --width 160 --height 90 --cut z --colour temperature 2>/dev/null
check '[ $? -eq 0 ] && png "$OUT/col/render/mesh-temperature-cut-z-00002.png"' "render --cut z: a cut view"
"$BAKESIM" render "$OUT/col" --mode particles --cut x=0.1 --width 160 --height 90 2>/dev/null
check '[ $? -eq 0 ] && png "$OUT/col/render/particles-browning-cut-x-00002.png"' "render --mode particles --cut x=0.1"
"$BAKESIM" render "$OUT/col" --turntable 3 --width 160 --height 90 2>/dev/null
check '[ $? -eq 0 ] && png "$OUT/col/render/mesh-browning-00002-turn-000.png" && png "$OUT/col/render/mesh-browning-00002-turn-002.png" && ! cmp -s "$OUT/col/render/mesh-browning-00002-turn-000.png" "$OUT/col/render/mesh-browning-00002-turn-001.png"' "render --turntable 3: three different views"
"$BAKESIM" render "$OUT/col" --camera 0.1,0.3,0.4 --look-at 0.1,0.1,0.1 --fov 25 --width 160 --height 90 2>/dev/null
check '[ $? -eq 0 ] && ! cmp -s "$OUT/col/render/mesh-browning-00002.png" "$OUT/col/render/mesh-browning-00002-turn-000.png"' "render --camera --look-at --fov: another view"
"$BAKESIM" render "$OUT/col" --camera 0.1,0.1 2>"$OUT/cam.txt"
check '[ $? -eq 2 ] && grep -q "render --camera" "$OUT/cam.txt"' "a camera that is not X,Y,Z is refused (exit 2)"
"$BAKESIM" render "$OUT/col" --cut q=1 2>"$OUT/cut.txt"
check '[ $? -eq 2 ] && grep -q "render --cut" "$OUT/cut.txt"' "a bad --cut is refused naming the option (exit 2)"
# A run written before environment.emissivity existed (its scene.json lacks the key) still renders:
# opening a run fills in the defaults of keys added since.
/usr/bin/python3 -c 'import json,sys; p=sys.argv[1]; d=json.load(open(p)); del d["environment"]["emissivity"]; json.dump(d, open(p, "w"))' "$OUT/col/scene.json"
"$BAKESIM" render "$OUT/col" --width 160 --height 90 2>"$OUT/col-old.txt"
check '[ $? -eq 0 ]' "a run whose scene.json predates environment.emissivity renders ($(tail -1 "$OUT/col-old.txt"))"
# The mesh file gone from beside the scene: that collider is left out, with a note; the picture is still made.
rm "$OUT/scn/bowl.obj"
"$BAKESIM" render "$OUT/col" --width 160 --height 90 2>"$OUT/col-gone.txt"
check '[ $? -eq 0 ] && grep -q "collider bowl not drawn" "$OUT/col-gone.txt"' "a collider whose mesh file is gone is named, the picture still made"

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
