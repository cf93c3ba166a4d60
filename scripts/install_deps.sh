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

exec "$(dirname "$0")/apt_install_missing.sh" install_deps "${packages[@]}"
