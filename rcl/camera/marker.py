"""Finding the calibration marker: a small bright or dark disc carried by the gripper.

This replaces the paper's step of putting a cursor on the marker by hand.
The disc is told from wires and noise by its shape (round, compact, not cut
by the image border) and located to a fraction of a pixel by the centroid of
its contrast against the local background, which is exact for the
anti-aliased edge pixels of a uniform disc.
"""
from __future__ import annotations

from typing import Optional

import numpy as np

from .images import as_grey

MIN_AREA = 5  # px: smaller blobs are noise
MAX_ELONGATION = 1.6  # ratio of a blob's principal axes: wires are far longer than wide
MIN_FILL = 0.6  # blob area over the area of the circle of its largest extent


def find_mark(image: np.ndarray, polarity: str = "auto") -> Optional[tuple[float, float]]:
    """(u, v): the centre of the marker disc in pixels (u = column, v = row), or None if none is seen.

    polarity: "bright" (a disc lighter than the background), "dark", or "auto" (either).
    """
    from scipy import ndimage  # here, not at import: `rcl run` starts faster

    g = as_grey(image)
    if g.shape[0] < 5 or g.shape[1] < 5:
        return None
    background = float(np.median(g))
    noise = max(1.4826 * float(np.median(np.abs(g - background))), 1e-4)
    signs = {"bright": (1.0,), "dark": (-1.0,), "auto": (1.0, -1.0)}[polarity]
    best = None
    for sign in signs:
        contrast = sign * (g - background)
        peak = float(contrast.max())
        if peak < 8 * noise:
            continue
        mask = contrast > max(0.5 * peak, 4 * noise)
        labels, count = ndimage.label(mask)
        for k, box in enumerate(ndimage.find_objects(labels), start=1):
            score = _disc_score(labels[box] == k, box, g.shape)
            if score is not None:
                strength = score * float(contrast[box][labels[box] == k].mean())
                if best is None or strength > best[0]:
                    best = (strength, sign, labels == k)
    if best is None:
        return None
    _, sign, blob = best
    return _centroid(g, sign, blob)


def _disc_score(blob: np.ndarray, box, shape) -> Optional[float]:
    """How disc-like a blob is (higher is better), or None if it is not a disc at all."""
    area = int(blob.sum())
    if area < MIN_AREA:
        return None
    if box[0].start == 0 or box[1].start == 0 or box[0].stop == shape[0] or box[1].stop == shape[1]:
        return None  # cut by the border: its centroid would be wrong
    rows, cols = np.nonzero(blob)
    cov = np.cov(np.stack([rows, cols])) if area > 1 else np.zeros((2, 2))
    evals = np.linalg.eigvalsh(cov)
    if evals[0] <= 0:
        return None
    elongation = float(np.sqrt(evals[1] / evals[0]))
    extent = max(blob.shape)
    fill = area / (np.pi / 4 * extent * extent)
    if elongation > MAX_ELONGATION or fill < MIN_FILL:
        return None
    return 1.0 / elongation * min(fill, 1.0)


def _centroid(g: np.ndarray, sign: float, blob: np.ndarray) -> tuple[float, float]:
    from scipy import ndimage

    inner = ndimage.binary_dilation(blob, iterations=2)
    ring = ndimage.binary_dilation(inner, iterations=3) & ~inner
    local = float(np.median(g[ring])) if ring.any() else float(np.median(g))
    weight = np.where(inner, np.clip(sign * (g - local), 0.0, None), 0.0)
    total = weight.sum()
    rows, cols = np.indices(g.shape)
    return float((weight * cols).sum() / total), float((weight * rows).sum() / total)
