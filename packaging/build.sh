#!/usr/bin/env bash
# Installs dependencies (once) and builds Linkscape into build/ (Release, Ninja).
set -euo pipefail
cd "$(dirname "$0")/.."
bash packaging/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build --parallel "$(nproc)"
