#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ with clang (ASan + UBSan + coverage,
# -O1 -g1, TENSORMASS_BUILD_FUZZERS=ON) in build-fuzz and runs each one for
# SECONDS on its seed corpus fuzz/corpus/<target>/ with the dictionary
# fuzz/dict/<target>.dict. A crash, sanitizer report, hang (over 10 s on one
# input), an exception other than InputError or an InputError that does not
# name the file fails the run; the input is kept in
# BUILD/fuzz-artifacts/<target>/ and copied to
# tests/data/fuzz_regressions/<target>/, where ctest fuzz.replay.<target>
# replays it in every build until the reader is fixed (commit it; see
# docs/sanitizers-and-fuzzing.md). What a run learns is kept in BUILD/fuzz-corpus/<target>/
# and extends the next run.
# Usage: scripts/run-fuzzers.sh [SECONDS_PER_TARGET [TARGET...]]
#   SECONDS_PER_TARGET  default 30 (CI); 600 or more for a real hunt
#   TARGET              gmsh_reader vtu_reader vtk_reader stl_reader obj_reader scene_reader (default: all)
# Environment: TENSORMASS_FUZZ_BUILD (build directory, default build-fuzz),
# CMAKE_BUILD_PARALLEL_LEVEL (build jobs).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-30}
shift $(($# > 0 ? 1 : 0))
build=${TENSORMASS_FUZZ_BUILD:-build-fuzz}
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(gmsh_reader vtu_reader vtk_reader stl_reader obj_reader scene_reader)
fi

# The benchmarks and tests are not built: the fuzzers need the runtime only.
cmake -S . -B "$build" -G Ninja -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DTENSORMASS_BUILD_FUZZERS=ON -DTENSORMASS_BUILD_TESTS=OFF -DTENSORMASS_BUILD_BENCH=OFF \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1"
cmake --build "$build" --target fuzzers

export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# A 64 MB quarantine instead of 256: the scene fuzzer's many small YAML
# allocations otherwise grow the sanitizer allocator past 1 GB in 4 minutes
# (not a leak: it levels off with a smaller quarantine), and a long run would
# stop on -rss_limit_mb. Freed memory is still poisoned until 64 MB more is freed.
export ASAN_OPTIONS=${ASAN_OPTIONS:-quarantine_size_mb=64}
failed=()
for target in "${targets[@]}"; do
  corpus=$build/fuzz-corpus/$target
  artifacts=$build/fuzz-artifacts/$target
  log=$build/fuzz-logs/$target.log
  mkdir -p "$corpus" "$artifacts" "$(dirname "$log")"
  dict=()
  if [ -f "fuzz/dict/$target.dict" ]; then dict=(-dict="fuzz/dict/$target.dict"); fi
  # The first directory receives what the run finds; the seeds stay as they are.
  "$build/fuzz/fuzz_$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -artifact_prefix="$artifacts/" -print_final_stats=1 "${dict[@]}" \
    "$corpus" "fuzz/corpus/$target" > "$log" 2>&1 &
  pid=$!
  status=0
  wait "$pid" || status=$?
  # LLVM's OpenMP runtime (linked by the clang-built library) registers each
  # process in /dev/shm and leaves the file behind when libFuzzer exits.
  rm -f "/dev/shm/__KMP_REGISTERED_LIB_${pid}_0"
  if [ "$status" -eq 0 ]; then
    echo "fuzz $target: ${seconds} s, $(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$') inputs, no finding"
  else
    echo "fuzz $target: FINDING (log $log, input in $artifacts/):" >&2
    grep -E 'ERROR|runtime error|InputError without|terminate|SUMMARY|Test unit written' "$log" | head -20 >&2 || tail -30 "$log" >&2
    keep=tests/data/fuzz_regressions/$target
    mkdir -p "$keep"
    for input in "$artifacts"/*; do
      [ -f "$input" ] || continue
      cp "$input" "$keep/"
      echo "fuzz $target: kept as $keep/$(basename "$input") (a regression input of ctest fuzz.replay.$target)" >&2
    done
    failed+=("$target")
  fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzzers with findings: ${failed[*]} (reproduce: $build/fuzz/fuzz_TARGET ARTIFACT)" >&2
  exit 1
fi
