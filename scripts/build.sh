#!/usr/bin/env bash
# Set-up shared by the two README commands: install what is missing, configure Release, build.
# Usage: scripts/build.sh   (env: BUILD_DIR, default build; JOBS, default nproc)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
bash scripts/install-deps.sh
build="${BUILD_DIR:-build}"
jobs="${JOBS:-$(nproc)}"
mkdir -p "$build"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release >"$build/configure.log" 2>&1 || {
  cat "$build/configure.log" >&2
  exit 1
}
grep "hemicontact:" "$build/configure.log" >&2 || true
cmake --build "$build" -j "$jobs"
