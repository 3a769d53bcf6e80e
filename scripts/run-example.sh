#!/usr/bin/env bash
# README command 1: set up, build, and run the main job — the paper's example (Sofonea, Han,
# Barboteu 2017, §5) in its Fig. 2 form (loads × 1e6, see problems/README.md) and as printed.
# Prints the status summary and certificate of each; results go to out/.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
bash scripts/build.sh
build="${BUILD_DIR:-build}"
for scene in sofonea2017-fig2 sofonea2017-printed; do
  echo
  echo "=== problems/$scene.json ==="
  "$build/hemicontact" solve "problems/$scene.json" --out "out/$scene" --force "$@"
done
