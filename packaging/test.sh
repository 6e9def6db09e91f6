#!/usr/bin/env bash
# Sets up, builds and runs the whole test suite through ctest. Tests that
# need an X server start their own Xvfb (see tests/gui/CMakeLists.txt).
set -euo pipefail
cd "$(dirname "$0")/.."
bash packaging/build.sh
cd build
ctest --output-on-failure --parallel "$(nproc)"
