#!/usr/bin/env bash
# Installs what is missing (with Chromium, for the report's browser test,
# and clang-format, for the format check),
# builds everything (warnings are errors under CI) and runs every test.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh --with-browser --with-format
scripts/build.sh
cd build
ctest --output-on-failure -j"$(nproc)"
