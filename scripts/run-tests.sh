#!/usr/bin/env bash
# README command 2: set up, build, and run the whole test suite (GoogleTest through ctest).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
bash scripts/build.sh
echo "run-tests: set-up and build took $SECONDS s" >&2
build="${BUILD_DIR:-build}"
ctest --test-dir "$build" --output-on-failure -j "${JOBS:-$(nproc)}"
