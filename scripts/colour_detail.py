#!/usr/bin/python3
"""Fine-scale colour of 600 x 600 top views: for each CIELAB channel (L, a,
b; OpenCV's 8-bit units) the median absolute difference of Gaussians
(sigma s minus sigma 2 s) over the seen pixels (not the black footprint or
unseen corners, eroded by 4 px), for s = 0.7, 1.5 and 3 pixels, and the
channel's standard deviation. Each folder's figure is the median over its
first --count views.

Used to compare rendered views with real ones (docs/training_data.md,
"Colour"); a statistic, nothing learned.

  scripts/colour_detail.py ../shared/data/ps2.0-sample /tmp/views
"""

import cv2
import numpy as np

import view_folders

SIGMAS = (0.7, 1.5, 3.0)
CHANNELS = ("L", "a", "b")


def detail(path):
    image = cv2.imread(path)
    if image is None:
        raise ValueError(f"{path}: not an image")
    seen = cv2.erode((image.max(axis=2) > 12).astype(np.uint8), np.ones((9, 9), np.uint8)) > 0
    lab = cv2.cvtColor(image, cv2.COLOR_BGR2LAB).astype(np.float32)
    row = []
    for k in range(3):
        x = lab[:, :, k]
        for s in SIGMAS:
            dog = cv2.GaussianBlur(x, (0, 0), s) - cv2.GaussianBlur(x, (0, 0), 2 * s)
            row.append(float(np.median(np.abs(dog[seen]))))
        row.append(float(np.std(x[seen])))
    return row


def main():
    args = view_folders.parse_args(__doc__)
    for folder in args.folders:
        paths = view_folders.views(folder, args.count)
        m = np.median(np.array([detail(p) for p in paths]), axis=0)
        parts = []
        for k, name in enumerate(CHANNELS):
            d = m[4 * k: 4 * k + 4]
            parts.append(f"{name} {d[0]:.2f} / {d[1]:.2f} / {d[2]:.2f}, sd {d[3]:.1f}")
        print(f"{folder} ({len(paths)} views; s = 0.7 / 1.5 / 3 px): " + "; ".join(parts))


if __name__ == "__main__":
    view_folders.run(main)
