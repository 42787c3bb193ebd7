#!/usr/bin/env bash
# Installs the Debian packages rtt builds and tests with; does nothing when all are present.
# Uses sudo when not root. The benchmark/test data packages are fetched separately
# (bench/fetch-scenes.sh) into a cache, never installed system-wide.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libembree-dev libopenexr-dev libcmocka-dev libcjson-dev libassimp-dev libpng-dev
  clang libclang-rt-14-dev llvm
  gnuplot-nox unzip jq python3
  libstb-dev libsdl2-dev xvfb xauth libopenmpi-dev openmpi-bin libosmesa6-dev
  zlib1g-dev
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
