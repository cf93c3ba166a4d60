"""Shared pieces of the training scripts: seeding, threads, logging, early
stopping (docs/learned_perception.md)."""

import json
import os
import random
import sys
import time

import numpy as np
import torch


def seed_everything(seed):
    random.seed(seed)
    np.random.seed(seed % (2 ** 32))
    torch.manual_seed(seed)


def set_threads(threads):
    if threads > 0:
        torch.set_num_threads(threads)
    import cv2
    cv2.setNumThreads(1)


def log(message):
    print(f"[{time.strftime('%H:%M:%S')}] {message}", flush=True)


def fail(message):
    print(f"error: {message}", file=sys.stderr)
    sys.exit(1)


def write_json_atomically(path, value):
    tmp = f"{path}.tmp.{os.getpid()}"
    with open(tmp, "w") as f:
        json.dump(value, f, indent=2)
        f.write("\n")
    os.replace(tmp, path)


def save_atomically(path, writer):
    """Calls writer(tmp_path), then renames tmp_path to path."""
    tmp = f"{path}.tmp.{os.getpid()}{os.path.splitext(path)[1]}"
    try:
        writer(tmp)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


class EarlyStopping:
    """Stops after `patience` validations without a better score."""

    def __init__(self, patience):
        self.patience = patience
        self.best = -float("inf")
        self.best_epoch = -1
        self.bad = 0

    def update(self, score, epoch):
        """Returns True when score is the best so far."""
        if score > self.best:
            self.best, self.best_epoch, self.bad = score, epoch, 0
            return True
        self.bad += 1
        return False

    def should_stop(self):
        return self.bad >= self.patience
