#!/usr/bin/env bash
# The safety net, run by .ci/run after the test suite: a second build folder with AddressSanitizer +
# UndefinedBehaviorSanitizer (Debian's clang 14, -O1), the whole test suite under it (so the next
# out-of-bounds read or undefined behaviour fails CI), then the libFuzzer targets
# fuzz/scene_fuzz.cpp (scene parsing, validation and model building) and fuzz/output_fuzz.cpp (the
# output folder's manifest parser and the UTF-8 checks) side by side for a bounded time.
# Usage: scripts/run-sanitizers.sh   (env: SAN_BUILD_DIR, default build-san; FUZZ_SECONDS, default 35;
#                                     JOBS, default nproc)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
bash scripts/install-deps.sh --with-sanitizers
build="${SAN_BUILD_DIR:-build-san}"
jobs="${JOBS:-$(nproc)}"
fuzz_seconds="${FUZZ_SECONDS:-35}"
mkdir -p "$build"
# This is also CI's build without the optional packages (Ipopt, NLopt, Gmsh, PETSc, Python all
# off): a test that assumes one of them, or an include only the full build provides, fails here as
# it would for a user who built without them. A third build for that alone would add ~6 min to a CI
# run already at ~15 min; the price is that the Ipopt, NLopt and Gmsh wrappers run uninstrumented
# (in the regular build only). PETSc would be left out anyway: OpenMPI keeps allocations until
# exit, which LeakSanitizer would report; and an instrumented Python module cannot be loaded by
# Debian's uninstrumented python3.
# Line tables for readable reports (full -g costs 20 % more compile time and 4x the object size),
# assertions on (no NDEBUG: Eigen's index checks too), the library at -O1 to keep the instrumented
# suite fast and the test files at -O0 (HEMICONTACT_TESTS_OPTIMIZE: 60 % less of their compile
# time); no benchmarks; the test files in unity batches and precompiled headers, as in
# scripts/build.sh.
CC=clang-14 CXX=clang++-14 cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_FLAGS="-O1 -gline-tables-only" \
  -DHEMICONTACT_SANITIZE=ON -DHEMICONTACT_BUILD_FUZZ=ON -DHEMICONTACT_BUILD_BENCH=OFF -DHEMICONTACT_WITH_PETSC=OFF -DHEMICONTACT_WITH_PYTHON=OFF \
  -DHEMICONTACT_WITH_IPOPT=OFF -DHEMICONTACT_WITH_NLOPT=OFF -DHEMICONTACT_WITH_GMSH=OFF \
  -DHEMICONTACT_UNITY_BUILD=ON -DHEMICONTACT_PCH=ON -DHEMICONTACT_TESTS_OPTIMIZE=-O0 >"$build/configure.log" 2>&1 || {
  cat "$build/configure.log" >&2
  exit 1
}
cmake --build "$build" -j "$jobs"
echo "run-sanitizers: set-up and build took $SECONDS s" >&2
t_tests=$SECONDS

# Any report ends the process with an error (halt_on_error; UBSan does not recover: the build
# passes -fno-sanitize-recover=all); leaks are checked, with suppressions for third-party code only.
export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:strict_string_checks=1:check_initialization_order=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$here/tests/sanitizers/lsan.supp:print_suppressions=0"
export ASAN_SYMBOLIZER_PATH="${ASAN_SYMBOLIZER_PATH:-/usr/bin/llvm-symbolizer-14}"
ctest --test-dir "$build" --output-on-failure -j "$jobs"
echo "run-sanitizers: the suite under ASan+UBSan took $((SECONDS - t_tests)) s" >&2

# Each fuzzer works on a copy of its seed corpus (it adds the inputs it finds interesting there),
# so the source tree is never written. A crash leaves its input in $build/fuzz-crashes and fails.
# The two targets run side by side, one core each, for FUZZ_SECONDS of wall time: the scene target
# (the larger input space) and the output target (manifest parser, UTF-8 checks) each get the
# whole time, where they used to share it one after the other (35 s + 10 s).
rm -rf "$build/fuzz-work" && mkdir -p "$build/fuzz-crashes"
# fuzz TARGET SECONDS CORPUS_GLOB [libFuzzer options...]
fuzz() {
  local target="$1" seconds="$2" seeds="$3"
  shift 3
  local work="$build/fuzz-work/$target"
  mkdir -p "$work"
  cp $seeds "$work/"
  "$build/fuzz/hemicontact_${target}_fuzz" "$@" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$build/fuzz-crashes/" "$work" 2>"$build/fuzz-$target.log" || {
    tail -60 "$build/fuzz-$target.log" >&2
    echo "run-sanitizers: the $target fuzzer found a crash; its input is in $build/fuzz-crashes/" >&2
    return 1
  }
  grep -E "stat::number_of_executed_units|stat::new_units_added|stat::peak_rss_mb" "$build/fuzz-$target.log" >&2 || true
}
fuzz scene "$fuzz_seconds" "fuzz/corpus/*.json" -dict=fuzz/scene.dict -max_len=8192 &
scene_pid=$!
fuzz output "$fuzz_seconds" "fuzz/corpus-output/*" -max_len=4096 &
output_pid=$!
status=0
wait "$scene_pid" || status=1
wait "$output_pid" || status=1
((status == 0)) || exit 1
echo "run-sanitizers: the tests passed under ASan+UBSan and ${fuzz_seconds} s of fuzzing (two targets side by side) found nothing" >&2
