#!/usr/bin/python3
"""Trains the marking-point network (models.MarkingPointNet) on top views
written by `parkslam make-training-set` and exports it to ONNX for OpenCV's
dnn module. See docs/learned_perception.md for the exact command, seed and
time of the committed weights.

Never train or tune on the real ps2.0 sample (../shared/data): it is test
data.
"""

import argparse
import copy
import functools
import glob
import math
import multiprocessing
import os
import sys
import time

import cv2
import numpy as np
import torch
import torch.nn.functional as F

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from reference_outputs import write_reference  # noqa: E402
from models import MarkingPointNet, export_onnx  # noqa: E402
from ps2_labels import read_marks  # noqa: E402

FULL_PX = 600          # the top view's size (10 m at 60 px/m)
MATCH_PX = 10.0        # DMPR-PS rule: within 10 px of 600 ...
MATCH_RAD = math.radians(30.0)  # ... and 30 degrees of direction
NMS_PX = 20.0          # two detections closer than this are one point


def read_resized(path, size):
    image = cv2.imread(path, cv2.IMREAD_COLOR)
    if image is None or image.shape[:2] != (FULL_PX, FULL_PX):
        common.fail(f"{path}: not a {FULL_PX} x {FULL_PX} image")
    return cv2.resize(image, (size, size), interpolation=cv2.INTER_AREA)


def load_folder(folder, size, limit, cache_dir, workers=0):
    """Images resized to size x size (uint8 BGR) and their marks; read by
    `workers` processes when above 0."""
    names = sorted(os.path.splitext(os.path.basename(p))[0]
                   for p in glob.glob(os.path.join(folder, "*.json")))
    names = [n for n in names if os.path.exists(os.path.join(folder, n + ".jpg"))]
    if not names:
        common.fail(f"{folder}: no labelled top views (NNNNNN.jpg with NNNNNN.json)")
    if limit > 0:
        names = names[:limit]
    marks = [read_marks(os.path.join(folder, n + ".json")) for n in names]
    cache = None
    if cache_dir:
        os.makedirs(cache_dir, exist_ok=True)
        key = f"{os.path.basename(os.path.normpath(folder))}_{len(names)}_{size}.npy"
        cache = os.path.join(cache_dir, key)
        if os.path.exists(cache):
            images = np.load(cache, mmap_mode="r")
            if images.shape[0] == len(names):
                return np.ascontiguousarray(images), marks
    images = np.empty((len(names), size, size, 3), np.uint8)
    paths = [os.path.join(folder, n + ".jpg") for n in names]
    if workers > 0:
        with multiprocessing.Pool(workers) as pool:
            for i, image in enumerate(pool.imap(functools.partial(read_resized, size=size), paths,
                                                chunksize=64)):
                images[i] = image
                if (i + 1) % 10000 == 0:
                    common.log(f"  {folder}: {i + 1} of {len(names)} images read")
    else:
        for i, path in enumerate(paths):
            images[i] = read_resized(path, size)
            if (i + 1) % 2000 == 0:
                common.log(f"  {folder}: {i + 1} of {len(names)} images read")
    if cache:
        common.save_atomically(cache, lambda tmp: np.save(open(tmp, "wb"), images))
    return images, marks


def cast_shadows(f, rng, size):
    """One to three soft-edged quadrilaterals darkened to 35-75 %: the hard
    shadows of cars, pillars and walls that fall across real lines."""
    shade = np.ones((size, size), np.float32)
    for _ in range(int(rng.integers(1, 4))):
        centre = rng.uniform(0, size, 2)
        corners = centre + rng.uniform(-0.35, 0.35, (4, 2)) * size
        cv2.fillConvexPoly(shade, corners.astype(np.int32), float(rng.uniform(0.35, 0.75)))
    edge = rng.uniform(0.5, 3.0)
    shade = cv2.GaussianBlur(shade, (0, 0), edge)
    return f * shade[:, :, None]


