#!/usr/bin/env bash
# Set-up shared by the two README commands: install what is missing, configure Release, build.
# Usage: scripts/build.sh [TARGET...]   (env: BUILD_DIR, default build; JOBS, default nproc)
# With targets, only those are built (the main job builds the programs it runs, not the test suite
# and the benchmarks, which are most of a fresh build's compile time); without, everything.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
bash scripts/install-deps.sh
build="${BUILD_DIR:-build}"
jobs="${JOBS:-$(nproc)}"
mkdir -p "$build"
# Unity batches of test files (HEMICONTACT_UNITY_BUILD): ~40 % less compile time for the suite,
# which is most of a fresh build; a developer iterating on one test file can configure without it.
# Precompiled Eigen, nlohmann-json and GoogleTest headers (HEMICONTACT_PCH) for the library and the
# tests: a fresh Release build on 2 cores 6 min 10 s -> 5 min 26 s (measured side by side).
# The test files at -O1 (HEMICONTACT_TESTS_OPTIMIZE; the library and the programs stay Release):
# one unity batch of tests took 57 CPU-seconds at -O3 against 39 at -O1, and the suite's run time is
# spent in the library.
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DHEMICONTACT_UNITY_BUILD=ON -DHEMICONTACT_PCH=ON \
  -DHEMICONTACT_TESTS_OPTIMIZE=-O1 >"$build/configure.log" 2>&1 || {
  cat "$build/configure.log" >&2
  exit 1
}
grep "hemicontact:" "$build/configure.log" >&2 || true
# The Python module is built with the programs too (python3 -c "import hemicontact" after either
# README command), where this build has it (pybind11 found: HEMICONTACT_WITH_PYTHON).
if [ "$#" -gt 0 ] && [ -d "$build/python/CMakeFiles" ]; then
  set -- "$@" _hemicontact
fi
if [ "$#" -gt 0 ]; then
  cmake --build "$build" -j "$jobs" --target "$@"
else
  cmake --build "$build" -j "$jobs"
fi
# `python3 -c "import hemicontact"`: a hemicontact.pth in the user's site-packages names
# $build/python (scripts/python-path-file.sh), where the build made the module
# (HEMICONTACT_WITH_PYTHON, pybind11 found).
if [[ -f "$build/python/hemicontact/__init__.py" ]]; then
  bash "$(dirname "${BASH_SOURCE[0]}")/python-path-file.sh" "$(cd "$build/python" && pwd)"
fi
