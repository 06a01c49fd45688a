#!/usr/bin/env bash
# bakesim sweep: a grid of runs from one scene, their table and plots; a bad
# value refused before anything runs; a second call keeps finished runs; a
# stopped sweep resumes its runs from their checkpoints. The runs go to a Dask
# LocalCluster by default (python3-distributed and the Python module, as
# ./test.sh installs and builds them), as processes with --processes, and to
# a scheduler and worker started by hand with --dask ADDRESS: the same frames
# byte for byte, the same stop and resume.
source "$(dirname "$0")/common.sh"
DASK=0
if /usr/bin/python3 -c "import distributed" 2>/dev/null && [ -f "$(dirname "$BAKESIM")/../python/bakesim/dask_runs.py" ]; then
  DASK=1
fi
same_frames() {  # same_frames SWEEP_DIR OTHER_SWEEP_DIR: every frame of every run equal byte for byte
  local run f n=0
  for run in "$1"/runs/*; do
    for f in "$run"/frames/*; do
      cmp -s "$f" "$2/runs/$(basename "$run")/frames/$(basename "$f")" || return 1
      n=$((n + 1))
    done
  done
  [ $n -gt 0 ]
}

# A water ball heated through on a fast bake clock: its core passes 95 degC.
sed 's/"solver"/"environment": {"bake_time_scale": 300000}, "solver"/' "$ROOT/tests/data/good_small.json" > "$OUT/ball.json"
"$BAKESIM" sweep "$OUT/ball.json" --set environment.air_temperature=90,250 --set 'bodies[0].temperature=10,30' \
  --set time.fps=200 --out "$OUT/sw" >"$OUT/table.md" 2>"$OUT/sweep.txt"
rc=$?
check '[ $rc -eq 0 ]' "a 2 x 2 sweep exits 0"
check '[ "$(wc -l < "$OUT/sw/sweep.csv")" -eq 5 ] && [ "$(ls "$OUT/sw/runs" | wc -l)" -eq 4 ]' "sweep.csv has a row per run, runs/ a directory per run"
check 'head -1 "$OUT/sw/sweep.csv" | grep -q "^run,air_temperature,temperature,fps,status,bake_minutes,core_degC:block,crust_degC:block,minutes_to_done:block,volume_ratio:block,height_cm:block,heat_in_kJ,wall_seconds,directory$"' "sweep.csv names its columns with units"
check 'grep -q "^| air_temperature=250,temperature=30 | 250 | 30 | done |" "$OUT/table.md" && cmp -s "$OUT/table.md" "$OUT/sw/sweep.md"' "the Markdown table is printed and written"
check 'grep -q "\[4/4\]" "$OUT/sweep.txt" && grep -q "2 at a time\|1 at a time" "$OUT/sweep.txt"' "progress names each finished run"
if [ $DASK -eq 1 ]; then
  check 'grep -q "on a Dask LocalCluster" "$OUT/sweep.txt"' "the runs went to a Dask LocalCluster (Dask and the module are installed)"
  "$BAKESIM" sweep "$OUT/ball.json" --set environment.air_temperature=90,250 --set 'bodies[0].temperature=10,30' \
    --set time.fps=200 --out "$OUT/sw-processes" --processes >/dev/null 2>"$OUT/processes.txt"
  check '[ $? -eq 0 ] && grep -q "as processes here" "$OUT/processes.txt" && same_frames "$OUT/sw" "$OUT/sw-processes"' "--processes: the same frames byte for byte as on Dask"
else
  check 'grep -q "the runs go as processes here" "$OUT/sweep.txt"' "without Dask the runs go as processes here, saying why"
fi
check '[ "$(head -c 8 "$OUT/sw/plots/core_temperature.png" | od -An -c | tr -d " ")" = "211PNG\r\n032\n" ]' "the core temperature plot is a PNG"
# Every number in the table comes from the run's own stats.csv (last row; first crossing of 95 degC).
for run in "$OUT"/sw/runs/*; do
  name="$(basename "$run")"
  expected="$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
    { t = $col["bake_time"]; c = $col["core_temperature:block"];
      if (!done && c >= 95) { done = 1; at = (NR == 2) ? t : pt + (95 - pc) / (c - pc) * (t - pt) }
      pt = t; pc = c; last = c }
    END { printf "%.2f %.2f\n", last, done ? at / 60 : -1 }' "$run/stats.csv")"
  got="$(/usr/bin/python3 -c '
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
r = [x for x in rows if x["directory"] == "runs/" + sys.argv[2]][0]
print("%.2f %.2f" % (float(r["core_degC:block"]), float(r["minutes_to_done:block"] or -1)))' "$OUT/sw/sweep.csv" "$name")"
  check '[ "$got" = "$expected" ]' "$name: core and time to 95 degC in sweep.csv ($got) as in its stats.csv ($expected)"
  check 'grep -q "\"temperature\": [13]0" "$run/scene.json"' "$name: its scene.json records its values"
done
check 'grep -q "^| air_temperature=90,temperature=10 | 90 | 10 | done | 100.0 | [0-9.]* | [0-9.]* | not reached |" "$OUT/table.md" && grep -q "^| air_temperature=250,temperature=30 | 250 | 30 | done | 100.0 | [0-9.]* | [0-9.]* | [0-9][0-9.]* |" "$OUT/table.md"' "the table says when the core reached 95 degC, or that it did not"
# A second call with the same grid runs nothing again.
before="$(stat -c %Y "$OUT"/sw/runs/*/stats.csv | sort | tr '\n' ' ')"
"$BAKESIM" sweep "$OUT/ball.json" --set environment.air_temperature=90,250 --set 'bodies[0].temperature=10,30' \
  --set time.fps=200 --out "$OUT/sw" >/dev/null 2>"$OUT/again.txt"
