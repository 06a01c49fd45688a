#!/usr/bin/env bash
# A short run writes every promised output: resolved scene, PLY and VTU frames,
# the ParaView series, stats.csv with the promised columns, and log.txt.
source "$(dirname "$0")/common.sh"

"$BAKESIM" run "$ROOT/tests/data/good_small.json" --out "$OUT/run" 2>"$OUT/stderr.txt"
rc=$?
check '[ $rc -eq 0 ]' "run exits 0"
check 'grep -q "particle-steps/s" "$OUT/stderr.txt"' "summary printed"
check 'grep -q "output: $OUT/run" "$OUT/stderr.txt"' "summary names the output directory"
check '[ -s "$OUT/run/scene.json" ] && grep -q "smoothing_ratio" "$OUT/run/scene.json"' "resolved scene.json with defaults"
check '[ -s "$OUT/run/frames/00000.ply" ] && [ -s "$OUT/run/frames/00002.ply" ]' "PLY frames 0..2"
check 'head -c 40 "$OUT/run/frames/00002.ply" | grep -q "format binary_little_endian"' "PLY is binary little-endian"
check '[ -s "$OUT/run/frames/00002.vtu" ] && grep -c DataSet "$OUT/run/particles.pvd" | grep -qx 3' "VTU frames listed in particles.pvd"
check '[ -s "$OUT/run/log.txt" ] && grep -q "limited by" "$OUT/run/log.txt"' "log names the active time-step bound"
header="$(head -1 "$OUT/run/stats.csv")"
for col in time steps dt particles kinetic_energy max_speed min_x min_y min_z max_x max_y max_z \
           mean_temperature min_temperature max_temperature; do
  check 'tr , "\n" <<<"$header" | grep -qx "$col"' "stats.csv has column $col"
done
check '[ "$(wc -l < "$OUT/run/stats.csv")" -eq 4 ]' "stats.csv has one row per frame (3 frames + header)"
# Per-body bake statistics come for both solvers (src/sim/bake_stats.hpp).
for col in volume:block height:block core_temperature:block crust_temperature:block; do
  check 'tr , "\n" <<<"$header" | grep -qx "$col"' "SPH stats.csv has column $col"
done
check '! grep -q "youngs_modulus" "$OUT/run/scene.json"' "the resolved SPH scene holds no MPM keys"
check '[ -z "$(find "$OUT/run" -name ".*tmp*")" ]' "no temporary files left behind"
# --end-time overrides the scene and is recorded in the resolved scene.
"$BAKESIM" run "$ROOT/tests/data/good_small.json" --out "$OUT/short" --end-time 0.01 --quiet
check 'grep -q "\"end\": 0.01" "$OUT/short/scene.json"' "--end-time recorded in scene.json"
exit $fail
