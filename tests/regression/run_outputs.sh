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
# The summary names what was written (it promised particles.pvd to runs without VTU frames).
sed 's/"solver"/"output": {"particles": ["ply"]}, "solver"/' "$ROOT/tests/data/good_small.json" > "$OUT/ply-only.json"
"$BAKESIM" run "$OUT/ply-only.json" --out "$OUT/ply-only" --end-time 0.02 2>"$OUT/ply-only.txt"
check 'grep -q "output: $OUT/ply-only/ (frames/ (ply), stats.csv" "$OUT/ply-only.txt" && ! grep -q pvd "$OUT/ply-only.txt" && [ ! -e "$OUT/ply-only/particles.pvd" ]' "a run without VTU frames does not promise particles.pvd"
check 'grep -q "output: $OUT/run/ (particles.pvd, frames/ (ply, vtu)" "$OUT/stderr.txt"' "a run with VTU frames names particles.pvd"
# A run directory given as the scene: the message says how to resume it.
"$BAKESIM" run "$OUT/run" 2>"$OUT/rundir.txt"
check '[ $? -eq 2 ] && grep -q "is a run directory, not a scene file: to go on with that run, bakesim run --resume $OUT/run" "$OUT/rundir.txt"' "bakesim run RUN_DIR suggests --resume"
# Values that look like a unit mistake are warned about, not refused.
sed 's/"solver"/"environment": {"air_temperature": 493}, "solver"/' "$ROOT/tests/data/good_small.json" > "$OUT/kelvin.json"
"$BAKESIM" validate "$OUT/kelvin.json" >/dev/null 2>"$OUT/kelvin.txt"
check '[ $? -eq 0 ] && grep -q "warning: environment.air_temperature reaches 493 degC: .*493 K would be 220 degC" "$OUT/kelvin.txt"' "an oven at 493 degC is warned about as kelvin or degF"
# A body its particle lattice fills short is warned about, with what the lattice holds (geometry/shapes.hpp).
"$BAKESIM" validate "$ROOT/scenes/tin-loaf-sph.json" --set solver.sph.spacing=0.003 2>"$OUT/fill.txt" >"$OUT/fill-summary.txt"
check '[ $? -eq 0 ] && grep -q "warning: .*bodies\[0\]: body .loaf. is sampled as 94.2% of its volume (17400 particles of 3 mm.*the lattice spans 114.0 x 45.0 x 114.0 mm of its 115.6 x 47.5 x 115.6 mm; solver.sph.spacing 0.00296875 would fill 99.4%" "$OUT/fill.txt"' "a loaf sampled at 94% of its volume is warned about, with the spacing that fills it"
check 'grep -q "fills 94.2% of its shape.s volume" "$OUT/fill-summary.txt"' "validate's summary says what each body's lattice fills"
"$BAKESIM" validate "$ROOT/scenes/tin-loaf-sph.json" 2>"$OUT/fill-shipped.txt" >/dev/null
check '[ $? -eq 0 ] && ! grep -q "sampled as" "$OUT/fill-shipped.txt"' "the shipped SPH tin loaf fills its tin"
# --set changes the scene before it is checked and is recorded in the resolved scene (which re-runs as it is).
"$BAKESIM" run "$ROOT/tests/data/good_small.json" --out "$OUT/set" --end-time 0.01 --quiet --set bodies[0].temperature=5 --set environment.air_temperature=200
check '[ $? -eq 0 ] && grep -q "\"air_temperature\": 200" "$OUT/set/scene.json" && grep -q -- "--set bodies\[0\].temperature=5" "$OUT/set/log.txt"' "--set recorded in scene.json and log.txt"
check '[ "$(cut -d, -f13 "$OUT/set/stats.csv" | sed -n 2p)" = 5 ]' "--set bodies[0].temperature=5: the first frame's mean temperature is 5"
"$BAKESIM" run "$OUT/set/scene.json" --out "$OUT/set-again" --quiet
check '[ $? -eq 0 ] && cmp -s "$OUT/set/frames/00001.ply" "$OUT/set-again/frames/00001.ply"' "the resolved scene.json re-runs to the same frames"
"$BAKESIM" validate "$ROOT/tests/data/good_small.json" --set bodies[0].temperature=hot 2>"$OUT/set-bad.txt" >/dev/null
check '[ $? -eq 2 ] && grep -q "bodies\[0\].temperature: expected a number" "$OUT/set-bad.txt"' "a bad --set value is refused with its key path"
# stats.units.csv: one row per stats.csv column, in order, with its unit.
check '[ "$(tail -n +2 "$OUT/run/stats.units.csv" | cut -d, -f1 | paste -sd,)" = "$header" ]' "stats.units.csv lists every stats.csv column in order"
for pair in time,s dt,s kinetic_energy,J max_speed,m/s min_y,m mean_temperature,degC volume:block,m3 height:block,m core_temperature:block,degC; do
  check 'grep -qx "$pair" "$OUT/run/stats.units.csv"' "stats.units.csv: $pair"
