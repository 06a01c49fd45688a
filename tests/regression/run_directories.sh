#!/usr/bin/env bash
# Run directories are owned (docs/reliability.md, "What a run directory holds"),
# and crafted files are refused before they are read. Each check below failed
# before issue 21 was fixed:
# * a new run in an earlier run's directory lost every new checkpoint (the old
#   run's higher-numbered ones were kept instead) and the resume failed;
# * two runs into one directory both "succeeded", their frames interleaved;
# * `run --out DIR` replaced a user's file and left stale frames behind;
# * SIGHUP and SIGXFSZ killed a run without a message or a checkpoint;
# * a foreign newest checkpoint blocked the fallback to older valid ones, and
#   a FIFO named like a checkpoint hung the resume;
# * stats.csv and log.txt were rewritten in full every frame (now appended).
source "$(dirname "$0")/common.sh"
wait_for() { local i; for i in $(seq 1 600); do [ -e "$1" ] && return 0; sleep 0.05; done; return 1; }
MPM="$ROOT/tests/data/resume_mpm.json"  # 20 frames of a small MPM bake
SPH="$ROOT/tests/data/good_small.json"

# --- a new run in an old run's directory starts clean; its own checkpoints survive and resume
"$BAKESIM" run "$MPM" --out "$OUT/again" --threads 2 --quiet --checkpoint-every 3
check '[ -f "$OUT/again/checkpoints/00018.ckpt" ]' "first run: checkpoints up to frame 18"
"$BAKESIM" run "$MPM" --out "$OUT/again" --threads 2 --quiet --checkpoint-every 1000 2>"$OUT/again.txt" &
pid=$!
wait_for "$OUT/again/previous/frames/00004.ply"  # the first run's frames moved aside,
wait_for "$OUT/again/frames/00004.ply"           # then the second run's own
kill -TERM $pid
wait $pid
rc=$?
check '[ $rc -eq 143 ]' "second run into the same directory: stopped by SIGTERM, exit 143 ($rc)"
check '[ -d "$OUT/again/previous/frames" ] && [ -f "$OUT/again/previous/checkpoints/00018.ckpt" ]' "the first run's files moved into previous/"
ckpts="$(ls "$OUT/again/checkpoints")"
check '[ "$(wc -l <<<"$ckpts")" -eq 1 ] && [ "$ckpts" != 00018.ckpt ]' "only the second run's checkpoint is in checkpoints/ ($ckpts)"
"$BAKESIM" run --resume "$OUT/again" --threads 2 --quiet
check '[ $? -eq 0 ] && [ "$(wc -l < "$OUT/again/stats.csv")" -eq 22 ]' "the second run resumes to its end (header and 21 rows)"
"$BAKESIM" run "$MPM" --out "$OUT/again" --threads 2 --quiet --end-time 0.1
check '[ $? -eq 0 ] && [ ! -e "$OUT/again/frames/00006.ply" ] && [ "$(wc -l < "$OUT/again/stats.csv")" -eq 7 ]' "a third, shorter run leaves no stale frames of the longer one"
check '[ ! -e "$OUT/again/previous/previous" ] && [ "$(wc -l < "$OUT/again/previous/stats.csv")" -eq 22 ]' "previous/ holds only the run before (the oldest one's files removed)"

# --- a user's directory is not a run directory
mkdir -p "$OUT/user"
printf '// my commented scene\n{}\n' > "$OUT/user/scene.json"
"$BAKESIM" run "$SPH" --out "$OUT/user" --quiet --end-time 0.02 2>"$OUT/user.txt"
check '[ $? -eq 2 ] && grep -q "not a bakesim run directory" "$OUT/user.txt"' "a directory with a user's file is refused (exit 2)"
"$BAKESIM" run "$SPH" --out "$OUT/user" --quiet --end-time 0.02 --force 2>"$OUT/user-force.txt"
check '[ $? -eq 2 ] && grep -q "does not replace files it did not write" "$OUT/user-force.txt"' "--force does not replace the user's scene.json"
check 'grep -q "my commented scene" "$OUT/user/scene.json" && [ ! -e "$OUT/user/frames" ]' "the user's file is untouched, nothing written"
mkdir -p "$OUT/notes"
echo "keep me" > "$OUT/notes/notes.txt"
"$BAKESIM" run "$SPH" --out "$OUT/notes" --quiet --end-time 0.02 --force
check '[ $? -eq 0 ] && grep -q "keep me" "$OUT/notes/notes.txt" && [ -f "$OUT/notes/frames/00002.ply" ]' "--force writes beside unrelated files, keeping them"
"$BAKESIM" run "$SPH" --out "$OUT/notes" --quiet --end-time 0.02
check '[ $? -eq 0 ] && grep -q "keep me" "$OUT/notes/notes.txt"' "a rerun there moves only bakesim's files aside"
sed 's/"solver"/"name": "other", "solver"/' "$SPH" > "$OUT/other.json"
"$BAKESIM" run "$OUT/other.json" --out "$OUT/notes" --quiet --end-time 0.02 2>"$OUT/other.txt"
check '[ $? -eq 2 ] && grep -q "holds a bakesim run of scene .good_small., not of .other." "$OUT/other.txt"' "another scene's run directory is refused"
echo "mine" > "$OUT/notes/previous/mine.txt"
"$BAKESIM" run "$SPH" --out "$OUT/notes" --quiet --end-time 0.02 2>"$OUT/prev.txt"
check '[ $? -eq 2 ] && grep -q "previous: holds files bakesim did not write" "$OUT/prev.txt" && [ -f "$OUT/notes/previous/mine.txt" ]' "a user's file in previous/ is never deleted (the rerun is refused)"
touch "$OUT/a-file"
"$BAKESIM" run "$SPH" --out "$OUT/a-file" --quiet --end-time 0.02 2>"$OUT/file.txt"
check '[ $? -eq 2 ] && grep -q "is not a directory" "$OUT/file.txt"' "an output path that is a file is refused"

