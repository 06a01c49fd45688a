# Sourced by the command-line test scripts: $1 the bakesim binary, $2 the
# source tree; a scratch directory $OUT removed on exit; check CMD TEXT prints
# ok/FAIL and remembers a failure in $fail.
set -u
BAKESIM="$1"
ROOT="$2"
OUT="$(mktemp -d)"
trap 'rm -rf "$OUT"' EXIT
fail=0
check() { if eval "$1"; then echo "ok: $2"; else echo "FAIL: $2"; fail=1; fi; }
