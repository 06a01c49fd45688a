#!/usr/bin/env bash
# The full example scene in docs/scenes.md is valid: extract the first json
# block, place it beside the shipped meshes, and validate it.
set -u
BAKESIM="$1"
ROOT="$(cd "$2" && pwd)"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
ln -s "$ROOT/scenes/meshes" "$TMP/meshes"
awk '/^```json/{on=1; next} /^```/{if(on){exit}} on' "$ROOT/docs/scenes.md" > "$TMP/example.json"
[ -s "$TMP/example.json" ] || { echo "FAIL: no json block in docs/scenes.md"; exit 1; }
"$BAKESIM" validate "$TMP/example.json"
