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
# Crafted files (issue 21): each was accepted, hung, or answered with a bare "stoi".
printf '{"solver": {"type": "sph", "sph": {"spacing": 0.01}}, "solver": {"type": "mpm"}}' > "$OUT/dup.json"
expect 2 'dup.json: solver: duplicate key' -- "$BAKESIM" validate "$OUT/dup.json"
expect 2 '/dev/zero: is not a regular file' -- "$BAKESIM" validate /dev/zero
mkfifo "$OUT/fifo.json"
expect 2 'fifo.json: is not a regular file' -- timeout 20 "$BAKESIM" validate "$OUT/fifo.json"
mkdir -p "$OUT/meshes"
printf 'v 0 0 0\nv 0.1 0 0\nv 0 nan 0\nv 0 0 0.1\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n' > "$OUT/meshes/nan.obj"
sed 's/no-such-bunny.obj/nan.obj/' "$DATA/missing_mesh.json" > "$OUT/nan-obj.json"
expect 2 'meshes/nan.obj:3: vertex coordinate .nan. is not a finite number' -- "$BAKESIM" validate "$OUT/nan-obj.json"
expect 2 'bench --particles: expects comma-separated positive whole numbers' -- "$BAKESIM" bench --particles 12x
expect 2 'bench: --set, --preview and --end-time time a scene: give it with --scene' -- "$BAKESIM" bench --set time.end=1
expect 2 'no-such-scene.json: scene file not found' -- "$BAKESIM" bench --scene "$DATA/no-such-scene.json"
expect 2 'good_small.json: time.end' -- "$BAKESIM" bench --scene "$DATA/good_small.json" --set time.end=-1
# A scene timed to its end: steps, the bounds that limited them, and the phases.
bench_out="$("$BAKESIM" bench --scene "$DATA/good_small.json" --threads 1 2>&1)"
if grep -Eq '^[0-9]+ particles, 1 threads: 0.02 s simulated in [0-9]+ steps' <<<"$bench_out" &&
   grep -Eq '^steps limited by: .*%' <<<"$bench_out" && grep -Eq '^  density ' <<<"$bench_out"; then
  echo "ok: bench --scene times the scene to its end"
else
  echo "FAIL: bench --scene: $bench_out"; fail=1
fi
# With an implicit solve, its conjugate-gradient iterations a step (mean and most).
bench_out="$("$BAKESIM" bench --scene "$DATA/good_small.json" --threads 1 --set solver.sph.viscosity_solver=implicit \
  --set 'materials.water.viscosity=50' 2>&1)"
if grep -Eq '^implicit viscosity: [0-9]+\.[0-9] iterations a step \(mean\), [1-9][0-9]* at most' <<<"$bench_out"; then
  echo "ok: bench --scene counts the implicit solve's iterations"
else
  echo "FAIL: bench --scene without the implicit solve's iterations: $bench_out"; fail=1
fi
sed 's/"solver"/"name": "loaf\\u001b[2J", "solver"/' "$DATA/good_small.json" > "$OUT/escape.json"
expect 2 '^bakesim: error: .*escape.json: name: must not contain control characters' -- "$BAKESIM" validate "$OUT/escape.json"
mkdir -p "$OUT/$(printf 'esc\033[2Jdir')"
err="$("$BAKESIM" validate "$OUT/$(printf 'esc\033[2Jdir')/none.json" 2>&1)"
if grep -q 'esc\\x1b\[2Jdir' <<<"$err" && ! grep -q "$(printf '\033')" <<<"$err"; then
  echo "ok: a control character in a file name is printed escaped"
else
  echo "FAIL: a control character in a file name reached the terminal: $err"; fail=1
fi
# An unwritable output directory is an I/O failure, reported with its path.
expect 1 "/proc/bakesim-out" -- "$BAKESIM" run "$DATA/good_small.json" --out /proc/bakesim-out --quiet
exit $fail
