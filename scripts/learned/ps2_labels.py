"""ps2.0 labels (DMPR-PS's JSON form) read as the project reads them: each
marking point with the direction of its separating line. Needs no torch, so
the analysis scripts share it with the training scripts.

ps2.0 labels an L by the arm from which the other arm turns by a positive
image angle: at a slot's second end that is the entrance line, towards the
partner (src/parkslam/io/ps2_labels.h says how the C++ reader does the same).
"""

import json
import math

LABEL_OFFSET_PX = 0.5    # ps2.0 labels are 1-based: 0-based = label - 0.5
ENTRANCE_ARM_RAD = 0.35  # an L labelled this close to its partner names its entrance


def angle_diff(a, b):
    """a - b wrapped into [-pi, pi)."""
    return (a - b + math.pi) % (2 * math.pi) - math.pi


def separating_lines(marks, slots):
    """`marks` [(x, y, direction_rad, is_t)] as labelled, with each L that
    ends a slot [i, j] (1-based) and is labelled within ENTRANCE_ARM_RAD of
    the way to its partner given its partner's direction (the parallel
    separating line), or its own plus 90 degrees where the partner points
    along the entrance too."""
    labelled = [m[2] for m in marks]
    out = list(marks)
    seen = set()
    for slot in slots:
        a, b = int(slot[0]) - 1, int(slot[1]) - 1
        for mark, partner in ((a, b), (b, a)):
            if marks[mark][3] or mark in seen:
                continue
            seen.add(mark)
            entrance = math.atan2(marks[partner][1] - marks[mark][1],
                                  marks[partner][0] - marks[mark][0])
            if abs(angle_diff(entrance, labelled[mark])) > ENTRANCE_ARM_RAD:
                continue
            along = abs(angle_diff(entrance + math.pi, labelled[partner])) <= ENTRANCE_ARM_RAD
            direction = angle_diff(labelled[mark] + math.pi / 2, 0.0) if along else labelled[partner]
            x, y, _, is_t = marks[mark]
            out[mark] = (x, y, direction, is_t)
    return out


def read_marks(path):
    """[(x, y, direction_rad, is_t)] in 0-based pixels of the 600 px view,
    each direction the mark's separating line."""
    with open(path) as f:
        labels = json.load(f)
    marks = labels.get("marks", [])
    if marks and not isinstance(marks[0], list):
        marks = [marks]
    slots = labels.get("slots", [])
    if slots and not isinstance(slots[0], list):
        slots = [slots]
    out = []
    for m in marks:
        if len(m) != 5:
            raise ValueError(f"{path}: marks: expected [x, y, dx, dy, shape], got {m}")
        x, y, dx, dy, shape = m
        out.append((x - LABEL_OFFSET_PX, y - LABEL_OFFSET_PX, math.atan2(dy - y, dx - x),
                    shape == 0))
    return separating_lines(out, slots)
