#!/usr/bin/python3
"""Width and edge sharpness of the painted separating lines at labelled
marking points of 600 x 600 top views (ps2.0 convention, 10 m across, DMPR-PS
labels: `marks` [x, y, x2, y2, shape], read as separating lines by
learned/ps2_labels.py).

For each mark, a grey-level profile is sampled across the separating line
18, 24 or 30 px from the junction (the first where the line stands at least
15 grey levels above the floor around it, the floor being the median of the
profile's outer 5 px each side): the line's full width at half its height
above the floor (FWHM) and the 10-90 % rise of one edge, in pixels of the
600 px view (6 px = 10 cm). Prints the 10th, 25th, 50th, 75th and 90th
percentiles of each over the folder's first --count views.

Used to compare rendered views with real ones (docs/training_data.md,
"What still gives the rendered views away"); a statistic, nothing learned.

  scripts/line_profiles.py ../shared/data/ps2.0-sample /tmp/views
"""

import math
import os
import sys

import cv2
import numpy as np

import view_folders

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "learned"))
from ps2_labels import read_marks  # noqa: E402

STEP_PX = 0.25
HALF_LENGTH_PX = 20.0
ALONG_PX = (18.0, 24.0, 30.0)
MIN_CONTRAST = 15.0


def profile_figures(profile):
    """(FWHM, rise) in samples of the profile, or None where no line stands
    out near its middle."""
    outer = int(5.0 / STEP_PX)
    floor = float(np.median(np.r_[profile[:outer], profile[-outer:]]))
    middle = len(profile) // 2
    reach = int(10.0 / STEP_PX)
    k = middle - reach + int(np.argmax(profile[middle - reach:middle + reach + 1]))
    height = profile[k] - floor
    if height < MIN_CONTRAST:
        return None
    half = floor + height / 2
    left, right = k, k
    while left > 0 and profile[left] > half:
        left -= 1
    while right < len(profile) - 1 and profile[right] > half:
        right += 1
    if left == 0 or right == len(profile) - 1:
        return None
    high, low = floor + 0.9 * height, floor + 0.1 * height
    top = k
    while top > 0 and profile[top] > high:
        top -= 1
    foot = top
    while foot > 0 and profile[foot] > low:
        foot -= 1
    return right - left, top - foot


def measure(path):
    image = cv2.imread(path, cv2.IMREAD_GRAYSCALE)
    if image is None:
        raise ValueError(f"{path}: not an image")
    if image.shape != (600, 600):
        raise ValueError(f"{path}: {image.shape[1]} x {image.shape[0]} px, expected 600 x 600")
    grey = image.astype(np.float32)
    offsets = np.arange(-HALF_LENGTH_PX, HALF_LENGTH_PX + STEP_PX / 2, STEP_PX)
    out = []
    for x, y, direction, _ in read_marks(os.path.splitext(path)[0] + ".json"):
        along = np.array([math.cos(direction), math.sin(direction)])
        across = np.array([-along[1], along[0]])
        for distance in ALONG_PX:
            points = (np.array([x, y]) + distance * along)[None, :] + offsets[:, None] * across
            if points.min() < 0 or points.max() > 599:
                continue
            profile = cv2.remap(grey, points[:, 0].astype(np.float32).reshape(-1, 1),
                                points[:, 1].astype(np.float32).reshape(-1, 1),
                                cv2.INTER_LINEAR).ravel()
            figures = profile_figures(profile)
            if figures is not None:
                out.append((figures[0] * STEP_PX, figures[1] * STEP_PX))
                break
    return out


def main():
    args = view_folders.parse_args(__doc__, default_count=400, labels=True)
    for folder in args.folders:
        files = view_folders.views(folder, args.count, labels=True)
        figures = np.array([m for f in files for m in measure(f)])
        if len(figures) == 0:
            view_folders.fail(f"{folder}: no line measured")
        quantiles = (10, 25, 50, 75, 90)
        print(f"{folder} ({len(files)} views, {len(figures)} lines measured)")
        print("  percentile        " + "  ".join(f"{q:5d}" for q in quantiles))
        for name, column in (("width (FWHM), px", 0), ("edge rise, px   ", 1)):
            values = np.percentile(figures[:, column], quantiles)
            print(f"  {name}  " + "  ".join(f"{v:5.1f}" for v in values))
    return 0


if __name__ == "__main__":
    view_folders.run(main)
