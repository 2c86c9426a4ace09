"""Pieces both wire finders use."""
from __future__ import annotations

import math
import time

import numpy as np

FRAME_MARGIN_MM = 3.0  # an end, or the wire near it, this close to the frame's edge may be cut by it


GRASP_MM = 15.0  # the grasp point's distance from the wire's end, along the wire (every finder, the ground truth)
FINGER_CLEARANCE_MM = 4.0  # room the fingers need round the grasp point


def block_centre(x, k: int):
    """An averaged pixel's centre (a column or a row of block_average(., k), or an array of
    them) in the input image's pixel coordinates."""
    return (x + 0.5) * k - 0.5


def to_input(rc, k: int) -> np.ndarray:
    """Averaged-image (row, col) points, one pair or (N, 2), as input (u, v) pixel coordinates."""
    return block_centre(np.asarray(rc, float)[..., ::-1], k)


def median(a: np.ndarray):
    """The median of a 1-d array, as np.median gives it (the mean of the middle two of an even
    count), without its overhead on the short arrays the finders take many medians of. An empty
    array, or one holding NaN, is np.median's."""
    a = np.asarray(a)
    n = a.size
    if n == 0:
        return np.median(a)
    if not np.issubdtype(a.dtype, np.inexact):
        a = a.astype(float)
    k = n // 2
    if n % 2:
        p = np.partition(a, (k, -1))  # (the last, the largest: NaN sorts there)
        m = p[k]
    else:
        p = np.partition(a, (k - 1, k, -1))
        m = (p[k - 1] + p[k]) / 2
    return np.median(a) if np.isnan(p[-1]) else m


def block_average(grey: np.ndarray, k: int) -> np.ndarray:
    """The mean of each k x k block (float32); a partial block at an edge is dropped. A colour
    image (rows, cols, channels) is averaged channel by channel."""
    if k == 1:
        return grey.astype(np.float32)
    h, w = grey.shape[0] // k * k, grey.shape[1] // k * k
    out = np.zeros((h // k, w // k, *grey.shape[2:]), np.float32)
    for i in range(k):
        for j in range(k):
            out += grey[i:h:k, j:w:k]
    out *= 1.0 / (k * k)
    return out


def two_thirds_average(image: np.ndarray) -> np.ndarray:
    """The image averaged over squares 1.5 px wide (float32): each 3 x 3 block of pixels becomes
    2 x 2, each of those the mean of the 1.5 x 1.5 px square it covers (the middle row and column
    of the block shared half and half). A partial block at an edge is dropped; a colour image
    (rows, cols, channels) is averaged channel by channel."""
    h, w = image.shape[0] // 3 * 3, image.shape[1] // 3 * 3
    out = np.asarray(image[:h, :w], np.float32)
    for axis in (0, 1):
        x = np.moveaxis(out, axis, 0)
        a, b, c = x[0::3], x[1::3] * np.float32(0.5), x[2::3]
        y = np.empty((2 * len(a), *x.shape[1:]), np.float32)
        np.divide(a + b, np.float32(1.5), out=y[0::2])
        np.divide(b + c, np.float32(1.5), out=y[1::2])
        out = np.moveaxis(y, 0, axis)
    return np.ascontiguousarray(out)


def tray_level(image: np.ndarray, step: int) -> tuple[float, float]:
    """(the tray's grey level, the noise's sigma): the median and the scaled median absolute
    deviation of a 1-in-step-squared subsample (most of a tray is bare tray)."""
    sample = image[::step, ::step]
    tray = float(np.median(sample))
    return tray, 1.4826 * float(np.median(np.abs(sample - tray)))


def principal_direction(pts: np.ndarray) -> np.ndarray:
    """The unit direction along which points spread most (either sign)."""
    return np.linalg.svd(pts - pts.mean(axis=0), full_matrices=False)[2][0]


def conductor_tip(image: np.ndarray, end: np.ndarray, out: np.ndarray, width: float, ppm: float,
                  bright: float):
    """The tip of a thinner, brighter conductor (a stripped end or a ferrule) running on
    beyond a dark wire's end: (row, col) in image pixels, None if there is none, False if
    the bright region there is more than a conductor (wider than 0.6 of the insulation).

    The conductor is the region brighter than `bright` touching the end face; it may
    bend away from the insulation's axis, so its tip is its point farthest from the end.
    end and out (unit, pointing out of the wire) are (row, col); width and the search
    reach (10 mm) are in image pixels at ppm px/mm.
    """
    from scipy import ndimage

    h, w = image.shape
    rad = int(math.ceil(10.0 * ppm))
    r0, r1 = max(int(end[0]) - rad, 0), min(int(end[0]) + rad + 1, h)
    c0, c1 = max(int(end[1]) - rad, 0), min(int(end[1]) + rad + 1, w)
    if r1 - r0 < 3 or c1 - c0 < 3:
        return None
    labels, _ = ndimage.label(image[r0:r1, c0:c1] > bright, np.ones((3, 3)))
    side = np.array([-out[1], out[0]])
    along = np.arange(0.5, 2.5 * ppm + 0.5, 0.5)
    lateral = np.linspace(-0.4 * width, 0.4 * width, 5)  # a conductor may bend off the axis
    seeds = end + along[:, None, None] * out + lateral[None, :, None] * side
    sr = np.round(seeds[..., 0]).astype(int).ravel() - r0
    sc = np.round(seeds[..., 1]).astype(int).ravel() - c0
    ok = (sr >= 0) & (sr < r1 - r0) & (sc >= 0) & (sc < c1 - c0)
    ids = set(np.unique(labels[sr[ok], sc[ok]]).tolist())
    ids.discard(0)
    if not ids:
        return None
    rr, cc = np.nonzero(np.isin(labels, list(ids)))
    if rr.size < 1.5 * ppm * ppm:
        return None  # a speck of noise
    pts = np.column_stack([rr + r0, cc + c0]).astype(float)
    pts = pts[(pts - end) @ out > 0]
    if not pts.size:
        return None
    dist = np.linalg.norm(pts - end, axis=1)
    far = pts[dist >= dist.max() - 1.0].mean(axis=0)
    if not np.linalg.norm(far - end) < 10.0 * ppm:
        return None
    axis = (far - end) / max(float(np.linalg.norm(far - end)), 1e-9)
    across = np.abs((pts - end) @ np.array([-axis[1], axis[0]]))
    if across.max() > 0.6 * width + 1.0:
        return False
    return far + axis * 0.5


class Clock:
    """Writes the milliseconds since the last call (or creation) under a stage's name."""

    def __init__(self, into: dict) -> None:
        self.into = into
        self.last = time.perf_counter()

    def __call__(self, stage: str) -> None:
        now = time.perf_counter()
        self.into[stage] = (now - self.last) * 1000.0
        self.last = now


def bridged(rows: np.ndarray, gap: int) -> np.ndarray:
    """Each row with its runs of False no longer than gap, between two Trues, made True: a
    binary closing along the rows (away from their ends)."""
    at = np.arange(rows.shape[1])
    before = np.maximum.accumulate(np.where(rows, at, -1), axis=1)
    after = np.minimum.accumulate(np.where(rows, at, rows.shape[1])[:, ::-1], axis=1)[:, ::-1]
    return rows | ((before >= 0) & (after < rows.shape[1]) & (after - before - 1 <= gap))
