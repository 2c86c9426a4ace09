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

Where many wires cross a faint grid, their own spectrum (broad, and streaked along the normal of
each straight wire) drowns the grid's peaks: about a third of the mats drawn. What is thinner
than a 3 x 3 block (the picture less its 3 x 3 mean, clipped to THIN_CLIP of its robust spread)
keeps most of a grid line's contrast but only a wire's edges, so the lattice is sought there
too, by the same test; where found there, it is taken out of each channel's thin part as above,
and what that takes out, divided by how much of each frequency the thin part keeps, is
subtracted from the channel. The grid's lowest harmonics, which the thin part keeps less than
THIN_KEEPS of, are left (a faint undulation, not a line). On 1,000 trays at seeds 264000-264999
the picture as it is finds the lattice on 73 of the 102 mats, the thin part on 18 more, and
neither on any of the 898 other boards.
"""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

PEAK = 8.0  # a peak: this many times the spectrum's magnitude round it (the geometric mean, 9 x 9 bins)
LATTICE_PAIRS = 6  # peaks with a perpendicular twin needed before the picture is taken to show a lattice
LONGEST_MM = 30.0  # periods longer than this are the light's falloff and the board's mottle, not a lattice
THIN_CLIP = 4.0  # the thin part of a picture (_thin) clipped to this many of its robust spreads
THIN_KEEPS = 0.25  # frequencies the thin part keeps less of than this are not taken out through it


def without_lattice(diff: np.ndarray, wppm: float, k: float = 1) -> tuple[np.ndarray, int]:
    """(diff with a square lattice taken out, how many of the lattice's peaks paired up; 0: no
    lattice, and diff itself).
    diff: (rows, cols, channels) difference from the board on the working grid, wppm its px/mm,
    k the input pixels per working pixel (where JPEG's blocks fall).

    Sought first in the picture as it is; where the wires' own spectrum drowns the grid's peaks
    (many wires, a faint grid: about a third of the mats drawn), again in what is thinner than
    a 3 x 3 block (_thin), where the grid's lines keep most of their contrast and the wires only
    their edges."""
    h, w, ch = diff.shape
    s = diff[:, :, 0].copy()
    for c in range(1, ch):
        s += diff[:, :, c]
    s -= s.mean()
    pairs = _pairs(s, wppm, k)
    if pairs:
        # taken out: every peak of the untapered spectrum (the lattice's harmonics whose twins were
        # too faint to pair, JPEG's blocks), scaled down to the spectrum round it
        gain = _notch(s, wppm)
        out = np.empty_like(diff)
        for c in range(ch):
            out[:, :, c] = np.fft.irfft2(np.fft.rfft2(diff[:, :, c]) * gain, s=(h, w))
        return out, pairs
    thin = _thin(s)
    pairs = _pairs(thin, wppm, k)
    if not pairs:
        return diff, 0
    # taken out of the thin part of each channel as above, what that takes out divided by how
    # much of each frequency the thin part keeps (THIN_KEEPS or more: the grid's lowest harmonics,
    # which hardly stand out of the board's mottle, are left)
    gain = _notch(thin, wppm)
    fy = np.fft.fftfreq(h)[:, None]
    fx = np.fft.rfftfreq(w)[None, :]
    keeps = 1.0 - (1.0 + 2.0 * np.cos(2 * np.pi * fy)) * (1.0 + 2.0 * np.cos(2 * np.pi * fx)) / 9.0
    taken = np.where(keeps >= THIN_KEEPS, (1.0 - gain) / np.maximum(keeps, THIN_KEEPS), 0.0).astype(np.float32)
    out = np.empty_like(diff)
    for c in range(ch):
        out[:, :, c] = diff[:, :, c] - np.fft.irfft2(np.fft.rfft2(_thin(diff[:, :, c])) * taken, s=(h, w))
    return out, pairs


def _pairs(s: np.ndarray, wppm: float, k: float) -> int:
    """How many of the spectrum's peaks (of s, the picture summed over channels) have a twin turned
    by 90 degrees: 0 where fewer than LATTICE_PAIRS."""
    h, w = s.shape
    fy, fx, short = _frequencies(h, w, wppm)
    # tapered to nothing at the frame's edges, whose jump would put a streak of peaks on both axes
    mag = np.log(np.abs(np.fft.rfft2(s * _taper(h, w))) + 1e-9).astype(np.float32)
    iy, ix = _peaks(mag, short)
    if len(iy) < LATTICE_PAIRS:
        return 0
    vy, vx = fy[iy, 0], fx[0, ix]
    tol = 1.5 / min(h, w)  # a bin and a half
    jpeg = _on_block_grid(vy, k, tol) & _on_block_grid(vx, k, tol)
    vy, vx = vy[~jpeg], vx[~jpeg]
    if len(vy) < LATTICE_PAIRS:
        return 0
    # each peak's twin turned by 90 degrees, (-vx, vy) or its mirror (vx, -vy): a peak there too?
    vecs = np.column_stack([vy, vx])
    turned = np.column_stack([-vx, vy])
    d = np.minimum(np.abs(turned[:, None, :] - vecs[None, :, :]).max(axis=2),
                   np.abs(turned[:, None, :] + vecs[None, :, :]).max(axis=2))
    paired = int(np.count_nonzero((d <= tol).any(axis=1)))
    return paired if paired >= LATTICE_PAIRS else 0


def _notch(s: np.ndarray, wppm: float) -> np.ndarray:
    """Per bin of s's (untapered) half spectrum, the gain that scales each of its peaks (and the bins
    round it) down to the spectrum round it: 1 elsewhere."""
    from scipy import ndimage

    h, w = s.shape
    short = _frequencies(h, w, wppm)[2]
    raw = np.log(np.abs(np.fft.rfft2(s)) + 1e-9).astype(np.float32)
    near = ndimage.uniform_filter(raw, 9, mode="wrap")
    notch = np.zeros(raw.shape, bool)
    notch[_peaks(raw, short, near)] = True
    notch = ndimage.binary_dilation(notch, np.ones((3, 3), bool)) & short
    return np.where(notch, np.minimum(np.exp(near - raw), 1.0), 1.0).astype(np.float32)


def _frequencies(h: int, w: int, wppm: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The half spectrum's frequencies of an h x w picture (cycles per working px: rows (h, 1),
    columns (1, w // 2 + 1)), and which bins lie at periods up to LONGEST_MM."""
    fy = np.fft.fftfreq(h).astype(np.float32)[:, None]
    fx = np.fft.rfftfreq(w).astype(np.float32)[None, :]
    return fy, fx, np.hypot(fy, fx) * wppm > 1.0 / LONGEST_MM


def _thin(a: np.ndarray) -> np.ndarray:
    """What of a (rows, cols) is thinner than a 3 x 3 block: a less its 3 x 3 mean, clipped to
    THIN_CLIP times its robust spread (a wire's edges and the board's specks have no more say
    than a grid's line)."""
    from scipy import ndimage

    t = a - ndimage.uniform_filter(a, 3, mode="nearest")
    spread = 1.4826 * float(np.median(np.abs(t[::2, ::2]))) + 1e-9
    return np.clip(t, -THIN_CLIP * spread, THIN_CLIP * spread)


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
