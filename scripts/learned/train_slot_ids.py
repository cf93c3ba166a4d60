#!/usr/bin/python3
"""Trains the slot-ID reader (models.SlotIdNet) on ID crops written by
`parkslam make-training-set --kind ids` and exports it to ONNX for OpenCV's
dnn module. See docs/learned_perception.md for the exact command, seed and
time of the committed weights.

Never train or tune on the real images in ../shared/data: they are test
data.
"""

import argparse
import csv
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
from models import ID_ALPHABET, ID_POSITIONS, SlotIdNet, export_onnx  # noqa: E402

WIDTH, HEIGHT = 96, 32


def encode(text, where):
    if len(text) > ID_POSITIONS:
        common.fail(f"{where}: ID '{text}' is longer than {ID_POSITIONS} characters")
    codes = []
    for ch in text:
        if ch not in ID_ALPHABET:
            common.fail(f"{where}: ID '{text}': character '{ch}' is not in the alphabet")
        codes.append(1 + ID_ALPHABET.index(ch))
    return codes + [0] * (ID_POSITIONS - len(codes))


def load_folder(folder, limit):
    labels = os.path.join(folder, "ids", "labels.csv")
    if not os.path.exists(labels):
        common.fail(f"{labels}: missing (write the set with --kind ids)")
    with open(labels) as f:
        rows = list(csv.DictReader(f))
    if limit > 0:
        rows = rows[:limit]
    images = np.empty((len(rows), HEIGHT, WIDTH, 3), np.uint8)
    codes = np.empty((len(rows), ID_POSITIONS), np.int64)
    for i, row in enumerate(rows):
        path = os.path.join(folder, row["file"])
        image = cv2.imread(path, cv2.IMREAD_COLOR)
        if image is None or image.shape[:2] != (HEIGHT, WIDTH):
            common.fail(f"{path}: not a {WIDTH} x {HEIGHT} image")
        images[i] = image
        codes[i] = encode(row["text"], f"{labels}:{i + 2}")
    return images, codes


def augment(image, rng):
    """The crop's box as a reader finds it, not as drawn: shifted, scaled,
    slightly rotated; and photometric changes."""
    angle = rng.uniform(-6, 6)
    zoom = rng.uniform(0.85, 1.15)
    A = cv2.getRotationMatrix2D((WIDTH / 2, HEIGHT / 2), angle, zoom)
    A[0, 2] += rng.uniform(-0.08, 0.08) * WIDTH
    A[1, 2] += rng.uniform(-0.12, 0.12) * HEIGHT
    out = cv2.warpAffine(image, A, (WIDTH, HEIGHT), flags=cv2.INTER_LINEAR,
                         borderMode=cv2.BORDER_REPLICATE)
    f = out.astype(np.float32) / 255.0
    f = np.power(np.clip(f * rng.uniform(0.6, 1.4), 0, 1), rng.uniform(0.7, 1.4))
    f *= rng.uniform(0.85, 1.15, 3).astype(np.float32)
    if rng.random() < 0.15:
        f[:] = f.mean(axis=2, keepdims=True)
    if rng.random() < 0.2:
        f = cv2.GaussianBlur(f, (0, 0), rng.uniform(0.4, 1.0))
    if rng.random() < 0.5:
        f += rng.normal(0, rng.uniform(0.005, 0.03), f.shape).astype(np.float32)
    return np.clip(f * 255.0, 0, 255).astype(np.uint8)


def to_tensor(images):
    return torch.from_numpy(np.ascontiguousarray(images)).permute(0, 3, 1, 2).float()


