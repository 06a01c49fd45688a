#!/usr/bin/env bash
# bakesim report: a self-contained HTML page, checked as Chromium renders it
# (headless, Debian's chromium): its plots are laid out, its pictures decode,
# its numbers are the run's, and measured data are overlaid and compared.
source "$(dirname "$0")/common.sh"
CHROMIUM="$(command -v chromium || command -v chromium-browser || true)"
if [ -z "$CHROMIUM" ]; then
  echo "SKIP: no chromium (scripts/install-deps.sh installs it)"
  exit 77
fi

# A short MPM bake with water and heat: the cookie's preview, 5.4 minutes of oven (its core passes 95 degC).
"$BAKESIM" run "$ROOT/scenes/cookie.json" --preview --end-time 0.9 --out "$OUT/run" --quiet
check '[ $? -eq 0 ]' "the bake runs"
# Measured data 2 degC above the simulated core at every frame (so the RMS difference is 2.00 degC), with a spread.
awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; print "# made by report.sh"; print "t_min,T_C,T_std_C,moisture_db"; next }
  { printf "%.9g,%.9g,0.5,%.9g\n", $col["bake_time"] / 60, $col["core_temperature:cookie"] + 2, 0.6 * (1 - $col["moisture_loss_percent:cookie"] / 100) }' \
  "$OUT/run/stats.csv" > "$OUT/measured.csv"
rows=$(($(wc -l < "$OUT/measured.csv") - 2))
"$BAKESIM" report "$OUT/run" --compare "$OUT/measured.csv=core_temperature:cookie" >"$OUT/report.txt" 2>&1
check '[ $? -eq 0 ] && grep -qx "$OUT/run/report.html" "$OUT/report.txt"' "report writes RUN_DIR/report.html"
check '[ -z "$(grep -o "src=\"[^d][^\"]*\"\|href=\|url(" "$OUT/run/report.html")" ]' "the page needs no other file (pictures inline, no links)"
check 'grep -q "wall radiation</th><td>none<" "$OUT/run/report.html"' "the scene table says whether the oven walls radiate"
check '! grep -q "air pressure</th>" "$OUT/run/report.html"' "a sea-level bake's scene table has no air-pressure row"
"$BAKESIM" run "$ROOT/scenes/cookie.json" --preview --end-time 0.05 --set environment.altitude=1000 --out "$OUT/high" --quiet &&
  "$BAKESIM" report "$OUT/high" >/dev/null 2>&1
check 'grep -q "air pressure</th><td>89.9 kPa (1000 m up): free water boils at 96.7 °C<" "$OUT/high/report.html"' "the scene table names the altitude's pressure and boiling point"
sed "s|REPORT|file://$OUT/run/report.html|" "$ROOT/tests/regression/report_check.html" > "$OUT/check.html"
timeout 120 "$CHROMIUM" --headless --no-sandbox --disable-gpu --disable-dev-shm-usage --allow-file-access-from-files --virtual-time-budget=10000 \
  --dump-dom "file://$OUT/check.html" 2>/dev/null | sed -n '/<pre/,/<\/pre>/p' | sed 's/<[^>]*>//g' > "$OUT/seen.txt"