done
# A bake: the progress bar counts minutes of oven with the core temperature, the summary says what the bake did.
"$BAKESIM" run "$ROOT/tests/data/resume_mpm.json" --out "$OUT/bake" --threads 2 2>"$OUT/bake.txt"
check 'tr "\r" "\n" < "$OUT/bake.txt" | grep -q "100%  bake 1.3/1.3 min  core [0-9.]* degC  frame 20/20"' "the progress bar shows bake minutes and the core temperature"
core="$(head -1 "$OUT/bake/stats.csv" | tr , '\n' | grep -nx "core_temperature:dough" | cut -d: -f1)"
last_core="$(tail -1 "$OUT/bake/stats.csv" | cut -d, -f"$core")"
check 'grep -q "^bake of 1.3 min: dough: core $(printf %.1f "$last_core") degC, crust [0-9.]* degC, volume x[0-9.]*, moisture loss [0-9.]* %" "$OUT/bake.txt"' "the summary ends with the bake's results (core $last_core degC, from stats.csv)"
check 'grep -Eq "^bake of 1.3 min: dough: .*, (done \(95 degC\) after [0-9.]+ min|not done \(95 degC not reached\))$" "$OUT/bake.txt"' "the summary says when the core was done (95 degC at sea level)"
check '! grep -q "bake of\\|  bake [0-9]" "$OUT/stderr.txt" && grep -q "t=0.020/0.020 s" "$OUT/stderr.txt"' "a 0.02 s run of water is not called a bake"
# A run's scene.json re-runs from its own directory also when the scene has meshes (their paths are made absolute).
"$BAKESIM" run "$ROOT/scenes/viscous-funnel.json" --out "$OUT/funnel" --end-time 0.01 --quiet
check 'grep -q "\"file\": \"/.*/scenes/meshes/funnel.obj\"" "$OUT/funnel/scene.json"' "mesh paths in the resolved scene are absolute"
(cd "$OUT/funnel" && "$BAKESIM" run scene.json --out "$OUT/funnel-again" --quiet)
check '[ $? -eq 0 ] && cmp -s "$OUT/funnel/frames/00001.ply" "$OUT/funnel-again/frames/00001.ply"' "a run's scene.json with meshes re-runs from its run directory to the same frames"
# "extends": a variant in another folder builds on a base; the run's scene.json stands alone and re-runs.
mkdir -p "$OUT/variants"
printf '{"extends": "%s", "name": "warm", "environment": {"air_temperature": 60}}\n' \
  "$ROOT/tests/data/good_small.json" > "$OUT/variants/warm.json"