def add_occluders(f, moved, rng, size):
    """One to three opaque blobs (a parked car's smeared body, a pillar, a
    person) of a random colour and grain, ellipses or rotated boxes 8-35 %
    of the view across; marks they cover are no longer visible and leave
    the targets."""
    covered = np.zeros((size, size), np.uint8)
    for _ in range(int(rng.integers(1, 4))):
        cover = np.zeros((size, size), np.uint8)
        centre = tuple(int(v) for v in rng.uniform(0, size, 2))
        axes = tuple(int(v) for v in rng.uniform(0.04, 0.18, 2) * size)
        angle = float(rng.uniform(0, 180))
        if rng.random() < 0.5:
            cv2.ellipse(cover, centre, axes, angle, 0, 360, 255, -1)
        else:
            box = cv2.boxPoints((centre, (2 * axes[0], 2 * axes[1]), angle))
            cv2.fillConvexPoly(cover, box.astype(np.int32), 255)
        colour = rng.uniform(0, 1, 3).astype(np.float32)
        grain = rng.normal(0, rng.uniform(0.02, 0.12), (size, size, 1)).astype(np.float32)
        paint = np.clip(colour[None, None, :] + grain, 0, 1)
        inside = cover > 0
        f[inside] = paint[inside]
        covered |= cover
    covered = cv2.dilate(covered, np.ones((5, 5), np.uint8))
    kept = [m for m in moved if covered[min(int(m[1]), size - 1), min(int(m[0]), size - 1)] == 0]
    return f, kept


def augment(image, marks, rng, size, shadows=0.0, occluders=0.0):
    """A random flip, small rotation, scale and shift, and photometric
    changes; returns the image and the marks moved with it (in the scaled
    image's continuous coordinates: pixel edges at 0 and size). With
    probabilities `shadows` and `occluders`, soft shadows and opaque
    blobs (marks under them dropped) as well."""
    scale = size / FULL_PX
    pts = [((x + 0.5) * scale, (y + 0.5) * scale, a, t) for x, y, a, t in marks]
    angle = rng.uniform(-8, 8) if rng.random() < 0.5 else 0.0
    zoom = rng.uniform(0.9, 1.1)
    shift = rng.uniform(-0.08, 0.08, 2) * size
    A = cv2.getRotationMatrix2D((size / 2, size / 2), angle, zoom)
    A[:, 2] += shift
    if rng.random() < 0.5:  # mirror left-right
        A = np.array([[-1, 0, size], [0, 1, 0]], float) @ np.vstack([A, [0, 0, 1]])
    if rng.random() < 0.5:  # mirror up-down
        A = np.array([[1, 0, 0], [0, -1, size]], float) @ np.vstack([A, [0, 0, 1]])
    # warpAffine maps pixel centres: shift by half a pixel either side.
    C = A.copy()
    C[:, 2] += A[:, :2] @ np.array([0.5, 0.5]) - 0.5
    out = cv2.warpAffine(image, C, (size, size), flags=cv2.INTER_LINEAR,
                         borderMode=cv2.BORDER_REPLICATE)
    moved = []
    for x, y, a, t in pts:
        p = A[:, :2] @ np.array([x, y]) + A[:, 2]
        d = A[:, :2] @ np.array([math.cos(a), math.sin(a)])
        if 0 <= p[0] < size and 0 <= p[1] < size:
            moved.append((p[0], p[1], math.atan2(d[1], d[0]), t))
    # Photometric: exposure, gamma, white balance, contrast, greyscale,
    # blur, noise, JPEG.
    f = out.astype(np.float32) / 255.0
    if occluders > 0 and rng.random() < occluders:
        f, moved = add_occluders(f, moved, rng, size)
    if shadows > 0 and rng.random() < shadows:
        f = cast_shadows(f, rng, size)
    f = np.power(np.clip(f * rng.uniform(0.6, 1.4), 0, 1), rng.uniform(0.7, 1.4))
    f *= rng.uniform(0.85, 1.15, 3).astype(np.float32)
    mean = f.mean()
    f = (f - mean) * rng.uniform(0.7, 1.3) + mean
    if rng.random() < 0.1:
        f[:] = f.mean(axis=2, keepdims=True)
    if rng.random() < 0.3:
        f = cv2.GaussianBlur(f, (0, 0), rng.uniform(0.4, 2.0))
    elif rng.random() < 0.15:  # smear along one direction, as a fused view's periphery
        k = np.zeros((7, 7), np.float32)
        k[3, :] = 1.0 / 7.0
        k = cv2.warpAffine(k, cv2.getRotationMatrix2D((3, 3), rng.uniform(0, 180), 1.0), (7, 7))
        f = cv2.filter2D(f, -1, k / max(k.sum(), 1e-6))
    if rng.random() < 0.5:
        f += rng.normal(0, rng.uniform(0.005, 0.03), f.shape).astype(np.float32)
    out = np.clip(f * 255.0, 0, 255).astype(np.uint8)
    if rng.random() < 0.3:
        ok, buf = cv2.imencode(".jpg", out, [cv2.IMWRITE_JPEG_QUALITY, int(rng.integers(30, 90))])
        out = cv2.imdecode(buf, cv2.IMREAD_COLOR)
    return out, moved


