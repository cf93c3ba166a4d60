#!/usr/bin/env bash
# Keeps the training scripts alive: a handful of generated images, one
# epoch of each network, export, reference outputs, and the C++ side
# loading the fresh networks. Skipped (exit 77) where Debian's python3-torch
# is not installed (scripts/install_training_deps.sh); CI never trains.
#   usage: smoke_test.sh PATH/TO/parkslam
set -euo pipefail
parkslam=${1:?usage: smoke_test.sh PATH/TO/parkslam}
here=$(cd "$(dirname "$0")" && pwd)
python=${PARKSLAM_TRAINING_PYTHON:-/usr/bin/python3}
if ! "$python" -c "import torch, onnx, cv2, numpy" 2>/dev/null; then
  echo "skipped: $python cannot import torch, onnx, cv2 and numpy (scripts/install_training_deps.sh installs them)"
  exit 77
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$parkslam" make-training-set --out "$work/train" --count 4 --seed 11 --threads 1 > /dev/null
"$parkslam" make-training-set --out "$work/val" --count 2 --seed 12 --threads 1 > /dev/null
"$parkslam" make-training-set --out "$work/ids" --kind ids --count 6 --seed 13 --threads 1 > /dev/null
mkdir "$work/models"
"$python" "$here/train_marking_points.py" --train "$work/train" --val "$work/val" \
  --out "$work/models/marking_points.onnx" --epochs 1 --batch 2 --seed 1 --threads 1
# The worker-process route (as trained on a GPU machine) reads and augments
# the same way; it and a third run keep the other input normalizations alive.
mkdir "$work/local" "$work/grey"
"$python" "$here/train_marking_points.py" --train "$work/train" --val "$work/val" \
  --out "$work/local/marking_points.onnx" --epochs 1 --batch 2 --seed 1 --threads 1 --workers 2 \
  --input-norm local
"$python" "$here/train_marking_points.py" --train "$work/train" --val "$work/val" \
  --out "$work/grey/marking_points.onnx" --epochs 1 --batch 2 --seed 1 --threads 1 --input-norm grey
"$python" "$here/train_slot_ids.py" --train "$work/ids" --val "$work/ids" \
  --out "$work/models/slot_ids.onnx" --epochs 1 --batch 4 --seed 1 --threads 1
for f in marking_points.onnx marking_points.onnx.json marking_points.reference.json \
         slot_ids.onnx slot_ids.onnx.json slot_ids.reference.json; do
  test -s "$work/models/$f" || { echo "missing $f"; exit 1; }
done
# The C++ side runs the fresh networks.
"$parkslam" eval-detect --ps2 "$work/train" --detector learned --models "$work/models" --json
for norm in local grey; do
  cp "$work/models/slot_ids.onnx" "$work/$norm/"
  "$parkslam" eval-detect --ps2 "$work/train" --detector learned --models "$work/$norm" --json
done
echo "training smoke test passed"
