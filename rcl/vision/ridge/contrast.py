"""The ridge finder's contrast: the image on its working grid, and how far each pixel stands out
from the board round it, in units of the board's spread (shadows told apart)."""
from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ...camera.images import ImageError
from ..common import block_average
from .lattice import without_lattice

SHADOW_LIGHT = (0.55, 0.97)  # a shadow leaves this share of the board's light: darker is a thing, lighter is board
SHADOW_TINT = 2.0  # ... and adds no more other colour than this (spreads)
MIN_SPREAD = 0.012  # the least board spread believed (3 grey levels): JPEG and sensor noise at the least
BOARD_BLOCK_MM = 8.0  # blocks in which the board's colour is estimated


def working_image(image: np.ndarray, px_per_mm: float) -> tuple[np.ndarray, int]:
    """(the image block-averaged to 2-4 px/mm as float32 (rows, cols, channels), the block size)."""
    a = np.asarray(image)
    scale = 1.0 / 255.0 if a.dtype == np.uint8 else 1.0 / 65535.0 if a.dtype == np.uint16 else 1.0
    if a.ndim == 2:
        a = a[:, :, None]
    if a.ndim != 3 or a.shape[2] not in (1, 3, 4) or not np.issubdtype(a.dtype, np.number):
        raise ImageError(f"an image is rows x columns (x 3 colours) of numbers, not shape {np.shape(image)}")
    a = a[:, :, :3]
    k = max(1, int(px_per_mm // 2.0))
    h, w = a.shape[0] // k * k, a.shape[1] // k * k
    if h < 16 * k or w < 16 * k:
        raise ImageError(f"the image ({a.shape[1]} x {a.shape[0]} px) is too small to find wires in")
    out = block_average(a[:h, :w], k)
    if scale != 1.0:
        out *= np.float32(scale)
    if not np.isfinite(out).all():
        raise ImageError("the image holds values that are not finite numbers (NaN or infinity)")
    return out, k


@dataclass
class Contrast:
    """F, each pixel's distance in colour from the board there in units of the board's spread,
    with what it was made of: the working image, the board's colour under each pixel, and the
    factor (per channel) that turns a colour difference into F's units."""

    f: np.ndarray
    work: np.ndarray
    board: np.ndarray
    unit: np.ndarray


def contrast(work: np.ndarray, wppm: float, outside: np.ndarray | None = None, k: int = 1) -> Contrast:
    """The contrast F: the board's colour estimated per BOARD_BLOCK_MM block (the median, then the
    median of 3 x 3 blocks, so blocks full of wire are outvoted), subtracted, a printed lattice on
    the board (a cutting mat's grid) taken out of the difference (lattice.py; k: input pixels per
    working pixel), each channel divided by its own robust spread, then the root mean square over
    the channels. Pixels `outside` the tray (a rim, the bench round it) have no say in the board
    and no contrast."""
    from scipy import ndimage

    h, w, ch = work.shape
    b = max(round(BOARD_BLOCK_MM * wppm), 4)
    nby, nbx = max(h // b, 1), max(w // b, 1)
    bh, bw = h // nby, w // nbx
    sh, sw = len(range(0, nby * bh, 3)) // nby, len(range(0, nbx * bw, 3)) // nbx

    def blocked(a: np.ndarray) -> np.ndarray:
        """Every third pixel of each block: (nby, nbx, samples, channels)."""
        sub = a[:nby * bh:3, :nbx * bw:3][:nby * sh, :nbx * sw]
        return sub.reshape(nby, sh, nbx, sw, -1).transpose(0, 2, 1, 3, 4).reshape(nby, nbx, sh * sw, -1)

    blocks = blocked(work)
    if outside is not None and outside.any():
        off = blocked(outside[..., None])[..., 0]
        with warnings.catch_warnings():  # a block wholly off the tray has no median: NaN, filled below
            warnings.simplefilter("ignore", RuntimeWarning)
            board = np.nanmedian(np.where(off[..., None], np.nan, blocks), axis=2)
        empty = np.isnan(board[..., 0])
        if empty.all():
            board = np.median(blocks, axis=2)
        elif empty.any():  # a block wholly off the tray takes the nearest block's board
            idx = ndimage.distance_transform_edt(empty, return_distances=False, return_indices=True)
            board = board[idx[0], idx[1]]
    else:
        board = np.median(blocks, axis=2)
    if nby >= 3 and nbx >= 3:
        board = ndimage.median_filter(board, size=(3, 3, 1), mode="nearest")
    # bilinear enlargement by two small matrix products per channel
    ay = _interp_matrix(h, nby, bh)
    ax = _interp_matrix(w, nbx, bw)
    under = np.empty_like(work)
    for c in range(ch):
        under[:, :, c] = ay @ board[:, :, c] @ ax.T
    diff, _ = without_lattice(work - under, wppm, k)
    sample = diff[::4, ::4].reshape(-1, ch)
    if outside is not None and outside.any() and not outside.all():
        sample = sample[~outside[::4, ::4].ravel()]
    spread = np.maximum(1.4826 * np.median(np.abs(sample), axis=0), MIN_SPREAD)
    unit = (1.0 / (spread * np.sqrt(ch))).astype(np.float32)
    diff *= unit
    if ch == 1:
        f = np.abs(diff[:, :, 0])
    else:
        f = diff[:, :, 0] * diff[:, :, 0]
        for c in range(1, ch):
            f += diff[:, :, c] * diff[:, :, c]
        f = np.sqrt(f)
    if outside is not None:
        f[outside] = 0.0
    return Contrast(f, work, under, unit)


def shadow_free(con: Contrast, p: np.ndarray, b: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(F with what looks like the board in shadow counted as board, which points look so), given
    the image's colour p, the board's b and F at the same points.

    A shadow darkens the board and keeps its colour: a pixel that is SHADOW_LIGHT of the board's
    colour under it, give or take SHADOW_TINT (spreads) of other colour, is board in shadow; its
    contrast is then only that other colour. In a grey image every such darkening looks so."""
    light = (p * b).sum(axis=1) / np.maximum((b * b).sum(axis=1), 1e-9)
    tint = np.sqrt((((p - light[:, None] * b) * con.unit) ** 2).sum(axis=1))
    shade = (light >= SHADOW_LIGHT[0]) & (light <= SHADOW_LIGHT[1]) & (tint < SHADOW_TINT)
    return np.where(shade, tint, f), shade


def bilinear(layers: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """The values of a (rows, cols) or (rows, cols, layers) array at N (row, col) points,
    interpolated linearly: (N,) or (N, layers). Points outside take the nearest edge's values
    (as map_coordinates' mode nearest); one gather serves every layer."""
    return _mix(layers, *_corners(layers.shape[0], layers.shape[1], pts))


def _corners(h: int, w: int, pts: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For bilinear() on an h x w grid: each point's top-left neighbour (flat index) and its
    fractional offsets from it (rows, cols); computed once, they serve several arrays."""
    r = np.clip(pts[:, 0], 0.0, h - 1.0)
    c = np.clip(pts[:, 1], 0.0, w - 1.0)
    r0 = np.minimum(r.astype(np.intp), h - 2)
    c0 = np.minimum(c.astype(np.intp), w - 2)
    return r0 * w + c0, (r - r0).astype(np.float32), (c - c0).astype(np.float32)


def _mix(layers: np.ndarray, i: np.ndarray, fr: np.ndarray, fc: np.ndarray) -> np.ndarray:
    h, w = layers.shape[:2]
    flat = layers.reshape(h * w, -1) if layers.ndim == 3 else layers.reshape(-1)
    if layers.ndim == 3:
        fr, fc = fr[:, None], fc[:, None]
    top = flat[i] * (1 - fc) + flat[i + 1] * fc
    bottom = flat[i + w] * (1 - fc) + flat[i + w + 1] * fc
    return top * (1 - fr) + bottom * fr


def _interp_matrix(n: int, blocks: int, size: int) -> np.ndarray:
    """(n, blocks) weights that interpolate block centres linearly to n pixels (edges held)."""
    pos = (np.arange(n) + 0.5) / size - 0.5
    pos = np.clip(pos, 0, blocks - 1)
    lo = np.floor(pos).astype(int)
    hi = np.minimum(lo + 1, blocks - 1)
    t = (pos - lo).astype(np.float32)
    m = np.zeros((n, blocks), np.float32)
    m[np.arange(n), lo] += 1 - t
    m[np.arange(n), hi] += t
    return m


