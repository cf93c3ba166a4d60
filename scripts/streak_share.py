#!/usr/bin/python3
"""How radially streaked 600 x 600 top views are (ps2.0 convention, 10 m
across): for each CIELAB channel (L, a, b), the share of gradient energy
that runs across the direction from the car's centre, over the seen floor
more than 60 px beyond the footprint's box. A fused view smears the
fisheyes' coarse far pixels outwards, so detail there is drawn out into
streaks along that direction and its gradients turn across it: 0.5 is no
preferred direction, 1 pure streaks. Each folder's figure is the median
over its first --count views.

Used to compare rendered views with real ones (docs/training_data.md,
"Streaks"); a statistic, nothing learned.

  scripts/streak_share.py ../shared/data/ps2.0-sample /tmp/views
"""

import cv2
import numpy as np

import view_folders

CHANNELS = ("L", "a", "b")


def shares(path):
    image = cv2.imread(path)
    if image is None:
        raise ValueError(f"{path}: not an image")
    if image.shape[:2] != (600, 600):
        raise ValueError(f"{path}: {image.shape[1]} x {image.shape[0]} px, expected 600 x 600")
    yy, xx = np.mgrid[0:600, 0:600].astype(np.float32)
    # Beyond the footprint's box (about 2 x 3.2 m at 60 px a metre), seen.
    beyond = np.maximum(np.abs(xx - 300) - 100, np.abs(yy - 300) - 150)
    seen = cv2.erode((image.max(axis=2) > 12).astype(np.uint8), np.ones((9, 9), np.uint8)) > 0
    far = (beyond > 60) & seen
    norm = np.hypot(xx - 300, yy - 300) + 1e-6
    ux, uy = (xx - 300) / norm, (yy - 300) / norm
    lab = cv2.cvtColor(image, cv2.COLOR_BGR2LAB).astype(np.float32)
    row = []
    for k in range(3):
        x = cv2.GaussianBlur(lab[:, :, k], (0, 0), 0.7)
        gx = cv2.Sobel(x, cv2.CV_32F, 1, 0)
        gy = cv2.Sobel(x, cv2.CV_32F, 0, 1)
        along = (gx * ux + gy * uy) ** 2  # gradient along the ray from the car
        total = gx**2 + gy**2
        row.append(1.0 - float(along[far].sum()) / max(1e-6, float(total[far].sum())))
    return row


def main():
    args = view_folders.parse_args(__doc__)
    for folder in args.folders:
        paths = view_folders.views(folder, args.count)
        m = np.median(np.array([shares(p) for p in paths]), axis=0)
        parts = [f"{name} {m[k]:.2f}" for k, name in enumerate(CHANNELS)]
        print(f"{folder} ({len(paths)} views): share across the rays: " + ", ".join(parts))


if __name__ == "__main__":
    view_folders.run(main)
