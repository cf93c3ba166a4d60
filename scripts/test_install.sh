#!/usr/bin/env bash
# The installed library as a car's own program would use it (docs/library.md):
# installs the build folder given into a temporary prefix, checks that no
# installed header includes the simulator side (sim, render, scene, eval,
# io, viz, harness), then configures, builds and runs
# examples/find_package against it with find_package(parkslam CONFIG).
#
#   scripts/test_install.sh BUILD_DIR
set -euo pipefail
build=${1:?usage: scripts/test_install.sh BUILD_DIR}
root=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

cmake --install "$build" --prefix "$tmp/prefix" > "$tmp/install.log"
include="$tmp/prefix/include/parkslam"
[ -f "$include/localization/localizer.h" ] || { echo "FAIL: no headers under $include"; exit 1; }
if grep -rn '#include "parkslam/\(sim\|render\|scene\|eval\|io\|viz\|harness\)/' "$include"; then
  echo "FAIL: installed headers include the simulator side (above)"
  exit 1
fi
if find "$include" -name '*test*' | grep .; then
  echo "FAIL: test helpers installed (above)"
  exit 1
fi
[ -f "$tmp/prefix/share/parkslam/models/marking_points.onnx" ] || { echo "FAIL: no models"; exit 1; }

cmake -S "$root/examples/find_package" -B "$tmp/example" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$tmp/prefix" > "$tmp/configure.log" || { cat "$tmp/configure.log"; exit 1; }
cmake --build "$tmp/example" -j"$(nproc)" > "$tmp/build.log" || { cat "$tmp/build.log"; exit 1; }
"$tmp/example/map_and_localize" | tee "$tmp/run.log"
grep -q "^slot 22 at (7.50, 3.00)$" "$tmp/run.log" || { echo "FAIL: slot 22 not mapped at (7.50, 3.00)"; exit 1; }
echo "PASS: installed, $(find "$include" -name '*.h' | wc -l) headers; the example built and ran"
