#!/usr/bin/env bash
# Builds everything with AddressSanitizer and UndefinedBehaviorSanitizer in
# build-asan/ (-O1 -g1: half the compile time of -O2 -g, with line numbers
# in reports; no benchmarks) and runs every test there. CI runs it after
# scripts/test.sh. Extra arguments go to ctest (e.g. -R io_test).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/compiler_cache.sh
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DPARKSLAM_SANITIZE=ON \
  -DPARKSLAM_BUILD_BENCHMARKS=OFF "${CACHE_ARGS[@]}" >/dev/null
cmake --build build-asan -j"$(nproc)"
# Leaks of libraries' own one-time allocations (fontconfig, OpenCV's
# thread pools) are not ours: leak checking is off, the rest is on.
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
cd build-asan
ctest --output-on-failure -j"$(nproc)" "$@"
