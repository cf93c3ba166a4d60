#!/usr/bin/env bash
# Installs what is missing (with Chromium, for the report's browser test,
# clang-format, for the format check, and ROS 1, for the node and its test),
# builds everything (warnings are errors under CI; the ROS 1 node too) and
# runs every test.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh --with-browser --with-format --with-ros
PARKSLAM_ROS=ON scripts/build.sh
cd build
ctest --output-on-failure -j"$(nproc)"
