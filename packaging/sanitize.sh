#!/usr/bin/env bash
# Usage: packaging/sanitize.sh [CTEST_ARGS...]
#
# The sanitizer build: configures build-asan with LINKSCAPE_SANITIZE=ON
# (AddressSanitizer + UndefinedBehaviorSanitizer, UBSan stopping at the first
# report; -O1 -g with assertions on), builds everything and runs the whole
# ctest suite under the sanitizers. Tests that render start their own Xvfb
# (tests/with-xvfb.sh) as in the normal build. Extra arguments go to ctest,
# e.g. `packaging/sanitize.sh -L fuzz-corpus` or `-R gui`.
#
# LeakSanitizer ignores only the third-party leaks listed, each with its
# reason, in packaging/lsan-suppressions.txt. Environment: SANITIZE_BUILD_DIR
# (default build-asan), SANITIZE_JOBS (build and test parallelism, default 2).
# Expect a slow build: VTK and Qt headers compile under ASan too.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
build=${SANITIZE_BUILD_DIR:-build-asan}
jobs=${SANITIZE_JOBS:-2}

# Also during the build: gtest_discover_tests runs each test binary to list its tests.
# check_initialization_order: static initialisers that read another file's globals.
export ASAN_OPTIONS="detect_leaks=1:check_initialization_order=1:strict_init_order=1:detect_odr_violation=1"
export LSAN_OPTIONS="suppressions=$root/packaging/lsan-suppressions.txt:print_suppressions=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"

# RelWithDebInfo without NDEBUG, at -O1: readable stacks, assertions checked.
cmake -S . -B "$build" -G Ninja -DLINKSCAPE_SANITIZE=ON \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" >/dev/null
cmake --build "$build" --parallel "$jobs"

# Mesa's software GL driver keeps context state in its own globals and is
# dlclose'd when the X display closes, before LeakSanitizer looks at exit: the
# blocks those globals held then look leaked, with "<unknown module>" stacks
# that no suppression can name. Preloaded, the driver stays mapped to the end
# and the blocks stay reachable. (The preload puts it ahead of the ASan
# runtime, hence verify_asan_link_order=0. ctest and all it starts get it,
# not the build.)
mesa_driver=/usr/lib/$(gcc -print-multiarch)/dri/swrast_dri.so
if [ -f "$mesa_driver" ]; then
  export LD_PRELOAD="$mesa_driver${LD_PRELOAD:+ $LD_PRELOAD}"
  export ASAN_OPTIONS="$ASAN_OPTIONS:verify_asan_link_order=0"
fi
cd "$build"
ctest --output-on-failure --parallel "$jobs" "$@"
