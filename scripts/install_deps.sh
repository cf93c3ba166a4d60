#!/usr/bin/env bash
# Installs the Debian packages parkslam needs, and only those that are missing.
# Safe to run again: with everything present it installs nothing.
# --with-browser also installs Chromium, which the report's browser test
# needs (scripts/test.sh asks for it; the demo does not).
set -euo pipefail

packages=(
  build-essential cmake
  libeigen3-dev libyaml-cpp-dev nlohmann-json3-dev libcli11-dev
  libceres-dev libopencv-dev libopencv-contrib-dev libapriltag-dev
  fonts-dejavu-core fonts-dejavu-extra fonts-liberation fonts-freefont-ttf fonts-urw-base35
  fonts-noto-core fonts-open-sans fonts-cantarell fonts-roboto-unhinted
  libgtest-dev libgmock-dev libbenchmark-dev
)
if [ "${1:-}" = "--with-browser" ]; then
  packages+=(chromium)
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install_deps: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install_deps: need root or sudo to install ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
