#!/bin/sh
# Runs every libFuzzer target for a set time (side by side), starting from the seeds under tests/fuzz/<target>/, and prints
# how many inputs each ran. Fails when a target finds a crash, a sanitizer report or a broken property; the
# input that did it is saved as build-dir/fuzz/artifacts/<target>-crash-*: fix the code, then keep the input
# in tests/fuzz/regressions/<target>/ so the test suite replays it.
# Usage: scripts/fuzz.sh [SECONDS] [BUILD_DIR]
#   (defaults: 60 seconds each; build-fuzz, configured with CXX=clang++ -DTERRACAST_FUZZ=ON)
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-60}
build=$(cd "${2:-build-fuzz}" && pwd)
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}"
targets="scene_file dem_loader cell_intersector"
for target in $targets; do
  [ -x "$build/fuzz/fuzz_$target" ] || { echo "fuzz.sh: no $build/fuzz/fuzz_$target; configure with CXX=clang++ -DTERRACAST_FUZZ=ON" >&2; exit 2; }
done
# The targets run side by side, each for the whole time; the working corpus grows in the build folder and the
# committed seeds are only read.
for target in $targets; do
  corpus="$build/fuzz/corpus/$target"
  mkdir -p "$corpus" "$build/fuzz/artifacts"
  "$build/fuzz/fuzz_$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
    -print_final_stats=1 -artifact_prefix="$build/fuzz/artifacts/$target-" "$corpus" "$here/tests/fuzz/$target" \
    >"$build/fuzz/$target.log" 2>&1 &
  eval "pid_$target=$!"
done
status=0
for target in $targets; do
  log="$build/fuzz/$target.log"
  if eval "wait \$pid_$target"; then
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
    echo "fuzz: $target: $runs executions in $seconds s, no crash"
  else
    echo "fuzz: $target FAILED; the end of $log:" >&2
    tail -n 40 "$log" >&2
    status=1
  fi
done
exit $status
