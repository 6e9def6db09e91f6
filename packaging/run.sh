#!/usr/bin/env bash
# Sets up, builds and starts the Linkscape window. Arguments are passed on,
# e.g. packaging/run.sh --param L1=12. Without a display it says so and shows
# the headless commands.
set -euo pipefail
cd "$(dirname "$0")/.."
bash packaging/build.sh
exec build/gui/linkscape "$@"
