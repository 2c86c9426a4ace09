"""Finding the calibration marker: a small disc, lighter or darker than what is round it.

This replaces the paper's step of putting a cursor on the marker by hand. The
marker is a disc: plain on a plain board, or, to be seen on any board and over
wires, a light disc on a dark pad about twice its size (the simulated cell's).
What is round the disc need not be the image's background, so it is found by
its contrast with its own surround:

1. candidates: the peaks of a centre-surround response (the mean of a box less
   the mean of the ring of a box about twice as wide), at every scale from 1.5 px
   to a fifth of the image, for each polarity;
2. each candidate is cut out at the level half-way between its centre and its
   surround; what is cut must be round, compact and whole (not running on out
   of its neighbourhood as a wire does, not cut by the image border);
3. the strongest disc is located to a fraction of a pixel by the centroid of its
   contrast against its immediate surround, which is exact for the anti-aliased
   edge pixels of a uniform disc.
"""
from __future__ import annotations

import math

import numpy as np

from .images import as_grey

MIN_AREA = 5  # px: smaller blobs are noise
MAX_ELONGATION = 1.6  # ratio of a blob's principal axes: wires are far longer than wide
MIN_FILL = 0.6  # blob area over the area of the circle of its largest extent
MIN_CONTRAST = 8.0  # a disc stands out from its surround by this many times the pixel noise
CENTRE = (3, 5)  # px: the centre boxes searched at each halving of the image (radii 1.5, 2.5 px there)
SURROUND = (7, 11)  # px: the box each is set against, a ring about twice as wide as the centre
PEAKS = 8  # the strongest peaks taken at each scale
CANDIDATES = 24  # of those, the strongest tried per polarity (a light wire's ends and bends may outdo the marker)


def find_mark(image: np.ndarray, polarity: str = "auto") -> tuple[float, float] | None:
    """(u, v): the centre of the marker disc in pixels (u = column, v = row), or None if none is seen.

    polarity: "bright" (a disc lighter than its surround), "dark", or "auto" (either).
    """
    g = np.asarray(as_grey(image), float)
    if g.shape[0] < 5 or g.shape[1] < 5:
        return None
    noise = _pixel_noise(g)
    best = None
    for sign in {"bright": (1.0,), "dark": (-1.0,), "auto": (1.0, -1.0)}[polarity]:
        for row, col, r in _candidates(g, sign):
            found = _disc_at(g, sign, row, col, r, noise)
            if found is not None and (best is None or found[0] > best[0]):
                best = found
    return None if best is None else best[1]


def _pixel_noise(g: np.ndarray) -> float:
    """The pixel noise (1 sigma), from the differences of neighbours: robust to edges and texture."""
    d = np.diff(g, axis=1).ravel()
    return max(1.4826 * float(np.median(np.abs(d - np.median(d)))) / math.sqrt(2.0), 1e-4)


def _candidates(g: np.ndarray, sign: float) -> list[tuple[int, int, float]]:
    """(row, col, radius px) of the strongest centre-surround peaks of one polarity over all
    scales: boxes of 3 and 5 px against the ring out to 7 and 11 px, on the image and on each
    halving of it (block means), so every scale costs the same few filters of a small image."""
    from scipy import ndimage  # here, not at import: `rcl run` starts faster

    level, factor = g.astype(np.float32), 1
    found: list[tuple[float, int, int, float]] = []
    while min(level.shape) >= 3 * SURROUND[-1]:
        means = {k: ndimage.uniform_filter(level, k, mode="nearest") for k in CENTRE + SURROUND}
        for c, s in zip(CENTRE, SURROUND):
            a, b = c * c, s * s
            resp = sign * (means[c] - (means[s] * b - means[c] * a) / (b - a))
            for value, row, col in _peaks(resp, c):
                found.append((value, row * factor + (factor - 1) // 2, col * factor + (factor - 1) // 2,
                              c / 2.0 * factor))
        h, w = level.shape[0] // 2 * 2, level.shape[1] // 2 * 2
        level = level[:h, :w].reshape(h // 2, 2, w // 2, 2).mean(axis=(1, 3))
        factor *= 2
    found.sort(reverse=True)
    return [(row, col, r) for _, row, col, r in found[:CANDIDATES]]


def _peaks(resp: np.ndarray, size: int) -> list[tuple[float, int, int]]:
    """The strongest positive local maxima of resp, each suppressing its neighbourhood."""
    resp = resp.copy()
    found = []
    for _ in range(PEAKS):
        row, col = divmod(int(np.argmax(resp)), resp.shape[1])
        value = float(resp[row, col])
        if value <= 0:
            break
        found.append((value, row, col))
        resp[max(row - 2 * size, 0):row + 2 * size + 1, max(col - 2 * size, 0):col + 2 * size + 1] = 0.0
    return found


def _disc_at(g: np.ndarray, sign: float, row: int, col: int, r: float,
             noise: float) -> tuple[float, tuple[float, float]] | None:
    """(strength, (u, v)) of the disc whose centre-surround peak is near (row, col), or None if
    what is there is not a disc."""
    from scipy import ndimage

    w = int(3 * r) + 8
    r0, r1, c0, c1 = max(row - w, 0), min(row + w + 1, g.shape[0]), max(col - w, 0), min(col + w + 1, g.shape[1])
    win = g[r0:r1, c0:c1]
    yy, xx = np.ogrid[r0 - row:r1 - row, c0 - col:c1 - col]
    d = np.hypot(yy, xx)
    core = d <= max(0.5 * r, 1.0)
    centre = float(np.median(win[core]))
    around = (d >= 1.6 * r) & (d <= 2.2 * r + 1)
    if not around.any():
        return None
    surround = float(np.median(win[around]))
    contrast = sign * (centre - surround)
    if contrast < MIN_CONTRAST * noise:
        return None
    labels, _ = ndimage.label(sign * (win - 0.5 * (centre + surround)) > 0)
    inside = labels[core]
    inside = inside[inside > 0]
    if inside.size == 0:
        return None
    blob = labels == np.bincount(inside).argmax()
    if blob[0].any() or blob[-1].any() or blob[:, 0].any() or blob[:, -1].any():
        return None  # runs on out of its neighbourhood (a wire), or is cut by the image's border
    score = _disc_score(blob)
    if score is None:
        return None
    u, v = _centroid(win, sign, blob)
    return score * contrast, (u + c0, v + r0)


def _disc_score(blob: np.ndarray) -> float | None:
    """How disc-like a blob is (higher is better), or None if it is not a disc at all."""
    area = int(blob.sum())
    if area < MIN_AREA:
        return None
    rows, cols = np.nonzero(blob)
    evals = np.linalg.eigvalsh(np.cov(np.stack([rows, cols])))
    if evals[0] <= 0:
        return None
    elongation = float(np.sqrt(evals[1] / evals[0]))
    extent = max(int(np.ptp(rows)), int(np.ptp(cols))) + 1
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
