#!/usr/bin/python3
"""Texture energy of 600 x 600 top views (ps2.0 convention, 10 m across) by
scale and by distance from the car: the median absolute difference of
Gaussians (sigma s minus sigma 2 s) over the floor around the car's
footprint, in grey levels, for s = 0.7, 1.5, 3 and 6 pixels and three
rings (0-60, 60-120 and 120-300 pixels beyond the footprint's box). Each
folder's figure is the median over its first --count images.

Used to compare rendered views with real ones (docs/training_data.md,
"Floors"); a statistic, nothing learned.

  scripts/texture_bands.py ../shared/data/ps2.0-sample /tmp/views
"""

import cv2
import numpy as np

import view_folders

SIGMAS = (0.7, 1.5, 3.0, 6.0)
RINGS = ((0, 60), (60, 120), (120, 300))


def bands(path):
    image = cv2.imread(path, cv2.IMREAD_GRAYSCALE)
    if image is None:
        raise ValueError(f"{path}: not an image")
    if image.shape != (600, 600):
        raise ValueError(f"{path}: {image.shape[1]} x {image.shape[0]} px, expected 600 x 600")
    grey = image.astype(np.float32)
    yy, xx = np.mgrid[0:600, 0:600]
    # The footprint (about 2 x 3.2 m at 60 px a metre) and its box's distance.
    car = (np.abs(xx - 300) < 110) & (np.abs(yy - 300) < 160)
    beyond = np.maximum(np.abs(xx - 300) - 100, np.abs(yy - 300) - 150)
    out = np.zeros((len(RINGS), len(SIGMAS)))
    for j, s in enumerate(SIGMAS):
        dog = np.abs(cv2.GaussianBlur(grey, (0, 0), s) - cv2.GaussianBlur(grey, (0, 0), 2 * s))
        for i, (lo, hi) in enumerate(RINGS):
            out[i, j] = np.median(dog[~car & (beyond >= lo) & (beyond < hi)])
    return out


def main():
    args = view_folders.parse_args(__doc__)
    for folder in args.folders:
        files = view_folders.views(folder, args.count)
        figure = np.median(np.array([bands(f) for f in files]), axis=0)
        print(f"{folder} ({len(files)} views)")
        print("  ring (px beyond the car)  " + "  ".join(f"s={s:<4}" for s in SIGMAS))
        for (lo, hi), row in zip(RINGS, figure):
            print(f"  {lo:3d}-{hi:<3d}                  " + "  ".join(f"{v:6.2f}" for v in row))
    return 0


if __name__ == "__main__":
    view_folders.run(main)
