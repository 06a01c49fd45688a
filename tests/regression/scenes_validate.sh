#!/usr/bin/env bash
# Every scene that ships in scenes/ validates, as it is and as run --preview would run it.
set -u
BAKESIM="$1"
ROOT="$2"
fail=0
for scene in "$ROOT"/scenes/*.json; do
  for mode in "" --preview; do
    if out="$("$BAKESIM" validate "$scene" $mode 2>&1)"; then
      echo "ok: $(basename "$scene") $mode: $(grep -E '^particles' <<<"$out")"
    else
      echo "FAIL: $scene $mode"
      echo "$out"
      fail=1
    fi
  done
done
exit $fail