def validate(model, images, codes, device):
    """Share of crops whose whole text (or its absence) is read right."""
    model.eval()
    right = 0
    with torch.no_grad():
        for start in range(0, len(images), 256):
            best = model(to_tensor(images[start:start + 256]).to(device)).argmax(2).cpu().numpy()
            right += int((best == codes[start:start + 256]).all(axis=1).sum())
    return right / max(len(images), 1)


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--train", nargs="+", required=True,
                        help="folders written by `parkslam make-training-set --kind ids`")
    parser.add_argument("--val", required=True, help="held-apart folder (another seed)")
    parser.add_argument("--out", required=True, help="the ONNX file to write (and OUT.json)")
    parser.add_argument("--widths", type=int, nargs=3, default=[24, 48, 96],
                        help="channels of the three convolution stages")
    parser.add_argument("--hidden", type=int, default=192, help="width of the hidden layer")
    parser.add_argument("--epochs", type=int, default=30)
    parser.add_argument("--batch", type=int, default=64)
    parser.add_argument("--lr", type=float, default=2e-3)
    parser.add_argument("--patience", type=int, default=4)
    parser.add_argument("--max-minutes", type=float, default=0)
    parser.add_argument("--max-images", type=int, default=0, help="per folder (0: all)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--device", default="cpu",
                        help="torch device to train on: cpu (the documented route) or cuda")
    args = parser.parse_args()
    if args.device.startswith("cuda") and not torch.cuda.is_available():
        common.fail(f"--device {args.device}: torch sees no CUDA device")
    device = torch.device(args.device)

    common.seed_everything(args.seed)
    common.set_threads(args.threads)
    parts = [load_folder(f, args.max_images) for f in args.train]
    images = np.concatenate([p[0] for p in parts])
    codes = np.concatenate([p[1] for p in parts])
    val_images, val_codes = load_folder(args.val, args.max_images)
    common.log(f"{len(images)} training and {len(val_images)} validation crops")

    model = SlotIdNet(tuple(args.widths), args.hidden).to(device)
    optimizer = torch.optim.AdamW(model.parameters(), lr=args.lr, weight_decay=1e-4)
    steps = max(1, len(images) // args.batch)
    schedule = torch.optim.lr_scheduler.OneCycleLR(optimizer, max_lr=args.lr,
                                                   total_steps=args.epochs * steps, pct_start=0.1)
    rng = np.random.default_rng(args.seed)
    stopper = common.EarlyStopping(args.patience)
    best_state, history = None, []
    started = time.time()
    for epoch in range(args.epochs):
        model.train()
        order = rng.permutation(len(images))
        total = 0.0
        for step in range(steps):
            idx = order[step * args.batch:(step + 1) * args.batch]
            batch = np.stack([augment(images[i], rng) for i in idx])
            raw = model.raw(to_tensor(batch).to(device))
            loss = F.cross_entropy(raw.reshape(-1, model.classes),
                                   torch.from_numpy(codes[idx]).reshape(-1).to(device))
            optimizer.zero_grad()
            loss.backward()
            optimizer.step()
            schedule.step()
            total += loss.item()
        accuracy = validate(model, val_images, val_codes, device)
        history.append({"epoch": epoch + 1, "loss": total / steps, "accuracy": accuracy})
        common.log(f"epoch {epoch + 1}: loss {total / steps:.4f}, validation: "
                   f"{100 * accuracy:.2f} % of crops read right")
        if stopper.update(accuracy, epoch + 1):
            best_state = {k: v.clone() for k, v in model.state_dict().items()}
        if stopper.should_stop():
            common.log(f"no better validation for {args.patience} epochs: stopping")
            break
        if args.max_minutes > 0 and (time.time() - started) / 60 >= args.max_minutes:
            common.log("time limit: stopping")
            break
    model.load_state_dict(best_state)
    model = model.cpu().eval()
    export_onnx(model, (1, 3, HEIGHT, WIDTH), args.out, "chars")
    write_reference(args.out, (1, 3, HEIGHT, WIDTH))
    common.write_json_atomically(args.out + ".json", {
        "network": "SlotIdNet", "widths": list(args.widths), "hidden": args.hidden,
        "input": [HEIGHT, WIDTH], "positions": ID_POSITIONS,
        "alphabet": ID_ALPHABET, "command": " ".join(
            ["scripts/learned/train_slot_ids.py"] + sys.argv[1:]),
        "seed": args.seed, "torch": torch.__version__, "threads": torch.get_num_threads(),
        "device": args.device, "training_crops": len(images), "validation_crops": len(val_images),
        "best_epoch": stopper.best_epoch, "validation_accuracy": stopper.best,
        "training_minutes": round((time.time() - started) / 60, 1), "history": history,
    })
    common.log(f"wrote {args.out} (best epoch {stopper.best_epoch}: "
               f"{100 * stopper.best:.2f} % of validation crops read right)")


if __name__ == "__main__":
    main()
