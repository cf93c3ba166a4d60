#!/usr/bin/env bash
# Installs what training and exporting the learned detectors needs (Debian's
# PyTorch, ONNX, NumPy and OpenCV for Python), and only what is missing.
# Neither the demo nor the tests need any of it: see docs/learned_perception.md.
set -euo pipefail

packages=(python3 python3-torch python3-onnx python3-numpy python3-opencv)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_training_deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install_training_deps: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install_training_deps: need root or sudo to install ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
