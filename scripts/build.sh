#!/usr/bin/env bash
# Configures and builds parkslam in build/ (Release). Extra arguments are
# passed to `cmake --build` (e.g. --target parkslam).
set -euo pipefail
cd "$(dirname "$0")/.."
werror=OFF
[ "${CI:-}" = "true" ] && werror=ON
source scripts/compiler_cache.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPARKSLAM_WERROR="$werror" "${CACHE_ARGS[@]}" >/dev/null
cmake --build build -j"$(nproc)" "$@"
