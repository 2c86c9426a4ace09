"""A thin conductor past an insulation's end, followed in the input image's own pixels.

The working image is the input averaged to 2-3 px/mm, so a tinned or copper conductor 0.4-0.7 mm
across on a board of nearly its shade is blurred there into the board's noise: conductor() in
reader.py cannot follow it, and the end is taken at the insulation's cut, short of the wire's
end by the conductor's length. In the input's pixels (4-8 px/mm) such a conductor is a line two
or three pixels wide. This reads it there: along rays from the insulation's end, straight on and
turned a little, at offsets across it, the colour on the ray less the mean of the board on both
sides of it (FLANK_OUT beyond the wire's edges), averaged over WINDOW_MM along, in units of its
own noise (the spread of the two sides' difference along the ray), the lesser of the two sides
(what stands out of one side only is the edge of a patch of print): a z-score. A conductor is a
stretch that starts within DIP_MM of the end (the blur of the insulation's cut face may come
first), stands Z or more, runs for at least CONDUCTOR_MIN_MM and stops before TIP_MAX_MM with
board beyond it (its z under OFF on average over the next 2 mm); that stands REL or more of the
insulation's own z (an end's soft shadow or halo past a wire of strong contrast stands out of the
noise too, but a small share of the wire); and that is narrower than the wire (its flanks, FLANK
of the wire's width off its axis, under NARROW of its middle: a shadow or a blur is as broad as
the wire); that stands out of what the board does beside it (rays BESIDE_AT wire widths off to
either side show no such line: the grain of a wood); and past whose tip no line goes on, straight
or turned up to FAN_DEG (a printed line slanting through the end). Its tip is where its contrast,
projected on its own colour, first falls under half.
"""
from __future__ import annotations

import math

import numpy as np
from scipy import ndimage

from ..common import bridged
from .contrast import bilinear

Z = 4.0  # the conductor's z-score over its sides, averaged over WINDOW_MM along it
OFF = 2.5  # ... and past its tip, on average over the next 2 mm, under this
REL = 0.2  # ... at least this share of the insulation's own z (its last 0.5-2 mm)
DIP_MM = 1.0  # it starts within this of the insulation's end
GAP_MM = 0.75  # a gap this short in it is no tip (a grain, a strand, the pixel grid)
WINDOW_MM = 1.0
FLANK_OUT_MM = 0.3  # the board sampled this far beyond the wire's edges (1.5 px at least)
FLANK = 0.45  # narrower than the wire: its flanks this share of the wire's width off its axis
NARROW = 0.7  # ... stand out less than this share of its middle
SHIFT = 0.3  # rays up to this share of the wire's width to either side of its axis
TURN_DEG = (0.0, -4.0, -2.0, 2.0, 4.0)  # ... and turned this much (straight on first)
STEP = 0.5  # px along a ray
FAN_DEG = 25.0  # past a conductor's tip no line goes on, straight or turned up to this
BESIDE_AT = (3.0, 5.0)  # rays alongside the conductor, this many wire widths off, to either side,
ALONGSIDE = 0.5  # ... showing a line this strong (a share of the conductor's score): the board's grain
NOISE_FLOOR = 0.002  # the least noise (colours 0-1): half an 8-bit level, where an image has none


