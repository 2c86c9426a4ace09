"""Pieces both wire finders use."""
from __future__ import annotations

import time

import numpy as np


def block_average(grey: np.ndarray, k: int) -> np.ndarray:
    """The mean of each k x k block (float32); a partial block at an edge is dropped."""
    if k == 1:
        return grey.astype(np.float32)
    h, w = grey.shape[0] // k * k, grey.shape[1] // k * k
    out = np.zeros((h // k, w // k), np.float32)
    for i in range(k):
        for j in range(k):
            out += grey[i:h:k, j:w:k]
    out *= 1.0 / (k * k)
    return out


class Clock:
    """Writes the milliseconds since the last call (or creation) under a stage's name."""

    def __init__(self, into: dict) -> None:
        self.into = into
        self.last = time.perf_counter()

    def __call__(self, stage: str) -> None:
        now = time.perf_counter()
        self.into[stage] = (now - self.last) * 1000.0
        self.last = now
