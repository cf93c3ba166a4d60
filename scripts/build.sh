#!/usr/bin/env bash
# Configures and builds parkslam in build/ (Release). Extra arguments are
# passed to `cmake --build` (e.g. --target parkslam). PARKSLAM_ROS=ON (or
# OFF) in the environment turns the ROS 1 node on (off); unset, the build
# folder's choice stays (off in a new one).
set -euo pipefail
cd "$(dirname "$0")/.."
werror=OFF
[ "${CI:-}" = "true" ] && werror=ON
source scripts/compiler_cache.sh
ros=()
[ -n "${PARKSLAM_ROS:-}" ] && ros=(-DPARKSLAM_ROS="$PARKSLAM_ROS")
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPARKSLAM_WERROR="$werror" "${CACHE_ARGS[@]}" "${ros[@]}" >/dev/null
cmake --build build -j"$(nproc)" "$@"
