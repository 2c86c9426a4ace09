"""A board's printed lattice (a cutting mat's grid): found in the spectrum and taken out.

A cutting mat's grid is thin straight lines at one pitch in two perpendicular directions. Its
lines are as long and as straight as a wire laid straight, and as thin as a thin one, so the
contrast sees them as wires; what sets them apart is that they repeat. In the spectrum of the
picture's difference from the board (tapered to nothing at the frame's edges) a repeating
pattern is a row of sharp peaks, each PEAK times the spectrum round it or more, and a square
lattice puts each of its peaks beside a twin of the same length turned by 90 degrees. Wires,
their crossings, wood grain, speckles and printed patches make no such pairs (a grain repeats
one way only); JPEG's 8 x 8 blocks do, at frequencies known in advance, which are left out.
Where LATTICE_PAIRS peaks or more pair up, every peak of the spectrum is scaled down to the
spectrum round it, in every colour channel: the grid goes, and what does not repeat (the wires)
stays. On the randomized trays no board but the mats shows a lattice (1000-1399: 29 mats of 40,
none of the other 360 trays), nor any of the 475 public photographs (taken at 4 px/mm).
"""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

PEAK = 8.0  # a peak: this many times the spectrum's magnitude round it (the geometric mean, 9 x 9 bins)
LATTICE_PAIRS = 6  # peaks with a perpendicular twin needed before the picture is taken to show a lattice
LONGEST_MM = 30.0  # periods longer than this are the light's falloff and the board's mottle, not a lattice


def without_lattice(diff: np.ndarray, wppm: float, k: float = 1) -> tuple[np.ndarray, int]:
    """(diff with a square lattice taken out, how many of the lattice's peaks paired up; 0: no
    lattice, and diff itself).
    diff: (rows, cols, channels) difference from the board on the working grid, wppm its px/mm,
    k the input pixels per working pixel (where JPEG's blocks fall)."""
    from scipy import ndimage

    h, w, ch = diff.shape
    s = diff[:, :, 0].copy()
    for c in range(1, ch):
        s += diff[:, :, c]
    s -= s.mean()
    fy = np.fft.fftfreq(h).astype(np.float32)[:, None]  # cycles per working px
    fx = np.fft.rfftfreq(w).astype(np.float32)[None, :]
    short = np.hypot(fy, fx) * wppm > 1.0 / LONGEST_MM
    # tapered to nothing at the frame's edges, whose jump would put a streak of peaks on both axes
    mag = np.log(np.abs(np.fft.rfft2(s * _taper(h, w))) + 1e-9).astype(np.float32)
    iy, ix = _peaks(mag, short)
    if len(iy) < LATTICE_PAIRS:
        return diff, 0
    vy, vx = fy[iy, 0], fx[0, ix]
    tol = 1.5 / min(h, w)  # a bin and a half
    jpeg = _on_block_grid(vy, k, tol) & _on_block_grid(vx, k, tol)
    iy, ix, vy, vx = iy[~jpeg], ix[~jpeg], vy[~jpeg], vx[~jpeg]
    if len(iy) < LATTICE_PAIRS:
        return diff, 0
    # each peak's twin turned by 90 degrees, (-vx, vy) or its mirror (vx, -vy): a peak there too?
    vecs = np.column_stack([vy, vx])
    turned = np.column_stack([-vx, vy])
    d = np.minimum(np.abs(turned[:, None, :] - vecs[None, :, :]).max(axis=2),
                   np.abs(turned[:, None, :] + vecs[None, :, :]).max(axis=2))
    paired = (d <= tol).any(axis=1)
    if np.count_nonzero(paired) < LATTICE_PAIRS:
        return diff, 0
    # taken out: every peak of the untapered spectrum (the lattice's harmonics whose twins were
    # too faint to pair, JPEG's blocks), scaled down to the spectrum round it
    raw = np.log(np.abs(np.fft.rfft2(s)) + 1e-9).astype(np.float32)
    near = ndimage.uniform_filter(raw, 9, mode="wrap")
    notch = np.zeros(raw.shape, bool)
    notch[_peaks(raw, short, near)] = True
    notch = ndimage.binary_dilation(notch, np.ones((3, 3), bool)) & short
    gain = np.where(notch, np.minimum(np.exp(near - raw), 1.0), 1.0).astype(np.float32)
    out = np.empty_like(diff)
    for c in range(ch):
        out[:, :, c] = np.fft.irfft2(np.fft.rfft2(diff[:, :, c]) * gain, s=(h, w))
    return out, int(np.count_nonzero(paired))


def _peaks(mag: np.ndarray, short: np.ndarray, around: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(rows, cols) of the spectrum's peaks: PEAK times the spectrum round them (9 x 9 bins, mag
    being its log) or more, the most of their 3 x 3 bins, at periods up to LONGEST_MM (short)."""
    from scipy import ndimage

    if around is None:
        around = ndimage.uniform_filter(mag, 9, mode="wrap")
    iy, ix = np.nonzero((mag - around > math.log(PEAK)) & short)
    h, w = mag.shape
    top = mag[iy, ix]
    keep = np.ones(len(iy), bool)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            if dy or dx:  # the neighbour, the columns clipped (the half spectrum does not wrap there)
                keep &= top >= mag[(iy + dy) % h, np.clip(ix + dx, 0, w - 1)]
    return iy[keep], ix[keep]


@lru_cache(maxsize=8)
def _taper(h: int, w: int) -> np.ndarray:
    return (np.hanning(h)[:, None] * np.hanning(w)[None, :]).astype(np.float32)


def _on_block_grid(f: np.ndarray, k: float, tol: float) -> np.ndarray:
    """Which frequencies (cycles per working px) lie within tol of a harmonic of JPEG's 8-pixel
    blocks (k input pixels per working pixel)."""
    step = k / 8.0  # cycles per working px of the blocks' first harmonic
    r = np.mod(f, step)
    return np.minimum(r, step - r) <= tol
