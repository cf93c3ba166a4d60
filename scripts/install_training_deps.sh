#!/usr/bin/env bash
# Installs what training and exporting the learned detectors needs (Debian's
# PyTorch, ONNX, NumPy and OpenCV for Python), and only what is missing.
# Neither the demo nor the tests need any of it: see docs/learned_perception.md.
set -euo pipefail

packages=(python3 python3-torch python3-onnx python3-numpy python3-opencv)

exec "$(dirname "$0")/apt_install_missing.sh" install_training_deps "${packages[@]}"
