#!/usr/bin/env bash
# Failures that must lose nothing (docs/reliability.md):
# * a run whose stable time step falls below solver.min_dt stops with exit
#   code 3 and a message naming the step, keeps the frames up to the last
#   complete one and writes that frame's state as a checkpoint; resuming from
#   it reaches the same failure at the same step;
# * a full disk (a small tmpfs, where this machine lets us mount one) or a
#   file-size limit (ulimit -f, always) stops the run with a non-zero exit
#   code and a message naming the file; no temporary file is left and every
#   frame that was written equals the same frame of an unhindered run;
# * a read-only output directory (a read-only tmpfs) is reported with its path.
source "$(dirname "$0")/common.sh"
trap 'umount "$OUT/disk" "$OUT/ro" 2>/dev/null; rm -rf "$OUT"' EXIT

# --- time-step floor
"$BAKESIM" run "$ROOT/tests/data/fails_min_dt.json" --out "$OUT/floor" --threads 2 --quiet 2>"$OUT/floor.txt"
rc=$?
check '[ $rc -eq 3 ]' "min_dt failure: exit code 3"
check 'grep -q "mpm step 91 .*below the floor" "$OUT/floor.txt"' "min_dt failure: the message names the step and the floor"
check '[ -f "$OUT/floor/frames/00005.ply" ] && [ ! -e "$OUT/floor/frames/00006.ply" ]' "min_dt failure: frames 0-5 kept, none after"
check '[ "$(ls "$OUT"/floor/checkpoints)" = 00005.ckpt ]' "min_dt failure: checkpoint of frame 5, the last complete one"
check '[ "$(wc -l < "$OUT/floor/stats.csv")" -eq 7 ]' "min_dt failure: stats.csv has the header and frames 0-5"
check 'grep -q "the state of frame 5" "$OUT/floor/log.txt"' "min_dt failure: the log says where the state is"
"$BAKESIM" run --resume "$OUT/floor" --threads 2 --quiet 2>"$OUT/floor-resumed.txt"
rc=$?
check '[ $rc -eq 3 ] && grep -q "mpm step 91 .*below the floor" "$OUT/floor-resumed.txt"' "min_dt failure: the resumed run fails at the same step"

# --- the reference for the disk tests
"$BAKESIM" run "$ROOT/tests/data/resume_mpm.json" --out "$OUT/whole" --threads 2 --quiet
written_frames_match() {  # $1: a run directory cut short; its frames equal the reference's
  local f n=0
  for f in "$1"/frames/*; do
    [ -e "$f" ] || continue
    cmp -s "$f" "$OUT/whole/frames/$(basename "$f")" || { echo "differs: $f"; return 1; }
    n=$((n + 1))
  done
  echo "$n frame files written before the failure"
  [ $n -ge 2 ]
}
no_temporaries() { [ -z "$(find "$1" -name '*.tmp*')" ]; }

# --- a full disk: a 2 MiB tmpfs holds the first few frames (430 kB each)
mkdir -p "$OUT/disk"
if mount -t tmpfs -o size=2m bakesim-test "$OUT/disk" 2>/dev/null; then
  "$BAKESIM" run "$ROOT/tests/data/resume_mpm.json" --out "$OUT/disk/run" --threads 2 --quiet 2>"$OUT/disk.txt"
  rc=$?
  cat "$OUT/disk.txt"
  check '[ $rc -ne 0 ] && [ $rc -ne 3 ]' "full disk: non-zero exit that is not a simulation failure ($rc)"
  check 'grep -q "$OUT/disk/run/.*No space left on device" "$OUT/disk.txt"' "full disk: the message names the file and the cause"
  check 'no_temporaries "$OUT/disk/run"' "full disk: no temporary file left"
  check 'written_frames_match "$OUT/disk/run"' "full disk: every frame written is complete"
  umount "$OUT/disk"
else
  echo "skipped: cannot mount a tmpfs here (not root, or no CAP_SYS_ADMIN); the file-size limit below covers the same path"
fi

# --- a read-only output directory (a read-only tmpfs; root ignores permission bits)
mkdir -p "$OUT/ro"
if mount -t tmpfs -o ro,size=1m bakesim-test-ro "$OUT/ro" 2>/dev/null; then
  "$BAKESIM" run "$ROOT/tests/data/resume_mpm.json" --out "$OUT/ro/run" --quiet 2>"$OUT/ro.txt"
  rc=$?
  cat "$OUT/ro.txt"
  check '[ $rc -eq 1 ] && grep -q "$OUT/ro/run.*Read-only file system" "$OUT/ro.txt"' "read-only directory: exit 1, the message names the path and the cause"
  umount "$OUT/ro"
else
  echo "skipped: cannot mount a read-only tmpfs here"
fi

# --- a file-size limit: frames (380 kB) fit under 600 kB, the first checkpoint (2 MB) does not
# (bakesim ignores SIGXFSZ itself, so the write fails with EFBIG and is reported.)
(
  ulimit -f 600
  exec "$BAKESIM" run "$ROOT/tests/data/resume_mpm.json" --out "$OUT/limit" --threads 2 --quiet --checkpoint-every 3
) 2>"$OUT/limit.txt"
rc=$?
cat "$OUT/limit.txt"
check '[ $rc -ne 0 ] && [ $rc -ne 3 ]' "file-size limit: non-zero exit that is not a simulation failure ($rc)"
check 'grep -q "$OUT/limit/checkpoints/00003.ckpt.*File too large" "$OUT/limit.txt"' "file-size limit: the message names the checkpoint and the cause"
check 'no_temporaries "$OUT/limit"' "file-size limit: no temporary file left"
check 'written_frames_match "$OUT/limit"' "file-size limit: every frame written is complete"
exit $fail
