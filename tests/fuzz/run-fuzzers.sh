#!/usr/bin/env bash
# Usage: tests/fuzz/run-fuzzers.sh [SECONDS | -runs=N] [TARGET...]
#
# Builds the libFuzzer targets with clang (LINKSCAPE_FUZZ=ON: ASan, UBSan
# halting on error, coverage instrumentation of the whole build) into
# build-fuzz/ and runs each TARGET (default: csv preset session eval) for
# SECONDS (default 60) or for N inputs, one after the other.
#
# Each run starts from the committed corpus tests/fuzz/corpus/TARGET, which it
# only reads. New interesting inputs go to build-fuzz/fuzz-work/TARGET/corpus;
# at the end they are merged with the committed corpus into the smallest set
# with the same coverage, build-fuzz/fuzz-work/TARGET/merged, to review and
# copy from by hand. Crashes are written as build-fuzz/fuzz-work/TARGET/crash-*.
#
# Environment: FUZZ_BUILD_DIR (default build-fuzz), FUZZ_JOBS (build
# parallelism, default 2), FUZZ_KEEP_GOING=1 (libFuzzer's fork mode: keep
# fuzzing after a crash, collecting every crash; one worker).
#
# Exit status: 0 if no target crashed, 1 otherwise. Prints one summary line
# per target: inputs executed, corpus size, crashes.
set -euo pipefail
cd "$(dirname "$0")/../.."

budget=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(csv preset session eval)
case "$budget" in
  -runs=[0-9]*) limit=("$budget") ;;
  [0-9]*) limit=("-max_total_time=$budget") ;;
  *) echo "usage: $0 [SECONDS | -runs=N] [TARGET...]" >&2; exit 2 ;;
esac

build=${FUZZ_BUILD_DIR:-build-fuzz}
# RelWithDebInfo without NDEBUG: Eigen's own assertions stay on.
CC=clang CXX=clang++ cmake -S . -B "$build" -G Ninja -DLINKSCAPE_FUZZ=ON -DLINKSCAPE_WITH_GUI=OFF \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g" >/dev/null
cmake --build "$build" --parallel "${FUZZ_JOBS:-2}" --target "${targets[@]/#/fuzz_}"

# The session target writes and reads files for every input: on tmpfs it runs
# several times faster than on disk.
if [ -z "${TMPDIR:-}" ] && [ -d /dev/shm ] && [ -w /dev/shm ]; then export TMPDIR=/dev/shm; fi
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}

status=0
summary=()
for target in "${targets[@]}"; do
  work="$build/fuzz-work/$target"
  mkdir -p "$work/corpus"
  log="$work/fuzz.log"
  mode=()
  [ "${FUZZ_KEEP_GOING:-0}" = 1 ] && mode=(-fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1)
  echo "== fuzz_$target ${limit[*]} (log: $log)"
  # -timeout: an input that runs for 10 s is a hang; every input here takes milliseconds.
  set +e
  "$build/tests/fuzz/fuzz_$target" "${limit[@]}" "${mode[@]}" -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -dict="tests/fuzz/dict/$target.dict" -artifact_prefix="$work/" \
    "$work/corpus" "tests/fuzz/corpus/$target" >"$log" 2>&1
  rc=$?
  set -e
  # Inputs executed: the final stats, or in fork mode the last status line's count.
  execs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | tail -n1 | grep -o '[0-9]*$' || true)
  [ -n "$execs" ] || execs=$(grep -o '^#[0-9]*' "$log" | tail -n1 | tr -d '#' || true)
  crashes=$(find "$work" -maxdepth 1 -name 'crash-*' -o -maxdepth 1 -name 'timeout-*' -o -maxdepth 1 -name 'oom-*' | wc -l)
  rm -rf "$work/merged" && mkdir -p "$work/merged"
  # The merge runs every input again: any that crashes is written under $work, not the current folder.
  "$build/tests/fuzz/fuzz_$target" -merge=1 -artifact_prefix="$work/merge-" "$work/merged" "tests/fuzz/corpus/$target" "$work/corpus" >"$work/merge.log" 2>&1 || true
  merged=$(find "$work/merged" -type f | wc -l)
  summary+=("$target: ${execs:-?} inputs, exit $rc, $crashes crash/timeout/oom files in $work, merged corpus $merged files")
  if [ "$rc" -ne 0 ] || [ "$crashes" -gt 0 ]; then
    status=1
    grep -m1 -A30 -E 'ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error|invariant broken' "$log" || tail -n 30 "$log"
  fi
done
printf '%s\n' "${summary[@]}"
exit "$status"
