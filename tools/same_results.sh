#!/usr/bin/env bash
# Bakes a fixed set of short SPH and MPM runs with one bakesim binary and prints
# a SHA-256 per run of its frames and of stats.csv without the wall_time column.
# Run it with the binary before and after a refactoring: the lists must match.
#   tools/same_results.sh BAKESIM OUT_DIR [THREADS]
set -euo pipefail
BIN=$(realpath "$1"); OUT=$2; THREADS=${3:-2}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$OUT"
# Implicit heat: the cookie with heat "implicit" (no shipped MPM scene uses it).
/usr/bin/python3 - "$ROOT/scenes/cookie.json" "$OUT/cookie-implicit.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1])); d["solver"]["mpm"]["heat"] = "implicit"; d["name"] = "cookie-implicit"
json.dump(d, open(sys.argv[2], "w"), indent=1)
PY
runs=(
  "bread-roll:$ROOT/scenes/bread-roll.json:0.1"          # SPH: heat, bubbles, surface exchange, hot tray
  "dam-break:$ROOT/scenes/dam-break.json:0.06"           # SPH: pressure, walls
  "melting-bunny:$ROOT/scenes/melting-bunny.json:0.1"    # SPH: implicit viscosity, heat, peak-following curves
  "cookie:$ROOT/scenes/cookie-oven-180.json:0.2"         # MPM: heat, water, gas, Cam-clay setting
  "cookie-implicit:$OUT/cookie-implicit.json:0.1"        # MPM: implicit heat (conjugate gradients)
  "pancake:$ROOT/scenes/pancake.json:0.25"               # MPM: moving collider (pitcher), heat, water, gas
  "dough-pull-twist:$ROOT/scenes/dough-pull-twist.json:0.1"  # MPM: moving sticky grips
)
for r in "${runs[@]}"; do
  IFS=: read -r name scene end <<<"$r"
  rm -rf "${OUT:?}/$name"
  "$BIN" run "$scene" --out "$OUT/$name" --end-time "$end" --threads "$THREADS" --quiet
  frames=$(cd "$OUT/$name" && cat frames/* | sha256sum | cut -c1-16)
  stats=$(cut -d, -f1-16,18- "$OUT/$name/stats.csv" | sha256sum | cut -c1-16)
  echo "$name frames $frames stats $stats ($(ls "$OUT/$name/frames" | wc -l) files, $(($(wc -l <"$OUT/$name/stats.csv") - 1)) frames)"
done