"$BAKESIM" validate "$OUT/variants/warm.json" > "$OUT/warm-validate.txt"
check '[ $? -eq 0 ] && grep -q "^extends    .*good_small.json" "$OUT/warm-validate.txt"' "validate names the base a variant extends"
"$BAKESIM" validate "$ROOT/tests/data/good_small.json" --set environment.air_temperature=200 --set environment.emissivity=0.9 > "$OUT/oven-validate.txt"
check 'grep -q "^oven       air 200 degC, h 10 W/(m^2 K), wall radiation at emissivity 0.9" "$OUT/oven-validate.txt"' "validate says the oven: air, coefficient, wall radiation"
"$BAKESIM" validate "$ROOT/tests/data/good_small.json" --set environment.altitude=2000 > "$OUT/altitude-validate.txt"
check 'grep -q "air pressure 79.5 kPa: free water boils at 93.4 degC" "$OUT/altitude-validate.txt"' "validate says where water boils at the scene's altitude"
"$BAKESIM" validate "$OUT/variants/warm.json" --resolved > "$OUT/warm-resolved.json"
check 'grep -q "\"air_temperature\": 60" "$OUT/warm-resolved.json" && ! grep -q extends "$OUT/warm-resolved.json"' "validate --resolved prints the merged scene"
(cd "$OUT/variants" && "$BAKESIM" run warm.json --out "$OUT/warm" --end-time 0.02 --quiet)
check '[ $? -eq 0 ] && grep -q "extends .*good_small.json" "$OUT/warm/log.txt" && ! grep -q extends "$OUT/warm/scene.json"' "a variant runs; log.txt names its base, scene.json has it merged in"
"$BAKESIM" run "$OUT/warm/scene.json" --out "$OUT/warm-again" --quiet
check '[ $? -eq 0 ] && cmp -s "$OUT/warm/frames/00001.ply" "$OUT/warm-again/frames/00001.ply"' "a variant's resolved scene.json re-runs to the same frames"
# A preset is named by validate and in the log, with what it gave.
"$BAKESIM" validate "$ROOT/scenes/cookie-on-a-tray.json" > "$OUT/preset.txt"
check 'grep -q "^material   .*materials.dough: preset cookie-dough (density [0-9.]* kg/m^3.*divided by the bake clock 1440" "$OUT/preset.txt"' "validate says what the preset gave"
# --preview: twice the spacing (or the nearest finer one that fills the body within 5%: this
# 60 mm sphere holds 19 particles of 20 mm, 134% of its volume; 15 mm fill 95.5%), at most
# 10 frames, pictures, into out/NAME-preview.
sed 's/"time": {"end": 0.02, "fps": 100}/"name": "small", "time": {"end": 0.04, "fps": 500}/' \
  "$ROOT/tests/data/good_small.json" > "$OUT/small.json"
(cd "$OUT" && "$BAKESIM" run small.json --preview 2>"$OUT/preview.txt")
check '[ $? -eq 0 ] && [ -f "$OUT/out/small-preview/scene.json" ]' "--preview runs into out/NAME-preview"
check 'grep -q "\"spacing\": 0.015," "$OUT/out/small-preview/scene.json" && grep -q "\"fps\": 250" "$OUT/out/small-preview/scene.json"' "the preview coarsens the spacing, keeping the body, and keeps to 10 frames (scene.json)"
check '[ "$(ls "$OUT"/out/small-preview/frames/*.ply | wc -l)" -eq 11 ]' "the preview writes frames 0..10"
check '[ -s "$OUT/out/small-preview/render/mesh-browning-00000.png" ] && [ -s "$OUT/out/small-preview/render/mesh-browning-00010.png" ]' "the preview draws the first and the last frame"
check 'grep -q "render/ (2 pictures, the last mesh-browning-00010.png)" "$OUT/preview.txt" && grep -q "preview: spacing 0.015 m, 250 fps" "$OUT/out/small-preview/log.txt"' "the summary and the log say what the preview did"
# --end-time overrides the scene and is recorded in the resolved scene.
"$BAKESIM" run "$ROOT/tests/data/good_small.json" --out "$OUT/short" --end-time 0.01 --quiet
check 'grep -q "\"end\": 0.01" "$OUT/short/scene.json"' "--end-time recorded in scene.json"
exit $fail
