#!/usr/bin/env bash
# Every kind of bad input gets a message naming where the problem is and exit
# code 2, from `run` and `validate` alike.
set -u
BAKESIM="$1"
DATA="$2"
OUT="$(mktemp -d)"
trap 'rm -rf "$OUT"' EXIT
fail=0

expect() {  # expect CODE REGEX -- command...
  local code="$1" regex="$2"
  shift 3
  local err rc
  err="$("$@" 2>&1 >/dev/null)"
  rc=$?
  if [ "$rc" -ne "$code" ]; then
    echo "FAIL: '$*' exited $rc, expected $code. stderr: $err"
    fail=1
  elif ! grep -Eq -- "$regex" <<<"$err"; then
    echo "FAIL: '$*' stderr does not match /$regex/: $err"
    fail=1
  else
    echo "ok: $* -> $code: $(head -c 200 <<<"$err")"
  fi
}

for cmd in validate run; do
  extra=()
  [ "$cmd" = run ] && extra=(--out "$OUT/run" --quiet)
  expect 2 'bad_syntax.json:3:[0-9]+: JSON syntax error' -- "$BAKESIM" "$cmd" "$DATA/bad_syntax.json" "${extra[@]}"
  expect 2 "bodies\[0\]\.shape\.raduis: unknown key; did you mean 'radius'" -- "$BAKESIM" "$cmd" "$DATA/unknown_key.json" "${extra[@]}"
  expect 2 'bodies\[0\]\.temperature: expected a number, got a string' -- "$BAKESIM" "$cmd" "$DATA/wrong_type.json" "${extra[@]}"
  expect 2 'bodies\[0\]\.shape\.radius: must be > 0 m, got -0.05' -- "$BAKESIM" "$cmd" "$DATA/out_of_range.json" "${extra[@]}"
  expect 2 'bodies\[0\]\.shape\.file: .*meshes/no-such-bunny.obj: mesh file not found' -- "$BAKESIM" "$cmd" "$DATA/missing_mesh.json" "${extra[@]}"
  expect 2 'bodies\[0\]\.shape\.file: .*meshes/broken.ply: PLY vertex element lacks x, y or z' -- "$BAKESIM" "$cmd" "$DATA/unreadable_mesh.json" "${extra[@]}"
  expect 2 "bodies\[0\]: body 'crumb' contains no particles" -- "$BAKESIM" "$cmd" "$DATA/zero_particles.json" "${extra[@]}"
  expect 2 'no-such-scene.json: scene file not found' -- "$BAKESIM" "$cmd" "$DATA/no-such-scene.json" "${extra[@]}"
done
expect 2 'threads' -- "$BAKESIM" run "$DATA/good_small.json" --threads 0
expect 2 'unknown-flag|not expected|Extras' -- "$BAKESIM" run "$DATA/good_small.json" --unknown-flag
expect 0 '' -- "$BAKESIM" --version
expect 0 '' -- "$BAKESIM" validate "$DATA/good_small.json"
# --end-time obeys the limits a scene file does (1e30 overflowed an int and "succeeded" after one frame).
expect 2 '--end-time: must be <= 1e6 s' -- "$BAKESIM" run "$DATA/good_small.json" --out "$OUT/long" --quiet --end-time 1e30
expect 2 '--end-time: .*more than a million frames' -- "$BAKESIM" run "$DATA/good_small.json" --out "$OUT/long" --quiet --end-time 1e5
# A scene's name makes one directory under out/, never a path elsewhere (../evil wrote beside out/).
mkdir -p "$OUT/cwd"
sed 's/"solver"/"name": "..\/..\/evil", "solver"/' "$DATA/good_small.json" > "$OUT/cwd/evil.json"
(cd "$OUT/cwd" && "$BAKESIM" run evil.json --quiet --end-time 0.01)
if [ -d "$OUT/cwd/out/_.._evil" ] && [ ! -e "$OUT/evil" ] && [ ! -e "$OUT/cwd/evil" ]; then
  echo "ok: a scene named ../../evil runs into out/_.._evil"
else
  echo "FAIL: a scene named ../../evil ran outside out/: $(ls "$OUT" "$OUT/cwd" "$OUT/cwd/out" 2>&1 | tr '\n' ' ')"
  fail=1
fi
# An unwritable output directory is an I/O failure, reported with its path.
expect 1 "/proc/bakesim-out" -- "$BAKESIM" run "$DATA/good_small.json" --out /proc/bakesim-out --quiet
exit $fail
