#!/usr/bin/env bash
# Every scene that ships in scenes/ starts: its first few milliseconds of
# mechanics run without an error or a non-finite state, and write a frame.
set -u
BAKESIM="$1"
ROOT="$2"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
fail=0
for scene in "$ROOT"/scenes/*.json; do
  name="$(basename "$scene" .json)"
  if out="$("$BAKESIM" run "$scene" --out "$TMP/$name" --end-time 0.003 --quiet 2>&1)" &&
     [ -s "$TMP/$name/stats.csv" ]; then
    echo "ok: $name"
  else
    echo "FAIL: $name"
    echo "$out"
    fail=1
  fi
done
exit $fail
