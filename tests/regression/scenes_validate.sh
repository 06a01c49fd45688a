#!/usr/bin/env bash
# Every scene that ships in scenes/ validates.
set -u
BAKESIM="$1"
ROOT="$2"
fail=0
for scene in "$ROOT"/scenes/*.json; do
  if out="$("$BAKESIM" validate "$scene" 2>&1)"; then
    echo "ok: $(basename "$scene"): $(grep -E '^particles' <<<"$out")"
  else
    echo "FAIL: $scene"
    echo "$out"
    fail=1
  fi
done
exit $fail
