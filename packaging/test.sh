#!/usr/bin/env bash
# Sets up, builds and runs the whole test suite through ctest. Window tests
# need an X server; they run under xvfb-run (installed by install-deps.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash packaging/build.sh
cd build
if [ -z "${DISPLAY:-}" ]; then
  exec xvfb-run -a -s "-screen 0 1280x800x24" ctest --output-on-failure --parallel "$(nproc)"
fi
exec ctest --output-on-failure --parallel "$(nproc)"