check '[ $? -eq 0 ] && grep -q "(0 to run" "$OUT/again.txt" && [ "$(stat -c %Y "$OUT"/sw/runs/*/stats.csv | sort | tr "\n" " ")" = "$before" ]' "a second call keeps the finished runs"
# A bad value anywhere in the grid is refused before anything runs.
"$BAKESIM" sweep "$OUT/ball.json" --set environment.air_temperature=150,hot --out "$OUT/bad" 2>"$OUT/bad.txt"
check '[ $? -eq 2 ] && grep -q "environment.air_temperature" "$OUT/bad.txt" && grep -q "in the sweep.s run air_temperature=hot" "$OUT/bad.txt" && [ ! -e "$OUT/bad" ]' "a bad value is refused with its run, nothing written"
"$BAKESIM" sweep "$OUT/ball.json" --set environment.air_temperature=150 --out "$OUT/one" 2>"$OUT/one.txt"
check '[ $? -eq 2 ] && grep -q "two or more values" "$OUT/one.txt"' "a sweep of one run is refused"
mkdir -p "$OUT/foreign" && echo mine > "$OUT/foreign/notes.txt"
"$BAKESIM" sweep "$OUT/ball.json" --set environment.air_temperature=150,180 --out "$OUT/foreign" 2>"$OUT/foreign.txt"
check '[ $? -eq 2 ] && grep -q "holds no bakesim sweep" "$OUT/foreign.txt" && [ "$(ls "$OUT/foreign")" = notes.txt ]' "a foreign directory is refused and left alone"
# Stopped: each run checkpoints; the same command again resumes them to the end. On Dask and as processes.
stop_and_resume() {  # stop_and_resume NAME [ENGINE OPTION]
  local name="$1" pid rc n f
  shift
  "$BAKESIM" sweep "$ROOT/tests/data/good_small.json" --set environment.air_temperature=100,200 --end-time 2 \
    --jobs 2 --threads 1 --out "$OUT/$name" "$@" >/dev/null 2>"$OUT/$name.txt" &
  pid=$!
  for _ in $(seq 1 300); do
    n=0
    for f in "$OUT/$name"/runs/*/stats.csv; do [ -f "$f" ] && [ "$(wc -l < "$f")" -ge 4 ] && n=$((n + 1)); done
    [ $n -ge 2 ] && break
    sleep 0.1
  done
  kill -TERM $pid
  wait $pid
  rc=$?
  check '[ $rc -eq 143 ] && grep -q "run the same command again" "$OUT/$name.txt"' "$name: SIGTERM stops the sweep (exit 143)"
  check '[ "$(ls "$OUT/$name"/runs/*/checkpoints/*.ckpt | wc -l)" -ge 2 ] && [ "$(grep -c "stopped (signal 15)" "$OUT/$name/bakesim-sweep.json")" -eq 2 ]' "$name: each stopped run wrote a checkpoint and is marked stopped"
  # As processes: the marker as a sweep killed outright (or one whose Dask helper was lost) leaves it,
  # its runs still "running": the next call resumes them all the same.
  if [ "$name" = stop-processes ]; then sed -i 's/"stopped (signal 15)"/"running"/' "$OUT/$name/bakesim-sweep.json"; fi
  "$BAKESIM" sweep "$ROOT/tests/data/good_small.json" --set environment.air_temperature=100,200 --end-time 2 \
    --jobs 2 --threads 1 --out "$OUT/$name" "$@" >/dev/null 2>"$OUT/$name-resume.txt"
  check '[ $? -eq 0 ] && grep -q "resumed from" "$OUT/$name"/runs/1-*/log.txt && grep -q "resumed from" "$OUT/$name"/runs/2-*/log.txt' "$name: the same command again resumes both runs"
  check '[ "$(wc -l < "$OUT/$name"/runs/1-air_temperature=100/stats.csv)" -eq 202 ]' "$name: a resumed run ends with every frame once (201 rows)"
}
stop_and_resume stop
[ $DASK -eq 1 ] && stop_and_resume stop-processes --processes
# The same grid as a preview into the same directory: each run's earlier run of the full scene moves aside.
"$BAKESIM" sweep "$ROOT/tests/data/good_small.json" --set environment.air_temperature=100,200 --preview \
  --out "$OUT/stop" >/dev/null 2>"$OUT/preview.txt"