# --- one run per directory at a time
"$BAKESIM" run "$MPM" --out "$OUT/busy" --threads 1 --quiet &
pid=$!
wait_for "$OUT/busy/frames/00001.ply"
"$BAKESIM" run "$MPM" --out "$OUT/busy" --threads 1 --quiet 2>"$OUT/busy.txt"
check '[ $? -eq 2 ] && grep -q "in use by another bakesim process (PID $pid)" "$OUT/busy.txt"' "a second run into a busy directory is refused, naming the PID"
"$BAKESIM" run --resume "$OUT/busy" --quiet 2>"$OUT/busy-resume.txt"
check '[ $? -eq 2 ] && grep -q "in use" "$OUT/busy-resume.txt"' "so is a resume of a running run"
wait $pid
check '[ $? -eq 0 ] && [ "$(ls "$OUT/busy/frames" | wc -l)" -eq 42 ] && [ ! -e "$OUT/busy/previous" ]' "the first run finished alone (21 frames, nothing moved)"

# --- SIGHUP stops like SIGTERM: checkpoint, message, exit 129; the resume ends like an unhindered run
"$BAKESIM" run "$MPM" --out "$OUT/whole" --threads 2 --quiet
"$BAKESIM" run "$MPM" --out "$OUT/hup" --threads 2 --quiet --checkpoint-every 1000 2>"$OUT/hup.txt" &
pid=$!
wait_for "$OUT/hup/frames/00004.ply"
kill -HUP $pid
wait $pid
rc=$?
check '[ $rc -eq 129 ] && grep -q "stopped by signal 1" "$OUT/hup.txt" && ls "$OUT"/hup/checkpoints/*.ckpt >/dev/null' "SIGHUP: checkpoint, message, exit 129 ($rc)"
"$BAKESIM" run --resume "$OUT/hup" --threads 2 --quiet
check '[ $? -eq 0 ] && cmp -s "$OUT/whole/frames/00020.ply" "$OUT/hup/frames/00020.ply"' "SIGHUP: the resumed run ends with the unhindered run's last frame"
check '[ "$(grep -c " run of " "$OUT/hup/log.txt")" -eq 2 ]' "log.txt: the resumed run appended to the stopped run's log"

# --- a file-size limit (ulimit -f) without ignoring SIGXFSZ in the shell: a message, not a silent death
( ulimit -f 300; exec "$BAKESIM" run "$MPM" --out "$OUT/xfsz" --threads 2 --quiet --checkpoint-every 3 ) 2>"$OUT/xfsz.txt"
rc=$?
check '[ $rc -eq 1 ] && grep -q "File too large" "$OUT/xfsz.txt"' "SIGXFSZ: exit 1 with the file and the cause ($rc)"

# --- resume: a foreign newest checkpoint and a FIFO are passed over for the older valid one
"$BAKESIM" run "$SPH" --out "$OUT/sph" --quiet --end-time 0.1 --checkpoint-every 2
cp -r "$OUT/whole" "$OUT/crafted"
rm -f "$OUT"/crafted/checkpoints/*
"$BAKESIM" run "$MPM" --out "$OUT/crafted" --threads 2 --quiet --checkpoint-every 4 --end-time 0.2
cp "$(ls "$OUT"/sph/checkpoints/*.ckpt | head -1)" "$OUT/crafted/checkpoints/99998.ckpt"
mkfifo "$OUT/crafted/checkpoints/99999.ckpt"
timeout 60 "$BAKESIM" run --resume "$OUT/crafted" --threads 2 --quiet --end-time 0.4 2>"$OUT/crafted.txt"
rc=$?
check '[ $rc -eq 0 ] && cmp -s "$OUT/whole/frames/00020.ply" "$OUT/crafted/frames/00020.ply"' "resume passes over a FIFO and another scene's checkpoint to the older valid one ($rc)"
check 'grep -q "99999.ckpt: is not a regular file" "$OUT/crafted/log.txt" && grep -q "99998.ckpt: checkpoint of a different scene" "$OUT/crafted/log.txt"' "the log names both refused checkpoints"
exit $fail
