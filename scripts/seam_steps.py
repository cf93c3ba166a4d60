#!/usr/bin/python3
"""Brightness and colour steps across the seams of 600 x 600 top views
(ps2.0 convention, the car's footprint a black rectangle at the centre).

From each of the footprint's four corners, rays leave outwards at 0.15-0.9
rad from the car's axis. Along each ray, 30-150 px out, the mean CIELAB
colour 4 px to one side is compared with the mean 4 px to the other. A
corner's seam is taken to be the ray of the largest lightness step, chosen
the same way for every view, so that real and rendered views are measured
alike (an edge of paint or of a car along a ray can be taken for a seam in
either). Prints, per folder, percentiles over its seams of the lightness
step and the colour (a, b) step, in OpenCV's 8-bit Lab units, and the
median angle found.

Used to compare rendered views with real ones (docs/training_data.md,
"Straight seams"); a statistic, nothing learned.

  scripts/seam_steps.py ../shared/data/ps2.0-sample /tmp/views
"""

import math

import cv2
import numpy as np

import view_folders

ANGLES_RAD = np.arange(0.15, 0.91, 0.025)
SIDE_PX = 4
REACH_PX = (30, 150)


def footprint(image):
    """The black box at the view's centre: (x0, y0, x1, y1), or None."""
    dark = (image.max(axis=2) < 12).astype(np.uint8)
    _, labels, stats, _ = cv2.connectedComponentsWithStats(dark)
    h, w = dark.shape
    label = labels[h // 2, w // 2]
    if label == 0:
        return None
    x, y, bw, bh = stats[label, :4]
    return x, y, x + bw - 1, y + bh - 1


def seam_steps(path):
    """[(lightness step, colour step, angle)] for each corner of one view."""
    image = cv2.imread(path)
    if image is None:
        raise ValueError(f"{path}: not an image")
    box = footprint(image)
    if box is None:
        return []
    lab = cv2.cvtColor(image, cv2.COLOR_BGR2LAB).astype(np.float32)
    h, w = lab.shape[:2]
    x0, y0, x1, y1 = box
    found = []
    for cx, cy, sx, sy in ((x0, y0, -1, -1), (x1, y0, 1, -1), (x0, y1, -1, 1), (x1, y1, 1, 1)):
        best = None
        for angle in ANGLES_RAD:
            dx, dy = sx * math.sin(angle), sy * math.cos(angle)  # the car points up
            nx, ny = -dy, dx
            one, other = [], []
            for r in range(REACH_PX[0], REACH_PX[1], 2):
                px, py = cx + dx * r, cy + dy * r
                a = (int(round(px + SIDE_PX * nx)), int(round(py + SIDE_PX * ny)))
                b = (int(round(px - SIDE_PX * nx)), int(round(py - SIDE_PX * ny)))
                if not all(0 <= p[0] < w and 0 <= p[1] < h for p in (a, b)):
                    break
                one.append(lab[a[1], a[0]])
                other.append(lab[b[1], b[0]])
            if len(one) < 20:
                continue
            d = np.mean(one, axis=0) - np.mean(other, axis=0)
            step = (abs(float(d[0])), math.hypot(float(d[1]), float(d[2])), float(angle))
            if best is None or step[0] > best[0]:
                best = step
        if best is not None:
            found.append(best)
    return found


def main():
    args = view_folders.parse_args(__doc__)
    for folder in args.folders:
        paths = view_folders.views(folder, args.count)
        steps = np.array([s for p in paths for s in seam_steps(p)])
        if len(steps) == 0:
            view_folders.fail(f"{folder}: no view with a black footprint at its centre")
        light, colour, angle = steps[:, 0], steps[:, 1], steps[:, 2]
        print(f"{folder}: {len(paths)} views, {len(steps)} seams; lightness step "
              f"p25/50/75/90 {np.percentile(light, 25):.1f} / {np.median(light):.1f} / "
              f"{np.percentile(light, 75):.1f} / {np.percentile(light, 90):.1f}; colour step "
              f"median {np.median(colour):.1f}, p75 {np.percentile(colour, 75):.1f}; "
              f"angle median {np.median(angle):.2f} rad")


if __name__ == "__main__":
    view_folders.run(main)
