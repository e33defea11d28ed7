#!/usr/bin/env bash
# Builds the runtime, the kernels and their GoogleTests with AddressSanitizer
# and UndefinedBehaviorSanitizer (GCC, -O1 -g1, TENSORMASS_SANITIZE=ON) in
# build-sanitize and runs the C++ tests under them; any report fails the run.
# Not run here (no sanitized C++ of ours to check, or not buildable so):
# generator.pytest (Python), labels examples (the long beam and thorax runs),
# scripts (the Python tools), validation (CalculiX comparisons driven from
# Python) and install (an external project linking the sanitized libraries).
# See docs/sanitizers-and-fuzzing.md.
# Usage: scripts/run-sanitizers.sh [extra ctest arguments, e.g. -R '^io\.']
# Environment: TENSORMASS_SANITIZE_BUILD (build directory, default build-sanitize),
# CMAKE_BUILD_PARALLEL_LEVEL (build jobs), CTEST_PARALLEL_LEVEL (test jobs, default: the cores).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${TENSORMASS_SANITIZE_BUILD:-build-sanitize}
supp=$PWD/scripts/sanitizer

# detect_leaks: LeakSanitizer on (the default, stated); the same for the
# build, which runs each test executable to list its tests. The suppressions
# name only third-party libraries, each justified in its file.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"

# -O1: the usual sanitizer level (readable stacks, tests still fast); -g1:
# line tables only, enough for FILE:LINE in every report at half the compile
# time of -g; no NDEBUG, so that assertions run too. No benchmarks.
cmake -S . -B "$build" -G Ninja -DTENSORMASS_SANITIZE=ON -DTENSORMASS_BUILD_BENCH=OFF \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1"
cmake --build "$build"

ctest --test-dir "$build" --output-on-failure --parallel "${CTEST_PARALLEL_LEVEL:-$(nproc)}" \
  --label-exclude '^(examples|scripts|validation|install|hostile)$' --exclude-regex '^generator\.pytest$' "$@"