def targets(batch_marks, size, grid):
    """Per-cell targets: mask, offset (2), cos/sin (2), is_t."""
    n = len(batch_marks)
    mask = np.zeros((n, grid, grid), np.float32)
    reg = np.zeros((n, 5, grid, grid), np.float32)
    cell = size / grid
    for b, marks in enumerate(batch_marks):
        for x, y, a, t in marks:
            cx, cy = min(int(x / cell), grid - 1), min(int(y / cell), grid - 1)
            mask[b, cy, cx] = 1.0
            reg[b, :, cy, cx] = (x / cell - cx, y / cell - cy, math.cos(a), math.sin(a), float(t))
    return torch.from_numpy(mask), torch.from_numpy(reg)


class AugmentedViews(torch.utils.data.Dataset):
    """The training views, augmented in DataLoader worker processes
    (--workers above 0). Worker w of epoch e draws from the generator
    seeded (seed, e, w), so a run is repeatable for a fixed worker count."""

    def __init__(self, images, marks, size, grid, seed, shadows=0.0, occluders=0.0):
        self.images, self.marks, self.size, self.grid, self.seed = images, marks, size, grid, seed
        self.shadows, self.occluders = shadows, occluders
        self.epoch = 0
        self.rng = None

    def __len__(self):
        return len(self.images)

    def augmented(self, i, rng):
        """View i augmented with `rng`, and its marks moved with it."""
        return augment(self.images[i], self.marks[i], rng, self.size, self.shadows,
                       self.occluders)

    def __getitem__(self, i):
        if self.rng is None:
            info = torch.utils.data.get_worker_info()
            self.rng = np.random.default_rng([self.seed, self.epoch, info.id if info else 0])
        image, moved = self.augmented(i, self.rng)
        mask, reg = targets([moved], self.size, self.grid)
        return torch.from_numpy(image), mask[0], reg[0]


