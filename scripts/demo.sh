#!/usr/bin/env bash
# Installs what is missing, builds, and runs the main job: `parkslam demo` on
# the built-in default parking lot. Results land in demo_out/ (or $1).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
scripts/build.sh --target parkslam
build/bin/parkslam demo --out "${1:-demo_out}"
