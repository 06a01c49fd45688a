#!/usr/bin/env bash
# The Blender add-on (tools/blender/bakesim_import) on a short run with a still
# and a moving collider: installed from its zip and enabled as Preferences >
# Install does, its operator imports the run (see blender_check.py for what is
# checked). Skipped (exit 77) where Blender is not installed; it is not in the
# install script (about 70 packages; docs/surfaces.md).
set -u
BAKESIM="$1"
ROOT="$2"
command -v blender >/dev/null 2>&1 || { echo "blender not installed: skipped"; exit 77; }
OUT="$(mktemp -d)"
trap 'rm -rf "$OUT"' EXIT
sed -e 's|"bodies": \[|"name": "blender-check", "colliders": [{"name": "tray", "shape": {"type": "plane", "point": [0, 0.06, 0], "normal": [0, 1, 0]}}, {"name": "paddle", "shape": {"type": "box", "min": [0.02, 0.02, 0.02], "max": [0.05, 0.05, 0.05]}, "motion": {"keyframes": [{"time": 0}, {"time": 0.02, "translation": [0.01, 0, 0]}]}}, {"name": "ghost", "look": "hidden", "shape": {"type": "box", "min": [0.15, 0.0, 0.0], "max": [0.2, 0.05, 0.05]}}],\n  "bodies": [|' \
  "$ROOT/tests/data/good_small.json" >"$OUT/scene.json"
"$BAKESIM" run "$OUT/scene.json" --out "$OUT/run" --quiet || exit 1
"$BAKESIM" mesh "$OUT/run" 2>/dev/null || exit 1
# The same body as chocolate (a raw_colour): imported with the vertex colours bakesim gave it.
sed -e 's|"density": 1000}|"density": 1000, "raw_colour": [17.4, 2.6, 1.4]}|' -e 's|"blender-check"|"blender-check-chocolate"|' \
  "$OUT/scene.json" >"$OUT/chocolate.json"
"$BAKESIM" run "$OUT/chocolate.json" --out "$OUT/chocolate" --quiet || exit 1
"$BAKESIM" mesh "$OUT/chocolate" 2>/dev/null || exit 1
python3 "$ROOT/tools/blender/make_addon.py" "$OUT" >/dev/null || exit 1
# A user folder of its own, so the add-on is not installed into the machine's Blender configuration.
export BLENDER_USER_CONFIG="$OUT/config" BLENDER_USER_SCRIPTS="$OUT/scripts"
blender -b --factory-startup --python "$ROOT/tests/regression/blender_check.py" -- \
  "$OUT/bakesim_import.zip" "$OUT/run" "$OUT/chocolate" ${BLENDER_CHECK_PNG:+"$BLENDER_CHECK_PNG"} >"$OUT/blender.txt" 2>&1
grep -q "blender_check: ok" "$OUT/blender.txt" && { echo "ok: $(grep 'blender_check: ok' "$OUT/blender.txt")"; exit 0; }
cat "$OUT/blender.txt"
exit 1