cat "$OUT/seen.txt"
seen() { grep -qx "$1" "$OUT/seen.txt"; }
check 'seen "title=bakesim report: cookie-preview"' "Chromium loads the page"
check 'seen "plots=4" && seen "plots_drawn=4"' "four SVG plots, laid out (temperature, volume, rise, moisture)"
check 'seen "images=3" && seen "images_decoded=3"' "the pictures of the first and last frame and the cut view of the last decode"
check 'seen "measured_markers=$rows"' "every measured point is drawn on the temperature plot ($rows)"
check 'seen "done_line=true"' "the temperature plot has the doneness line"
check 'seen "rms=2.00 °C"' "the RMS difference from the measured data is 2.00 degC"
check 'seen "visible_results=true"' "the results table is laid out"
# The numbers are those of stats.csv.
last_core="$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next } { v = $col["core_temperature:cookie"] } END { printf "%.1f", v }' "$OUT/run/stats.csv")"
check 'seen "core=$last_core °C"' "the final core temperature is the last row of stats.csv ($last_core degC)"
check 'grep -q "^done=[0-9.]* min$" "$OUT/seen.txt" && grep -q "^weight=[0-9.]* % of the mass$" "$OUT/seen.txt" && grep -q "^crust-colour=.*browning index" "$OUT/seen.txt" && grep -q "^heat-in=[0-9.]* kJ" "$OUT/seen.txt"' "time to 95 degC, weight loss, crust colour and heat in are shown"
# A moist bake (the Zhang loaf on 8 mm cells, under a second): its crust thickness and the crust's and
# crumb's moisture are in the results table, as the last row of stats.csv has them.
"$BAKESIM" run "$ROOT/scenes/zhang-loaf-unrisen-mpm.json" --set solver.mpm.cell_size=0.008 --out "$OUT/moist" --quiet --threads 1
"$BAKESIM" report "$OUT/moist" >/dev/null 2>&1
crust_layer="$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next } { t = $col["crust_thickness:loaf"]; c = $col["crust_moisture:loaf"]; m = $col["crumb_moisture:loaf"] } END { printf "%.1f mm (%.2f; %.2f kg/kg)", 1000 * t, c, m }' "$OUT/moist/stats.csv")"
check 'grep -qF "data-key=\"crust-layer\">$crust_layer<" "$OUT/moist/report.html" && [ "${crust_layer%% *}" != "0.0" ]' "a moist bake's crust is in the results ($crust_layer)"
timeout 120 "$CHROMIUM" --headless --no-sandbox --disable-gpu --disable-dev-shm-usage --hide-scrollbars --window-size=1200,2400 \
  --screenshot="$OUT/report.png" "file://$OUT/run/report.html" >/dev/null 2>&1
check '[ "$(head -c 4 "$OUT/report.png" | od -An -c | tr -d " ")" = "211PNG" ] && [ "$(stat -c %s "$OUT/report.png")" -gt 50000 ]' "Chromium screenshots the page"
[ -n "${BAKESIM_REPORT_SCREENSHOT:-}" ] && cp "$OUT/report.png" "$BAKESIM_REPORT_SCREENSHOT"
# Bad measured data is refused with the file named.
printf 'minutes,T_C\n1,20\n' > "$OUT/no-time.csv"
"$BAKESIM" report "$OUT/run" --compare "$OUT/no-time.csv" 2>"$OUT/no-time.txt"
check '[ $? -eq 2 ] && grep -q "no-time.csv: needs a time column" "$OUT/no-time.txt"' "measured data without a time column is refused"
"$BAKESIM" report "$OUT/run" --compare "$OUT/measured.csv=core:nothing" 2>"$OUT/no-column.txt"
check '[ $? -eq 2 ] && grep -q "stats.csv has no such column" "$OUT/no-column.txt"' "an unknown stats.csv column is refused"
# A run whose scene.json was edited into another shape is named (exit 2), not reported with JSON's message alone.
cp -r "$OUT/run" "$OUT/edited"
sed -i 's/"bodies": \[/"bodies": 5, "unused": [/' "$OUT/edited/scene.json"
"$BAKESIM" report "$OUT/edited" 2>"$OUT/edited.txt"
check '[ $? -eq 2 ] && grep -q "edited/scene.json: does not read as the resolved scene of a run" "$OUT/edited.txt"' "a hand-edited scene.json is refused with its file named"
# A run written before a key existed (here environment.emissivity): the report reads it with the key's default.
cp -r "$OUT/run" "$OUT/older"
/usr/bin/python3 -c 'import json,sys; p=sys.argv[1]; d=json.load(open(p)); del d["environment"]["emissivity"]; json.dump(d, open(p, "w"))' "$OUT/older/scene.json"
"$BAKESIM" report "$OUT/older" >/dev/null 2>"$OUT/older.txt"
check '[ $? -eq 0 ] && grep -q "wall radiation</th><td>none<" "$OUT/older/report.html"' "a run older than a key reports with its default"
exit $fail