def follow(image: np.ndarray, end: np.ndarray, out: np.ndarray, width: float, ppm: float,
           least_mm: float, tip_max_mm: float) -> np.ndarray | None:
    """The tip (input px, (row, col)) of a thin conductor running on from the insulation's end
    `end` along the unit direction `out`, on an image (rows, cols, channels; colours 0-1) at ppm px/mm whose
    wire is `width` px across, or None. least_mm, tip_max_mm: how long it must and may be."""
    h, w = image.shape[:2]
    s = np.arange(-2.0 * ppm, (tip_max_mm + 3.0) * ppm, STEP)
    beside = 0.5 * width + max(1.5, FLANK_OUT_MM * ppm)
    nw = max(int(round(WINDOW_MM * ppm / STEP)), 1)
    noise_gain = math.sqrt(max(WINDOW_MM * ppm, 1.0))  # about one independent sample a pixel
    shifts = np.arange(-SHIFT * width, SHIFT * width + 0.01, 0.5)
    best = None
    for turn in np.radians(TURN_DEG):
        c, sn = math.cos(turn), math.sin(turn)
        o = np.array([c * out[0] - sn * out[1], sn * out[0] + c * out[1]])
        side = np.array([-o[1], o[0]])
        offs = np.concatenate([shifts, shifts - beside, shifts + beside])
        pts = (end + s[:, None] * o)[:, None, :] + offs[None, :, None] * side
        inside = ((pts >= 0).all(axis=2) & (pts[..., 0] <= h - 1) & (pts[..., 1] <= w - 1)).all(axis=1)
        n = len(s) if inside.all() else int(np.argmin(inside))
        near = (s[:n] >= 0.5 * ppm) & (s[:n] <= 2.5 * ppm)
        if not near.any():
            continue
        v = bilinear(image, pts[:n].reshape(-1, 2)).reshape(n, 3, len(shifts), -1)
        d = v[:, 0] - 0.5 * (v[:, 1] + v[:, 2])  # (steps, shifts, channels)
        e = v[:, 1] - v[:, 2]  # the two sides' difference: noise and the board's grain
        sigma = np.maximum(1.4826 * np.median(np.abs(e - np.median(e, axis=0)), axis=0), NOISE_FLOOR)
        # over each side alone (what lies on the ray must stand out of the board on both sides of
        # it, not of one: the edge of a patch of the board's print): the lesser
        z = _score(v, sigma, nw) * noise_gain
        j = int(np.argmax(z[near].mean(axis=0)))
        score = float(z[near, j].mean())
        if best is None or score > best[0]:
            best = (score, z[:, j], d[:, j], s[:n], o, side, shifts[j], sigma[j])
        if turn == 0.0 and score < 0.5 * Z:
            return None  # nothing there straight on
    if best is None:
        return None
    _, z, d, at, o, side, shift, sigma = best
    own = float(np.median(z[(at >= -2.0 * ppm) & (at <= -0.5 * ppm)]))
    z, d, at = z[at >= 0], d[at >= 0], at[at >= 0]
    on = bridged((z >= Z)[None, :], max(int(round(GAP_MM * ppm / STEP)), 1))[0]
    first = np.flatnonzero(on)
    if not first.size or at[first[0]] > DIP_MM * ppm:
        return None
    a = int(first[0])
    off = np.flatnonzero(~on[a:])
    if not off.size:
        return None  # on to the frame's edge or past the longest conductor
    b = a + int(off[0])  # one past the stretch
    if at[b - 1] < least_mm * ppm or at[b - 1] > tip_max_mm * ppm or float(np.median(z[a:b])) < REL * own:
        return None
    past = (at > at[b - 1] + 0.5 * ppm) & (at <= at[b - 1] + 2.5 * ppm)
    if not past.any() or float(z[past].mean()) >= OFF:
        return None  # it goes on: a line of the board's print, or another wire
    colour = np.median(d[a:b], axis=0)
    norm = max(float(colour @ colour), 1e-9)
    share = ndimage.uniform_filter1d((d @ colour) / norm, max(int(round(0.25 * ppm / STEP)), 1), mode="nearest")
    start = int(np.searchsorted(at, 0.5 * ppm))
    enter = np.flatnonzero(share[start:b] >= 0.5)
    if not enter.size or at[start + enter[0]] > (DIP_MM + 0.5) * ppm:
        return None
    start += int(enter[0])
    m = max(int(round(0.5 * ppm / STEP)), 1)  # (a dip shorter than 0.5 mm is no tip: a strand, the specular line)
    ahead = ndimage.maximum_filter1d(share, m, origin=-(m // 2), mode="nearest")  # the most over the next m steps
    below = np.flatnonzero(ahead[start:b + nw] < 0.5)
    last = start + int(below[0]) - 1 if below.size else min(b + nw, len(at)) - 1
    if at[last] < least_mm * ppm:
        return None
    run = slice(start, last + 1)
    flanks = np.array([shift - FLANK * width, shift + FLANK * width, shift - beside, shift + beside])
    pts = (end + at[run, None] * o)[:, None, :] + flanks[None, :, None] * side
    f = bilinear(image, pts.reshape(-1, 2)).reshape(last + 1 - start, 4, -1)
    flank = (0.5 * (f[:, 0] + f[:, 1]) - 0.5 * (f[:, 2] + f[:, 3])) @ colour / norm
    if float(np.median(flank)) > NARROW * float(np.median(share[run])):
        return None  # as broad as the wire: a shadow or the blur of its end
    # past its tip lies board, straight on or turned up to FAN_DEG (a printed line slanting
    # through the end runs on at a slant, off the ray)
    tip = end + at[last] * o + shift * side
    ahead = np.arange(1.0 * ppm, 3.0 * ppm, STEP)
    for fan in np.radians(np.arange(-FAN_DEG, FAN_DEG + 0.1, 5.0)):
        fc, fs = math.cos(fan), math.sin(fan)
        way = np.array([fc * o[0] - fs * o[1], fs * o[0] + fc * o[1]])
        across_way = np.array([-way[1], way[0]])
        pts = (tip + ahead[:, None] * way)[:, None, :] + np.array([0.0, -beside, beside])[None, :, None] * across_way
        if not ((pts >= 0).all() and (pts[..., 0] <= h - 1).all() and (pts[..., 1] <= w - 1).all()):
            continue
        vf = bilinear(image, pts.reshape(-1, 2)).reshape(len(ahead), 3, -1)
        zf = _score(vf, sigma, nw) * noise_gain
        if float(zf.mean()) >= Z:
            return None
    # it stands out of what the board does beside it: rays alongside, BESIDE_AT wire widths off to
    # either side (each searched across as this one was), show no such line (the grain of a wood)
    mine = float(np.median(z[a:last + 1]))
    for apart in BESIDE_AT:
        for sign in (-1.0, 1.0):
            centres = shift + sign * apart * width + shifts
            offs = np.concatenate([centres, centres - beside, centres + beside])
            pts = (end + at[a:last + 1, None] * o)[:, None, :] + offs[None, :, None] * side
            inside = (pts >= 0).all(axis=2) & (pts[..., 0] <= h - 1) & (pts[..., 1] <= w - 1)
            if not inside.all():
                continue
            v = bilinear(image, pts.reshape(-1, 2)).reshape(last + 1 - a, 3, len(shifts), -1)
            zb = _score(v, sigma, nw) * noise_gain
            if float(np.median(zb, axis=0).max()) >= ALONGSIDE * mine:
                return None
    return end + at[last] * o + shift * side


def _score(v: np.ndarray, sigma: np.ndarray, window: int) -> np.ndarray:
    """How far the ray's colours v[:, 0] stand out of each side's, v[:, 1] and v[:, 2] (steps
    first, channels last), averaged over `window` steps along it, in units of sigma (root mean
    square over the channels): the lesser of the two sides."""
    def one(side: int) -> np.ndarray:
        z = ndimage.uniform_filter1d(v[:, 0] - v[:, side], window, axis=0, mode="nearest") / sigma
        return np.sqrt((z * z).mean(axis=-1))

    return np.minimum(one(1), one(2))