check '[ $? -eq 0 ] && [ -f "$OUT"/stop/runs/1-air_temperature=100/previous/stats.csv ] && grep -q "good_small-preview\|-preview" "$OUT"/stop/runs/1-air_temperature=100/scene.json' "a preview of the grid into the same sweep moves the earlier runs into their previous/"

# A scheduler and a worker started by hand, as on a cluster (docs/python.md): the same frames as here.
if [ $DASK -eq 1 ] && command -v dask-scheduler >/dev/null && command -v dask-worker >/dev/null; then
  dask-scheduler --host 127.0.0.1 --port 0 --no-dashboard --scheduler-file "$OUT/scheduler.json" >"$OUT/scheduler.txt" 2>&1 &
  spid=$!
  trap 'kill $spid ${wpid:-} 2>/dev/null; wait; rm -rf "$OUT"' EXIT
  for _ in $(seq 1 300); do [ -s "$OUT/scheduler.json" ] && break; sleep 0.1; done
  PYTHONPATH="$(dirname "$BAKESIM")/../python" dask-worker --scheduler-file "$OUT/scheduler.json" --nthreads 2 \
    --no-dashboard >"$OUT/worker.txt" 2>&1 &
  wpid=$!
  for _ in $(seq 1 300); do grep -q "Registered to" "$OUT/worker.txt" && break; sleep 0.1; done
  address="$(/usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["address"])' "$OUT/scheduler.json")"
  "$BAKESIM" sweep "$OUT/ball.json" --set environment.air_temperature=90,250 --set 'bodies[0].temperature=10,30' \
    --set time.fps=200 --out "$OUT/sw-cluster" --dask "$address" >/dev/null 2>"$OUT/cluster.txt"
  check '[ $? -eq 0 ] && grep -q "2 at a time on 1 thread each, on the Dask scheduler tcp://127.0.0.1:" "$OUT/cluster.txt" && same_frames "$OUT/sw" "$OUT/sw-cluster"' "--dask ADDRESS: a scheduler and a two-thread worker started by hand run the grid, two at a time, the same frames"
fi
exit $fail
