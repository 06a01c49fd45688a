#!/usr/bin/env bash
# The Blender importer (tools/blender_import_bakesim.py) on a short run's
# meshes. Skipped (exit 77) where Blender is not installed; it is not in the
# install script (see docs/surfaces.md).
set -u
BAKESIM="$1"
ROOT="$2"
command -v blender >/dev/null 2>&1 || { echo "blender not installed: skipped"; exit 77; }
OUT="$(mktemp -d)"
trap 'rm -rf "$OUT"' EXIT
"$BAKESIM" run "$ROOT/tests/data/good_small.json" --out "$OUT/run" --quiet || exit 1
"$BAKESIM" mesh "$OUT/run" 2>/dev/null || exit 1
blender -b --factory-startup --python "$ROOT/tests/regression/blender_check.py" -- \
  "$ROOT/tools/blender_import_bakesim.py" "$OUT/run" >"$OUT/blender.txt" 2>&1
grep -q "blender_check: ok" "$OUT/blender.txt" && { echo "ok: blender imports the mesh sequence"; exit 0; }
cat "$OUT/blender.txt"
exit 1