def random_convolution(pixels, share, generator):
    """Random convolutions (RandConv; Xu et al., "Robust and Generalizable
    Visual Representation Learning via Random Convolutions", ICLR 2021):
    with probability `share` a view (float, 0-255, N x 3 x H x W) passes
    through a 3-to-3-channel convolution of random Gaussian weights (kernel
    1, 3 or 5 px), is rescaled to the view's own per-channel mean and
    spread, and is blended with the view by a random weight. Colours,
    contrast (even its sign) and local texture change while shapes stay: a
    way to generalize beyond the rendering's look without target images."""
    out = pixels.clone()
    for b in range(pixels.shape[0]):
        if torch.rand(1, generator=generator).item() >= share:
            continue
        k = (1, 3, 5)[int(torch.randint(0, 3, (1,), generator=generator))]
        weights = torch.randn(3, 3, k, k, generator=generator) / math.sqrt(3 * k * k)
        x = pixels[b:b + 1]
        y = F.conv2d(x, weights.to(x.device), padding=k // 2)
        y = ((y - y.mean((2, 3), keepdim=True)) / y.std((2, 3), keepdim=True).clamp(min=1e-3)
             * x.std((2, 3), keepdim=True) + x.mean((2, 3), keepdim=True))
        a = torch.rand(1, generator=generator).item()
        out[b] = (a * x + (1 - a) * y).clamp(0, 255)[0]
    return out


def loss_of(raw, mask, reg):
    conf = F.binary_cross_entropy_with_logits(raw[:, 0], mask,
                                              pos_weight=torch.tensor(2.0, device=raw.device))
    positives = mask.sum().clamp(min=1.0)
    m = mask.unsqueeze(1)
    offset = ((torch.sigmoid(raw[:, 1:3]) - reg[:, 0:2]) ** 2 * m).sum() / positives
    direction = ((torch.tanh(raw[:, 3:5]) - reg[:, 2:4]) ** 2 * m).sum() / positives
    shape = (F.binary_cross_entropy_with_logits(raw[:, 5], reg[:, 4], reduction="none")
             * mask).sum() / positives
    return conf + 5.0 * offset + 2.0 * direction + 0.5 * shape


def decode(cells, threshold):
    """Marking points [(x, y, direction_rad, is_t, score)] in 0-based
    pixels of the 600 px view from one output (6 x G x G), after NMS. The
    C++ side (perception/learned_slot_detector.cc) does the same."""
    grid = cells.shape[1]
    ys, xs = np.nonzero(cells[0] >= threshold)
    found = []
    for cy, cx in zip(ys, xs):
        c = cells[:, cy, cx]
        x = (cx + c[1]) / grid * FULL_PX - 0.5
        y = (cy + c[2]) / grid * FULL_PX - 0.5
        found.append((x, y, math.atan2(c[4], c[3]), c[5] >= 0.5, float(c[0])))
    found.sort(key=lambda p: -p[4])
    kept = []
    for p in found:
        if all((p[0] - q[0]) ** 2 + (p[1] - q[1]) ** 2 > NMS_PX ** 2 for q in kept):
            kept.append(p)
    return kept


def match_counts(found, truth):
    """(true positives, false positives, false negatives) by the DMPR-PS
    rule, greedily by score."""
    used = [False] * len(truth)
    tp = 0
    for x, y, a, _, _ in found:
        for k, (tx, ty, ta, _) in enumerate(truth):
            da = abs((a - ta + math.pi) % (2 * math.pi) - math.pi)
            if not used[k] and (x - tx) ** 2 + (y - ty) ** 2 <= MATCH_PX ** 2 and da <= MATCH_RAD:
                used[k] = True
                tp += 1
                break
    return tp, len(found) - tp, len(truth) - tp


def to_tensor(images):
    return torch.from_numpy(np.ascontiguousarray(images)).permute(0, 3, 1, 2).float()


def validate(model, images, marks, device, thresholds=(0.3, 0.4, 0.5, 0.6, 0.7)):
    model.eval()
    counts = {t: [0, 0, 0] for t in thresholds}
    with torch.no_grad():
        for start in range(0, len(images), 64):
            out = model(to_tensor(images[start:start + 64]).to(device)).cpu().numpy()
            for k, cells in enumerate(out):
                for t in thresholds:
                    c = match_counts(decode(cells, t), marks[start + k])
                    counts[t] = [a + b for a, b in zip(counts[t], c)]
    scores = {}
    for t, (tp, fp, fn) in counts.items():
        p = tp / max(tp + fp, 1)
        r = tp / max(tp + fn, 1)
        scores[t] = {"precision": p, "recall": r, "f1": 2 * p * r / max(p + r, 1e-9)}
    return scores


def write_outputs(model, args, size, training_images, validation_images, stopper, best_scores,
                  history, train_started):
    """The network (ONNX), its reference outputs and OUT.json, the record
    of how it was made."""
    model = copy.deepcopy(model).cpu().eval()
    export_onnx(model, (1, 3, size, size), args.out, "cells")
    write_reference(args.out, (1, 3, size, size))
    common.write_json_atomically(args.out + ".json", {
        "network": "MarkingPointNet", "input_size": size, "stride": MarkingPointNet.STRIDE,
        "widths": list(args.widths), "input_norm": args.input_norm,
        "random_conv": args.random_conv,
        "outputs": ["confidence", "offset_x", "offset_y", "cos", "sin", "t_shape"],
        "command": " ".join(["scripts/learned/train_marking_points.py"] + sys.argv[1:]),
        "seed": args.seed, "torch": torch.__version__, "threads": torch.get_num_threads(),
        "device": args.device, "workers": args.workers,
        "training_images": training_images, "validation_images": validation_images,
        "best_epoch": stopper.best_epoch, "validation": best_scores,
        "training_minutes": round((time.time() - train_started) / 60, 1), "history": history,
    })


def batches(views, rng, epoch, args, steps):
    """(images, mask, reg) batches of one epoch: augmented here, one view at
    a time from `rng` (--workers 0, the committed CPU recipe), or by worker
    processes."""
    if args.workers == 0:
        order = rng.permutation(len(views.images))
        for step in range(steps):
            idx = order[step * args.batch:(step + 1) * args.batch]
            batch, batch_marks = [], []
            for i in idx:
                image, moved = views.augmented(i, rng)
                batch.append(image)
                batch_marks.append(moved)
            mask, reg = targets(batch_marks, views.size, views.grid)
            yield torch.from_numpy(np.stack(batch)), mask, reg
        return
    views.epoch, views.rng = epoch, None
    sampler = torch.utils.data.RandomSampler(
        views, generator=torch.Generator().manual_seed(args.seed * 1000 + epoch))
    loader = torch.utils.data.DataLoader(views, batch_size=args.batch, sampler=sampler,
                                         num_workers=args.workers, drop_last=True,
                                         pin_memory=args.device != "cpu", persistent_workers=False)
    for step, item in enumerate(loader):
        if step >= steps:
            break
        yield item


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--train", nargs="+", required=True,
                        help="folders written by `parkslam make-training-set`")
    parser.add_argument("--val", required=True, help="held-apart folder (another seed)")
    parser.add_argument("--out", required=True, help="the ONNX file to write (and OUT.json)")
    parser.add_argument("--input-size", type=int, default=256, help="network input, pixels")
    parser.add_argument("--widths", type=int, nargs=4, default=[16, 32, 64, 128],
                        help="channels at strides 2, 4, 8 and 16")
    parser.add_argument("--epochs", type=int, default=30)
    parser.add_argument("--batch", type=int, default=32)
    parser.add_argument("--lr", type=float, default=2e-3)
    parser.add_argument("--patience", type=int, default=4,
                        help="epochs without a better validation F1 before stopping")
    parser.add_argument("--max-minutes", type=float, default=0,
                        help="stop after this much training time (0: no limit)")
    parser.add_argument("--max-images", type=int, default=0, help="per folder (0: all)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--threads", type=int, default=0, help="torch threads (0: default)")
    parser.add_argument("--cache", default="", help="folder for decoded, resized images")
    parser.add_argument("--device", default="cpu",
                        help="torch device to train on: cpu (the documented route) or cuda")
    parser.add_argument("--workers", type=int, default=0,
                        help="processes that read and augment the views (0: in this process, "
                             "as the committed CPU recipe)")
    parser.add_argument("--input-norm", choices=["none", "local", "grey"], default="none",
                        help="inside the network, before the first convolution: local, each "
                             "channel's local contrast normalized (models.LocalContrastNorm); "
                             "grey, the channels' mean (models.Greyscale)")
    parser.add_argument("--shadows", type=float, default=0.0,
                        help="share of views augmented with soft shadows (0: the committed recipe)")
    parser.add_argument("--occluders", type=float, default=0.0,
                        help="share of views augmented with opaque blobs over the floor; marks "
                             "under them leave the targets (0: the committed recipe)")
    parser.add_argument("--random-conv", type=float, default=0.0,
                        help="share of views passed through a random convolution and blended "
                             "with it (random_convolution; 0: the committed recipe)")
    args = parser.parse_args()
    if args.device.startswith("cuda") and not torch.cuda.is_available():
        common.fail(f"--device {args.device}: torch sees no CUDA device")
    if args.input_size % MarkingPointNet.STRIDE != 0:
        common.fail(f"--input-size: {args.input_size} is not a multiple of {MarkingPointNet.STRIDE}")

    common.seed_everything(args.seed)
    common.set_threads(args.threads)
    size, grid = args.input_size, args.input_size // MarkingPointNet.STRIDE
    started = time.time()
    parts = [load_folder(f, size, args.max_images, args.cache, args.workers) for f in args.train]
    images = np.concatenate([p[0] for p in parts])
    marks = [m for p in parts for m in p[1]]
    val_images, val_marks = load_folder(args.val, size, args.max_images, args.cache, args.workers)
    common.log(f"{len(images)} training and {len(val_images)} validation images "
               f"({time.time() - started:.0f} s to read)")

    device = torch.device(args.device)
    torch.backends.cudnn.benchmark = True
    model = MarkingPointNet(tuple(args.widths), args.input_norm).to(device)
    optimizer = torch.optim.AdamW(model.parameters(), lr=args.lr, weight_decay=1e-4)
    steps_per_epoch = max(1, len(images) // args.batch)
    schedule = torch.optim.lr_scheduler.OneCycleLR(
        optimizer, max_lr=args.lr, total_steps=args.epochs * steps_per_epoch, pct_start=0.1)
    rng = np.random.default_rng(args.seed)
    stopper = common.EarlyStopping(args.patience)
    best_state, best_scores, history = None, None, []
    train_started = time.time()
    views = AugmentedViews(images, marks, size, grid, args.seed, args.shadows, args.occluders)
    conv_generator = torch.Generator().manual_seed(args.seed)
    for epoch in range(args.epochs):
        model.train()
        total = 0.0
        for step, (batch, mask, reg) in enumerate(batches(views, rng, epoch, args, steps_per_epoch)):
            pixels = batch.to(device, non_blocking=True).permute(0, 3, 1, 2).float()
            if args.random_conv > 0:
                pixels = random_convolution(pixels, args.random_conv, conv_generator)
            loss = loss_of(model.raw(pixels),
                           mask.to(device, non_blocking=True), reg.to(device, non_blocking=True))
            optimizer.zero_grad()
            loss.backward()
            optimizer.step()
            schedule.step()
            total += loss.item()
            if (step + 1) % 50 == 0:
                common.log(f"  epoch {epoch + 1} step {step + 1}/{steps_per_epoch} "
                           f"loss {total / (step + 1):.4f}")
        scores = validate(model, val_images, val_marks, device)
        threshold = max(scores, key=lambda t: scores[t]["f1"])
        best = scores[threshold]
        history.append({"epoch": epoch + 1, "loss": total / steps_per_epoch,
                        "threshold": threshold, **best})
        common.log(f"epoch {epoch + 1}: loss {total / steps_per_epoch:.4f}, validation at "
                   f"{threshold}: precision {100 * best['precision']:.2f} %, recall "
                   f"{100 * best['recall']:.2f} %")
        if stopper.update(best["f1"], epoch + 1):
            best_state = {k: v.clone() for k, v in model.state_dict().items()}
            best_scores = {"threshold": threshold, **best}
            write_outputs(model, args, size, len(images), len(val_images), stopper, best_scores,
                          history, train_started)
        minutes = (time.time() - train_started) / 60
        if stopper.should_stop():
            common.log(f"no better validation for {args.patience} epochs: stopping")
            break
        if args.max_minutes > 0 and minutes >= args.max_minutes:
            common.log(f"{minutes:.1f} minutes of training: stopping")
            break
    model.load_state_dict(best_state)
    write_outputs(model, args, size, len(images), len(val_images), stopper, best_scores, history,
                  train_started)
    common.log(f"wrote {args.out} (best epoch {stopper.best_epoch}: validation precision "
               f"{100 * best_scores['precision']:.2f} %, recall {100 * best_scores['recall']:.2f} %)")


if __name__ == "__main__":
    main()
