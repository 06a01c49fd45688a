#!/usr/bin/env bash
# Installs what is missing, builds Release, and bakes the default scene into out/.
set -euo pipefail
cd "$(dirname "$0")"
./scripts/install-deps.sh
./scripts/build.sh
SCENE="${1:-scenes/bread-roll.json}"
NAME="$(basename "$SCENE" .json)"
./build/app/bakesim run "$SCENE" --out "out/$NAME"
echo "Frames, particles.pvd and stats.csv are in out/$NAME/ (open particles.pvd in ParaView)."
