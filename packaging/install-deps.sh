#!/usr/bin/env bash
# Installs every Debian 12 package Linkscape needs to build, test and run.
# Idempotent: apt is skipped when every package is already installed.
set -euo pipefail

packages=(
  cmake ninja-build g++ dpkg-dev pkg-config
  libeigen3-dev nlohmann-json3-dev libcli11-dev libhwy-dev libmuparser-dev
  libvtk9-dev libopenmesh-dev
  qt6-base-dev libqt6opengl6-dev qt6-svg-dev qt6-charts-dev
  libgtest-dev libbenchmark-dev libmujoco-dev
  libopenmpi-dev openmpi-bin
  xvfb xauth libgl1-mesa-dri
  lintian desktop-file-utils bash-completion
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
