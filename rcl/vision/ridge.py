"""The default wire finder: wire centre lines as ridges; every end classified; unsure means no.

The paper's systems threshold grey levels or follow grey-level edges, so they
need wires of one polarity on a plain board. This finder asks of every pixel
how far its colour is from the board's, so a red wire on a green mat, a white
wire beside a black one and a copper tip all stand out alike; it finds centre
lines as ridges of that contrast at the scales wires have, and it takes an end
only when what lies around it can be seen to be bare board.

1. The working image: k x k block averaging to 2-4 px/mm, colour kept; a tray's rim
   (or the bench round the tray) along a side of the frame found (find_rim): what
   lies beyond it is off the tray.
2. Contrast: the board's colour is estimated per BOARD_BLOCK_MM block (the median,
   then the median of each 3 x 3 blocks, so blocks full of wire are outvoted) and
   subtracted; each channel is divided by its own robust spread (noise and board
   texture); the contrast F is the root mean square over the channels.
3. Ridges: F smoothed at scales matched to wire diameters 0.8-3 mm; the Hessian's
   most negative eigenvalue, scale-normalised, is the ridge strength; each pixel
   keeps its best scale; non-maximum suppression across the ridge and hysteresis
   leave the centre lines, thinned to one pixel.
4. The wire graph: ends (one neighbour) and crossings (three or more); spurs shorter
   than SPUR_MM are pruned; a trace jumps a break of up to GAP_MM to another line
   end facing it; only ends on lines long enough to hold SPAN_MM are read.
5. Each end: traced inward for SPAN_MM (a crossing on the way: it touches another
   wire); the wire's width measured across it; the tip followed outward along the
   contrast past the ridge's end (a rounded cap, a ferrule, stripped copper) to
   where the board begins; an end at the frame border, or whose contrast runs on
   (under another wire), is refused.
6. Free: the board must show beside the whole span, beyond the tip, and in a
   CLEARANCE_MM disc round the grasp point (room for the fingers).
7. The sighting: the tip; the direction into the wire at the tip, the chord of the
   centre line's TIP_FIT_MM nearest it (the tip put on that axis); the
   grasp point GRASP_MM along the centre line, centred across the wire; the tangent
   there. Of the first ENOUGH free ends, the one with the most room round it comes first:
   the least contrast, relative to the board's threshold, in bands 1-3 mm out beside
   its span, beyond its tip and round the grasp point (a nearby wire the free test
   just missed makes an end a worse bet).
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from ..camera.images import ImageError
from .common import FRAME_MARGIN_MM, GRASP_MM, Clock, block_average, principal_direction
from .sighting import Sighting

SPAN_MM = 20.0  # wire that must be free from the tip: the grasp point and 5 mm beyond
CLEARANCE_MM = 4.6  # free board round the grasp point, from the centre line: the fingers' room
SIDE_FREE_MM = 0.9  # free board beside the wire's edges along the span and beyond its tip
SPAN_SLACK_MM = 2.0  # ... along the span and this much more: a wire crossing just past it touches it (tip and arc errors)
SATURATION = 12.0  # contrast (spreads) beyond which a wire is simply there: highlights count no more
SHADOW_LIGHT = (0.55, 0.97)  # a shadow leaves this share of the board's light: darker is a thing, lighter is board
SHADOW_TINT = 2.0  # ... and adds no more other colour than this (spreads)
SHADOW_LIKE_WIRE = 0.2  # a wire this much of whose centre line looks like shadow: shadows are not told from it
SHADOW_SIDE = 0.3  # ... and one that casts one: so much of the board along one side of it looks like shadow
MIN_SPREAD = 0.012  # the least board spread believed (3 grey levels): JPEG and sensor noise at the least
BOARD_BLOCK_MM = 8.0  # blocks in which the board's colour is estimated
SCALES_MM = (0.35, 0.7, 1.2)  # Gaussian sigmas matched to wire diameters ~0.8, 1.6 and 3 mm
MIN_SIGMA_PX = 0.8  # below this a Gaussian on the working grid is no longer one
RIDGE_HIGH = 2.0  # hysteresis on the ridge strength, in units of the contrast's spread
RIDGE_LOW = 0.9
MIN_LINE_MM = 10.0  # shorter centre-line pieces are noise, texture or too short to take
SPUR_MM = 3.0  # branches this short that end at a crossing are whiskers
GAP_MM = 2.5  # a break in a centre line this long, straight ahead, is bridged
GAP_CONE_DEG = 30.0
TIP_MAX_MM = 12.0  # the longest ferrule or stripped conductor followed past the insulation
CONDUCTOR_RIDGE = 1.5  # the finest scale's ridge strength that marks a thin conductor
CONDUCTOR_CONTRAST = 1.2  # a faint conductor: its axis this far (spreads) above the board beside it
CONDUCTOR_MIN_MM = 2.5  # ... at least this long (a shorter one is the blur or the shadow of the end)
CONDUCTOR_WINDOW_MM = 1.0  # ... on average over this much of its length
CONDUCTOR_NARROW = 0.7  # ... and narrower than the wire: 0.45 of its width off the axis, less than this share of it
TIP_START_MM = 10.0  # the search for the tip starts this far in along the centre line: on the insulation
END_FIT_MM = 8.0  # the ridge's direction at its end, to search for the tip along: over this much of it
TIP_FIT_MM = (1.0, 5.0)  # the end's direction: the chord of the centre line this far from the tip (its first
# mm may hook; a longer chord leans with a wire curving near its end, and a parabola's slope at the tip, tried
# too, is the noisiest of the three)
BRIDGE_MM = 0.6  # across a wire, a break in its contrast narrower than this is no edge (a specular line)
TANGENT_MM = 2.5  # the tangent at the grasp point: over this much either side
BOARD_FLOOR = 4.0  # contrast (spreads) below which a pixel may be bare board, whatever the wire
TIP_SHARE = 0.5  # the tip: where the contrast falls below half the wire's (a blurred edge's middle; a shadow is fainter)
BOARD_SHARE = 0.3  # ... and below this share of the wire's own contrast
FADE_SHARE = 0.12  # straight past a tip, this share of the wire's contrast still means wire
FADE_FLOOR = 2.5  # ... and so does this much (spreads): bare board beyond an end is darker than that
RUN_MM = 0.6  # beside the span: contrast this long along the wire is something there
CAP_HITS = 3  # beyond the tip and round the grasp point: so many samples with contrast are something
DISC_HITS = 4
ROOM_BAND_MM = (1.0, 2.0, 3.0)  # the room round a free end: bands this far out from the wire's edges along the span
ROOM_CAP_MM = (1.5, 3.0)  # ... arcs this far beyond its tip
ROOM_PERCENTILE = 95.0  # ... each band and the disc round the grasp point judged by its nearly-highest contrast
RIM_SCAN_MM = 25.0  # a tray's rim (or the bench round the tray) is looked for this far in from each side
RIM_MIN_MM = 1.5  # ... at least this wide
RIM_SEGMENT_MM = 8.0  # ... in segments of the side this long: each its own profile (a median across it)
RIM_BOARD_MM = 3.0  # ... against this much board next to it
RIM_STEP = 0.03  # ... differing from the board by this much (0-1 colour)
RIM_BOARD_LOW, RIM_BOARD_HIGH = 20, 80  # ... whose spread is judged between these percentiles
RIM_CLEAR = 4.0  # ... this many times more than the band or the board varies
RIM_SHARE = 0.6  # ... along this share of the side's segments
RIM_BEND_PX = 1.5  # ... on one smooth curve (a lens bows a straight rim) to within this
RIM_EDGE_MM = 1.0  # the blur of a rim's edge: samples this near it say nothing of what lies round an end
MIDDLE_AWAY_MM = 8.0  # a middle grasp: this far from every crossing of the centre lines
MIDDLE_END_MM = 15.0  # ... and this far (straight) from every end of them: held by its middle (along a loop, 20 mm or more)
MIDDLE_THROUGH = 0.8  # ... its line runs on this share of the way out of the disc round it, both ways
MIDDLE_BOW = 0.5  # ... bowing from its tangent there by no more than this share of that
MIDDLE_STEP_MM = 3.0  # ... tried at points this far apart
MIDDLE_MAX = 60  # ... at most this many
LOOP_END_MM, LOOP_BOW = 8.0, 0.8  # where there is no such place: as near ends, bowing as much (a small loop with short tails)
ENOUGH = 4  # free ends to find before the search stops (0: all); the roomiest is taken

_COS_CONE = math.cos(math.radians(GAP_CONE_DEG))
# 8-neighbour offsets (row, col), clockwise from E
NEIGHBOURS = ((0, 1), (1, 1), (1, 0), (1, -1), (0, -1), (-1, -1), (-1, 0), (-1, 1))


@dataclass
class RidgeResult:
    """What the ridge finder saw: candidates best-first, stage times, its centre lines and refusals."""

    candidates: list = field(default_factory=list)
    timings: dict = field(default_factory=dict)
    skeleton: np.ndarray | None = None  # the centre lines on the working grid
    scale: int = 1  # input pixels per working pixel
    rejected: list = field(default_factory=list)  # ((u, v) input px, why) for each refused end


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


def contrast(work: np.ndarray, wppm: float, outside: np.ndarray | None = None) -> Contrast:
    """The contrast F: the board's colour estimated per BOARD_BLOCK_MM block (the median, then the
    median of 3 x 3 blocks, so blocks full of wire are outvoted), subtracted, each channel divided
    by its own robust spread, then the root mean square over the channels. Pixels `outside` the
    tray (a rim, the bench round it) have no say in the board and no contrast."""
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
    diff = work - under
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


def ridges(f: np.ndarray, wppm: float) -> tuple[np.ndarray, list, np.ndarray, np.ndarray]:
    """(strength, smoothed, scale, fine): the best scale's ridge strength of F at each pixel
    (-sigma^2 times the Hessian's most negative eigenvalue), F smoothed at each scale, the index
    of the best scale per pixel, and the finest scale's strength (thin conductors)."""
    from scipy import ndimage

    best = np.zeros_like(f)
    which = np.zeros(f.shape, np.uint8)
    grr = np.zeros_like(f)
    gcc = np.zeros_like(f)
    grc = np.zeros_like(f)
    fine = best
    smoothed = []
    for n, sigma in enumerate(_sigmas(wppm)):
        g = ndimage.gaussian_filter(f, sigma, mode="nearest", truncate=3.0)
        smoothed.append(g)
        np.subtract(g[2:], g[1:-1], out=grr[1:-1])
        grr[1:-1] -= g[1:-1]
        grr[1:-1] += g[:-2]
        np.subtract(g[:, 2:], g[:, 1:-1], out=gcc[:, 1:-1])
        gcc[:, 1:-1] -= g[:, 1:-1]
        gcc[:, 1:-1] += g[:, :-2]
        np.subtract(g[2:, 2:], g[2:, :-2], out=grc[1:-1, 1:-1])
        grc[1:-1, 1:-1] -= g[:-2, 2:]
        grc[1:-1, 1:-1] += g[:-2, :-2]
        half = grr - gcc
        half *= 0.5
        half *= half
        q = grc * grc
        q *= 0.0625  # grc was 4x the cross derivative
        half += q
        strength = np.sqrt(half)
        strength -= (grr + gcc) * 0.5
        strength *= sigma * sigma
        if n == 0:
            fine = strength
            best = strength.copy()
        else:
            better = strength > best
            np.maximum(best, strength, out=best)
            which[better] = n
    return best, smoothed, which, fine


def _sigmas(wppm: float) -> list[float]:
    return sorted({max(round(s * wppm, 1), MIN_SIGMA_PX) for s in SCALES_MM})


def normals(smoothed: list, which: np.ndarray, rows: np.ndarray, cols: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The unit normal (row, col) across the ridge at the given pixels, at each one's best scale."""
    h, w = which.shape
    r = rows.clip(1, h - 2)
    c = cols.clip(1, w - 2)
    grr = np.empty(len(r), np.float32)
    gcc = np.empty(len(r), np.float32)
    grc = np.empty(len(r), np.float32)
    sel = which[rows, cols]
    for n, g in enumerate(smoothed):
        m = sel == n
        if not m.any():
            continue
        rr, cc = r[m], c[m]
        mid = g[rr, cc]
        grr[m] = g[rr + 1, cc] - 2 * mid + g[rr - 1, cc]
        gcc[m] = g[rr, cc + 1] - 2 * mid + g[rr, cc - 1]
        grc[m] = (g[rr + 1, cc + 1] - g[rr + 1, cc - 1] - g[rr - 1, cc + 1] + g[rr - 1, cc - 1]) * 0.25
    low = (grr + gcc) * 0.5 - np.sqrt(((grr - gcc) * 0.5) ** 2 + grc * grc)
    ar, ac = low - gcc, grc
    br, bc = grc, low - grr
    use_a = ar * ar + ac * ac >= br * br + bc * bc
    vr = np.where(use_a, ar, br)
    vc = np.where(use_a, ac, bc)
    norm = np.maximum(np.sqrt(vr * vr + vc * vc), 1e-12)
    return vr / norm, vc / norm


def centre_lines(strength: np.ndarray, smoothed: list, which: np.ndarray, wppm: float) -> np.ndarray:
    """The ridges' centre lines: non-maximum suppression across each ridge, hysteresis, thinning."""
    from scipy import ndimage

    h, w = strength.shape
    W = w + 2
    pad = np.zeros((h + 2, W), np.float32)
    pad[1:-1, 1:-1] = strength
    flat = pad.ravel()
    cand = np.flatnonzero(flat > RIDGE_LOW)
    rows, cols = np.divmod(cand, W)
    ok = (rows >= 1) & (rows <= h) & (cols >= 1) & (cols <= w)
    cand, rows, cols = cand[ok], rows[ok] - 1, cols[ok] - 1
    # the neighbour across the ridge, the normal rounded to one of the 8 directions
    nr, nc = normals(smoothed, which, rows, cols)
    step = np.rint(nr * 1.2).clip(-1, 1).astype(np.int64) * W + np.rint(nc * 1.2).clip(-1, 1).astype(np.int64)
    v = flat[cand]
    keep = (v >= flat[cand + step]) & (v > flat[cand - step])
    peak = np.zeros(h * w, bool)
    peak[rows[keep] * w + cols[keep]] = True
    peak = peak.reshape(h, w)
    labels, n = ndimage.label(peak, np.ones((3, 3)))
    if n == 0:
        return peak
    strong = np.zeros(n + 1, bool)
    strong[np.unique(labels[peak & (strength > RIDGE_HIGH)])] = True
    size = np.bincount(labels.ravel(), minlength=n + 1)
    strong &= size >= MIN_LINE_MM * wppm * 0.7
    strong[0] = False
    lines = strong[labels]
    # a ridge's end may fork round a pixel (a rounded cap): fill such one-pixel holes, or thinning
    # keeps them as a tiny loop and the end is lost
    hole = ~lines[1:-1, 1:-1] & lines[:-2, 1:-1] & lines[2:, 1:-1] & lines[1:-1, :-2] & lines[1:-1, 2:]
    lines[1:-1, 1:-1] |= hole
    return minimal(thin_sparse(lines))


def minimal(mask: np.ndarray) -> np.ndarray:
    """The thinned lines with their corners cut: a pixel whose two 4-neighbours at a right angle
    are joined diagonally anyway, and that has nothing on the far side, is dropped. Thinning may
    leave such a pixel as a little triangle where lines meet or a ridge end forks, and that reads
    as a crossing."""
    h, w = mask.shape
    grid = np.pad(mask, 1).ravel()
    _cut_corners(grid, w + 2)
    return grid.reshape(h + 2, w + 2)[1:-1, 1:-1].copy()


def _cut_corners(grid: np.ndarray, W: int) -> None:
    """minimal() in place on a flattened grid W wide with an empty one-pixel frame."""
    n, e, s, west = -W, 1, W, -1
    for a, b in ((n, e), (e, s), (s, west), (west, n)):
        on = np.flatnonzero(grid)
        far = -(a + b)  # the diagonal opposite the corner
        cut = grid[on + a] & grid[on + b] & ~grid[on + far] & ~grid[on - a] & ~grid[on - b]
        grid[on[cut]] = False


def thin_sparse(mask: np.ndarray) -> np.ndarray:
    """The binary system's thinning (its passes and tables) computed on the set pixels only:
    masks of thin lines cost what their pixels do, not what the image does."""
    from .binary import NEIGHBOURS as PAPER_NEIGHBOURS
    from .binary import deletion_tables

    tables = deletion_tables()
    h, w = mask.shape
    W = w + 2
    grid = np.zeros((h + 2) * W, bool)
    grid.reshape(h + 2, W)[1:-1, 1:-1] = mask
    offsets = np.array([dr * W + dc for dr, dc in PAPER_NEIGHBOURS])
    on = np.flatnonzero(grid)
    quiet = 0
    p = 0
    while quiet < 4 and p < 400:
        codes = np.zeros(len(on), np.uint8)
        for k, o in enumerate(offsets):
            codes |= grid[on + o].astype(np.uint8) << k
        remove = tables[p % 4][codes]
        if remove.any():
            grid[on[remove]] = False
            on = on[~remove]
            quiet = 0
        else:
            quiet += 1
        p += 1
    return grid.reshape(h + 2, W)[1:-1, 1:-1].copy()


def find_wires_ridge(image: np.ndarray, px_per_mm: float = 4.0, enough: int = ENOUGH) -> RidgeResult:
    """Graspable wire ends in an image (grey or colour) at px_per_mm, best first."""
    result, clock, began, graph, reader = _look(image, px_per_mm)
    ordered = graph.ends_in_order(reader.f)
    for end in graph.short:
        reader.refuse(graph.rc(int(end)), "its line meets another or stops within 20 mm")
    for end in ordered:
        s = reader.read(end)
        if s is not None:
            result.candidates.append(s)
            if enough and len(result.candidates) >= enough:
                break
    result.candidates.sort(key=lambda s: -s.score)
    clock("ends")
    result.timings["total"] = (clock.last - began) * 1000.0
    return result


def find_middle(image: np.ndarray, px_per_mm: float = 4.0) -> RidgeResult:
    """Places to take a wire by its middle, best first: for a wire none of whose ends is free
    (a loop that crosses itself near both ends, say), to lift it and let it fall in a new
    shape. Each Sighting's end and grasp are the same point on a centre line, MIDDLE_AWAY_MM
    from every crossing (so on top) and MIDDLE_END_MM from every end of the centre lines, with
    the CLEARANCE_MM disc round it free (room for the fingers); end_angle and grasp_angle are
    the line's direction there. The roomiest comes first. Where there is no such place, places
    LOOP_END_MM from the ends, bowing up to LOOP_BOW (the far side of a small loop whose tails
    are short)."""
    result, clock, began, graph, reader = _look(image, px_per_mm)
    for end_mm, bow in ((MIDDLE_END_MM, MIDDLE_BOW), (LOOP_END_MM, LOOP_BOW)):
        result.candidates = [s for s in (reader.middle(p, bow) for p in graph.middles(end_mm)) if s is not None]
        if result.candidates:
            break
    result.candidates.sort(key=lambda s: -s.score)
    clock("middles")
    result.timings["total"] = (clock.last - began) * 1000.0
    return result


def _look(image: np.ndarray, px_per_mm: float):
    """The stages before ends are read: (result, clock, start time, the wire graph, its reader)."""
    result = RidgeResult()
    clock = Clock(result.timings)
    began = clock.last
    work, k = working_image(image, px_per_mm)
    wppm = px_per_mm / k
    result.scale = k
    clock("average")
    outside = find_rim(work, wppm)
    clock("rim")
    con = contrast(work, wppm, outside)
    clock("contrast")
    flat = SATURATION * np.tanh(con.f * (1.0 / SATURATION))  # a wire's body, not its highlight, makes the ridge
    strength, smoothed, which, fine = ridges(flat, wppm)
    clock("ridges")
    skeleton = centre_lines(strength, smoothed, which, wppm)
    clock("centre lines")
    graph = _Graph(skeleton, wppm)
    graph.prune_spurs()
    result.skeleton = graph.skeleton
    clock("graph")
    reader = _EndReader(con, flat, fine, graph, wppm, k, result, outside)
    return result, clock, began, graph, reader


def find_rim(work: np.ndarray, wppm: float) -> np.ndarray:
    """Where the frame shows a tray's rim or the bench round the tray, (rows, cols) bool: along a
    side, a band from the frame's edge of one even colour that gives way, on one smooth curve, to
    a different, even board. What lies there is not on the tray: ends near it are refused as at
    the frame's border, and it is neither board nor a thing round an end."""
    outside = np.zeros(work.shape[:2], bool)
    # each side seen as the left one: rows along it, columns inward (views, so the mask is written through)
    sides = (lambda a: a, lambda a: a[:, ::-1], lambda a: a.swapaxes(0, 1), lambda a: a[::-1].swapaxes(0, 1))
    for side in sides:
        v = side(work)
        n, m = v.shape[:2]
        depth = min(int(0.2 * m), int(RIM_SCAN_MM * wppm))
        seg = max(int(RIM_SEGMENT_MM * wppm), 4) // 2 * 2
        board = max(int(RIM_BOARD_MM * wppm), 3)
        kmin = max(int(RIM_MIN_MM * wppm), 2)
        gap = max(round(RIM_EDGE_MM * wppm), 2)
        nseg = n // seg
        if depth < kmin + board + gap + 2 or nseg < 3:
            continue
        rows = v[:nseg * seg:2, :depth]  # every other row: a median across 8 mm needs no more
        prof = np.median(rows.reshape(nseg, -1, depth, rows.shape[2]), axis=1)  # (nseg, depth, channels)
        edges = _steps(prof, kmin, board, gap)
        ok = np.isfinite(edges)
        if ok.mean() < RIM_SHARE:
            continue
        centres = np.arange(nseg) * seg + seg / 2
        coef = np.polyfit(centres[ok], edges[ok], 2)
        ok &= np.abs(np.polyval(coef, centres) - np.nan_to_num(edges)) <= RIM_BEND_PX
        if ok.mean() < RIM_SHARE:
            continue
        coef = np.polyfit(centres[ok], edges[ok], 2)
        k = np.clip(np.polyval(coef, np.arange(n)) + 1.0, 0, depth)
        mask = side(outside)
        mask |= np.arange(m)[None, :] < k[:, None]
    return outside


def _steps(prof: np.ndarray, kmin: int, board: int, gap: int) -> np.ndarray:
    """Per segment's profile (nseg, depth, channels) from the frame's edge inward: where an even
    band from the edge (its first k columns) gives way, across a blurred edge `gap` columns
    wide, to a board of another colour, even for the most part; NaN where it does not."""
    nseg, d, _ = prof.shape
    ks = np.arange(kmin, d - board - gap)
    if not len(ks):
        return np.full(nseg, np.nan)
    band = np.cumsum(prof, axis=1)[:, ks - 1] / ks[None, :, None]  # the mean of the first k columns
    hi = np.maximum.accumulate(prof, axis=1)[:, ks - 1]
    lo = np.minimum.accumulate(prof, axis=1)[:, ks - 1]
    band_spread = np.maximum(hi - band, band - lo).max(axis=2)
    wide = 3 * board
    pad = np.concatenate([prof, np.repeat(prof[:, -1:], wide, axis=1)], axis=1)
    # the board next to it, over the `wide` columns from ks + gap: its median, and how far its
    # RIM_BOARD_LOW and RIM_BOARD_HIGH percentiles lie from that (a wire or a speck there, or
    # the board's grain, does not hide the edge); every other column of each window, as the
    # percentiles need no more and they are the cost
    windows = np.lib.stride_tricks.sliding_window_view(pad, wide, axis=1)[:, ks + gap, :, ::2]  # (nseg, K, ch, wide/2)
    low, b, high = np.percentile(windows, (RIM_BOARD_LOW, 50, RIM_BOARD_HIGH), axis=3)  # each (nseg, K, ch)
    board_spread = np.maximum(high - b, b - low).max(axis=2)
    step = np.abs(band - b).max(axis=2)
    score = step / np.maximum(np.maximum(band_spread, board_spread), 0.01)
    score = np.where((step >= RIM_STEP) & (score >= RIM_CLEAR), score, 0.0)
    best = score.argmax(axis=1)
    edges = np.full(nseg, np.nan)
    for i in np.flatnonzero(score.max(axis=1) > 0):  # the edge: where the profile is half-way across
        j = best[i]
        a, z = band[i, j], b[i, j]
        c = int(np.argmax(np.abs(z - a)))
        part = (prof[i, :, c] - a[c]) / (z[c] - a[c])
        beyond = np.flatnonzero(part[ks[j]:] >= 0.5)
        if beyond.size:
            e = ks[j] + int(beyond[0])
            p0, p1 = part[e - 1], part[e]
            edges[i] = e - 1 + (0.5 - p0) / max(p1 - p0, 1e-6)
    return edges


class _Graph:
    """The centre lines as a graph on the working grid: ends, crossings, tracing."""

    def __init__(self, skeleton: np.ndarray, wppm: float) -> None:
        self.wppm = wppm
        self.h, self.w = skeleton.shape
        self.W = self.w + 2
        self.flat = np.pad(skeleton, 1).ravel().copy()
        self.offsets = [dr * self.W + dc for dr, dc in NEIGHBOURS]
        self._window = None
        self.short = np.zeros(0, np.int64)  # ends on lines too short to read (set by ends_in_order)
        self._count()

    def _count(self) -> None:
        on = np.flatnonzero(self.flat)
        self.degree = np.zeros(len(self.flat), np.uint8)
        for o in self.offsets:
            self.degree[on] += self.flat[on + o]

    @property
    def skeleton(self) -> np.ndarray:
        return self.flat.reshape(self.h + 2, self.W)[1:-1, 1:-1]

    def ends(self) -> np.ndarray:
        return np.flatnonzero(self.flat & (self.degree == 1))

    def rc(self, i: int) -> tuple[int, int]:
        return i // self.W - 1, i % self.W - 1

    def trace(self, start: int, limit_px: float) -> tuple[list[int], str]:
        """Follow the centre line from an end for limit_px of arc: (pixels, how it stopped:
        'crossing', 'end' or 'far')."""
        flat, offsets = self.flat.tobytes(), self.offsets  # bytes: a Python index per pixel is cheap
        path = [start]
        prev = -1
        cur = start
        arc = 0.0
        while arc < limit_px:
            nxt = [cur + o for o in offsets if flat[cur + o] and cur + o != prev and cur + o not in path[-3:]]
            if not nxt:
                jump = self.across_gap(path) if len(path) > 4 else None
                if jump is None:
                    return path, "end"
                arc += float(np.hypot(*np.subtract(divmod(jump, self.W), divmod(cur, self.W))))
                prev, cur = -1, jump
                path.append(cur)
                continue
            if len(nxt) > 1:
                # an edge neighbour and the diagonal beside it are one step of the same line
                edge = [q for q in nxt if abs(q - cur) in (1, self.W)]
                if len(nxt) == 2 and len(edge) == 1 and _adjacent(nxt[0], nxt[1], self.W):
                    nxt = edge
                else:
                    return path, "crossing"
            step = nxt[0]
            arc += 1.0 if abs(step - cur) in (1, self.W) else 1.4142
            prev, cur = cur, step
            path.append(cur)
        return path, "far"

    def prune_spurs(self) -> None:
        limit = SPUR_MM * self.wppm
        for e in self.ends():
            if not self.flat[e]:
                continue
            path, how = self.trace(int(e), limit)
            if how == "crossing":
                self.flat[path[:-1] if len(path) > 1 else path] = False
        _cut_corners(self.flat, self.W)  # a whisker gone may leave a corner where it joined
        self._count()

    def across_gap(self, path: list[int]) -> int | None:
        """Where the centre line goes on across a short break straight ahead of path's last pixel:
        the nearest other line end within GAP_MM in a GAP_CONE_DEG cone (a break leaves two ends
        facing each other), or None."""
        W = self.W
        here = np.array(divmod(path[-1], W), float)
        back = np.array(divmod(path[max(len(path) - 1 - int(2.0 * self.wppm), 0)], W), float)
        ahead = here - back
        n = float(np.linalg.norm(ahead))
        if n < 1.0:
            return None
        ahead /= n
        rr, cc, dist = self._gap_window
        cone = rr * ahead[0] + cc * ahead[1] >= _COS_CONE * dist
        idx = path[-1] + (rr[cone] * W + cc[cone]).astype(np.int64)
        ok = (idx >= 0) & (idx < len(self.flat))
        idx, d = idx[ok], dist[cone][ok]
        hit = (self.degree[idx] == 1) & self.flat[idx]
        if not hit.any():
            return None
        recent = set(path[-12:])
        for k in np.argsort(d[hit]):
            i = int(idx[hit][k])
            if i not in recent:
                return i
        return None

    @property
    def _gap_window(self):
        if self._window is None:
            reach = math.ceil(GAP_MM * self.wppm)
            rr, cc = np.mgrid[-reach:reach + 1, -reach:reach + 1]
            dist = np.hypot(rr, cc)
            keep = (dist >= 1.5) & (dist <= reach)
            self._window = (rr[keep], cc[keep], dist[keep])
        return self._window

    def middles(self, end_mm: float = MIDDLE_END_MM) -> list[np.ndarray]:
        """Points (row, col) on lines MIN_LINE_MM long or more, end_mm or more from every
        end of those lines and MIDDLE_AWAY_MM from every crossing, MIDDLE_STEP_MM apart at least,
        farthest from them (relative to those distances) first."""
        from scipy import ndimage

        grid = self.skeleton.astype(bool)
        if not grid.any():
            return []
        deg = self.degree.reshape(self.h + 2, self.W)[1:-1, 1:-1]

        def distance(marks):
            return ndimage.distance_transform_edt(~marks) if marks.any() else np.full(grid.shape, np.inf)

        # the ends and crossings of lines MIN_LINE_MM long or more (a speck of the board's
        # texture leaves a short line whose ends are no wire's)
        pieces, n = ndimage.label(grid, np.ones((3, 3)))
        size = np.bincount(pieces.ravel(), minlength=n + 1)
        size[0] = 0
        lines = size[pieces] >= MIN_LINE_MM * self.wppm
        from_end = distance(lines & (deg <= 1)) / (end_mm * self.wppm)
        from_crossing = distance(lines & (deg >= 3)) / (MIDDLE_AWAY_MM * self.wppm)
        away = np.minimum(from_end, from_crossing)
        rr, cc = np.nonzero(lines & (away >= 1.0))
        order = np.argsort(-away[rr, cc], kind="stable")
        pts = np.column_stack([rr[order], cc[order]]).astype(float)
        step2 = (MIDDLE_STEP_MM * self.wppm) ** 2
        kept: list[np.ndarray] = []
        while len(pts) and len(kept) < MIDDLE_MAX:  # the farthest left, then none near it
            kept.append(pts[0])
            pts = pts[((pts - pts[0]) ** 2).sum(axis=1) >= step2]
        return kept

    def ends_in_order(self, f: np.ndarray) -> list[int]:
        """The ends worth reading, best first: those whose line runs on for at least SPAN_MM
        before it meets another (every other end fails the span test anyway), on the longest,
        strongest lines first."""
        from scipy import ndimage

        ends = self.ends()
        if not len(ends):
            return []
        grid = self.flat.reshape(self.h + 2, self.W)
        crossing = (self.degree >= 3).reshape(grid.shape)
        pieces, n = ndimage.label(grid & ~ndimage.binary_dilation(crossing, np.ones((3, 3))), np.ones((3, 3)))
        length = np.bincount(pieces.ravel(), minlength=n + 1).astype(float)
        length[0] = 0.0
        piece = pieces.ravel()[ends]
        long_enough = length[piece] >= 0.85 * SPAN_MM * self.wppm
        self.short = ends[~long_enough]
        ends, piece = ends[long_enough], piece[long_enough]
        r, c = np.divmod(ends, self.W)
        score = np.minimum(length[piece], 2 * SPAN_MM * self.wppm) * \
            np.minimum(f[np.clip(r - 1, 0, self.h - 1), np.clip(c - 1, 0, self.w - 1)], 50.0)
        return [int(e) for e in ends[np.argsort(-score)]]


def _adjacent(a: int, b: int, W: int) -> bool:
    ra, ca = divmod(a, W)
    rb, cb = divmod(b, W)
    return max(abs(ra - rb), abs(ca - cb)) == 1


class _EndReader:
    """Reads one centre-line end: classify it, follow its tip, check it is free, make a Sighting."""

    def __init__(self, con: Contrast, flat: np.ndarray, fine: np.ndarray, graph: _Graph, wppm: float, k: int,
                 result: RidgeResult, outside: np.ndarray | None = None) -> None:
        self.con = con
        self.f = con.f  # the contrast
        self.g = graph
        self.wppm = wppm
        self.k = k
        self.result = result
        self.h, self.w = self.f.shape
        # what sample() may be asked for: F, its saturated form (what centres the line), the finest
        # scale's ridge strength
        self.layers = (con.f, flat, fine)
        self.shadows = False  # whether shadows round the wire being read are told from things (set by read)
        self.rim = None  # how far (working px) each pixel lies from a rim or bench the frame shows, if any
        if outside is not None and outside.any():
            from scipy import ndimage

            self.rim = ndimage.distance_transform_edt(~outside).astype(np.float32)

    def off_tray(self, pts: np.ndarray, margin: float) -> np.ndarray:
        """Which points lie within margin (working px) of a rim or bench the frame shows."""
        if self.rim is None:
            return np.zeros(len(pts), bool)
        r = np.clip(np.round(pts[:, 0]).astype(int), 0, self.h - 1)
        c = np.clip(np.round(pts[:, 1]).astype(int), 0, self.w - 1)
        return self.rim[r, c] < margin

    def refuse(self, at, why: str) -> None:
        r, c = at
        self.result.rejected.append(((float((c + 0.5) * self.k - 0.5), float((r + 0.5) * self.k - 0.5)), why))

    F, FLAT, FINE = 0, 1, 2  # the layers sample() may be asked for

    def sample(self, pts: np.ndarray, of: int = F) -> np.ndarray:
        """One layer (F, FLAT or FINE) at the points."""
        return bilinear(self.layers[of], pts)

    def shade(self, pts: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(F, F with the board in shadow counted as board, which points look so) at the points."""
        at = _corners(self.h, self.w, pts)
        f = _mix(self.f, *at)
        free, shade = shadow_free(self.con, _mix(self.con.work, *at), _mix(self.con.board, *at), f)
        return f, free, shade

    def around(self, pts: np.ndarray) -> np.ndarray:
        """The contrast at points round the wire (not on it): shadows on the board count as board
        unless the wire being read looks like a shadow itself."""
        return self.shade(pts)[1] if self.shadows else self.sample(pts)

    def read(self, end: int):
        g, mm = self.g, self.wppm
        start = np.array(g.rc(end), float)
        border = FRAME_MARGIN_MM * mm
        path, how = g.trace(end, (SPAN_MM + CLEARANCE_MM + 4.0) * mm * 1.1)  # past the disc round the grasp
        line = np.array([g.rc(i) for i in path], float)
        if len(line) >= 5:  # the pixel staircase smoothed, so arc lengths along it are true lengths
            from scipy import ndimage

            line = ndimage.uniform_filter1d(line, 5, axis=0, mode="nearest")
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(line, axis=0), axis=1))])
        if how == "crossing" and arc[-1] < SPAN_MM * mm:
            return self.refuse(start, f"it meets another line {arc[-1] / mm:.0f} mm from its end")
        if how == "end" and arc[-1] < SPAN_MM * mm:
            return self.refuse(start, f"the line is only {arc[-1] / mm:.0f} mm long")
        fit = line[arc <= END_FIT_MM * mm]
        inward = principal_direction(fit) if len(fit) >= 3 else line[-1] - line[0]
        inward = inward / max(float(np.linalg.norm(inward)), 1e-9)
        if inward @ (line[min(len(line) - 1, len(fit))] - line[0]) < 0:
            inward = -inward
        # the wire's contrast and width along its first SPAN_MM
        core = self.sample(line)
        level = float(np.median(core))
        board = max(BOARD_FLOOR, BOARD_SHARE * level)
        width = self.width(line, board)
        self.shadows = self.casts_shadow(line, width)
        # the tip: from inside the wire, follow the contrast outward along the centre line and on
        # past the ridge's end (which smoothing may carry beyond the wire) to where it drops
        out = -inward
        beyond = np.arange(TIP_MAX_MM * mm, 0.0, -0.5)
        ext = np.vstack([start + beyond[:, None] * out, line])
        es = np.concatenate([-beyond, arc])
        inside = es <= TIP_START_MM * mm
        scan = ext[inside][::-1]  # from TIP_START_MM in, outward
        scan_s = es[inside][::-1]
        side = np.array([-out[1], out[0]])
        lateral = np.array([-0.25, 0.0, 0.25]) * width
        ray = scan[:, None, :] + lateral[None, :, None] * side
        along = self.around(ray.reshape(-1, 2)).reshape(len(scan), len(lateral)).max(axis=1)
        thin = self.sample(ray.reshape(-1, 2), self.FINE).reshape(len(scan), len(lateral)).max(axis=1)
        # the wire goes on while it stands out as the insulation does (shadows on the board do not
        # count), or as a thin conductor does: a faint but sharp ridge on the axis (a shadow or a
        # blur is faint and broad; tin or a ferrule may have the colour of a shadow)
        conductor = (along >= BOARD_FLOOR) & (thin >= CONDUCTOR_RIDGE)
        edge = max(BOARD_FLOOR, TIP_SHARE * level)
        below = (along < edge) & ~conductor
        along = np.where(conductor & (along < edge), edge, along)
        gone = np.flatnonzero(below[:-1] & below[1:])
        if not gone.size:
            return self.refuse(start, "its contrast runs on past its end (under or into something)")
        i = int(gone[0])
        if i == 0:
            return self.refuse(start, "no wire to be seen at its end")
        a, b = along[i - 1], along[i]
        frac = float(np.clip((a - edge) / max(a - b, 1e-6), 0, 1))
        tip_s = scan_s[i - 1] + frac * (scan_s[i] - scan_s[i - 1])
        tip = np.array([np.interp(tip_s, es, ext[:, 0]), np.interp(tip_s, es, ext[:, 1])])
        tip = self.conductor(tip, out, width)
        r, c = tip
        if r < border or c < border or r > self.h - 1 - border or c > self.w - 1 - border:
            return self.refuse(start, "its end is at the frame's border")
        if self.off_tray(tip[None, :], border)[0]:
            return self.refuse(start, "its end is at the tray's rim")
        # the centre line from the tip, and the grasp point GRASP_MM along it
        full = self.recentred(_resample(np.vstack([tip[None, :], ext[es > tip_s + 0.5]]), 1.0), width)
        s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(full, axis=0), axis=1))])
        if s[-1] < SPAN_MM * mm * 0.98 and how != "far":
            return self.refuse(start, "too little wire past its end")
        if np.any(full < border) or np.any(full[:, 0] > self.h - 1 - border) or np.any(full[:, 1] > self.w - 1 - border):
            return self.refuse(start, "the wire runs off the frame near its end")
        if self.off_tray(full, border).any():
            return self.refuse(start, "the wire runs to the tray's rim near its end")
        head = full[(s >= TIP_FIT_MM[0] * mm) & (s <= TIP_FIT_MM[1] * mm)]
        if len(head) >= 3:  # the direction at the tip itself (a ridge may bend as it overshoots the end)
            inward, on_axis = tip_axis(head, full[0])
        else:
            on_axis = full[0]
        grasp = np.array([np.interp(GRASP_MM * mm, s, full[:, 0]), np.interp(GRASP_MM * mm, s, full[:, 1])])
        near = (s >= (GRASP_MM - TANGENT_MM) * mm) & (s <= (GRASP_MM + TANGENT_MM) * mm)
        tangent = principal_direction(full[near]) if near.sum() >= 3 else inward
        span = self.span(full, grasp, width)
        why = self.crowded(span, tip, out, width, board, level)
        if why:
            return self.refuse(start, why)
        clutter = self.clutter(span, tip, out, width, board)
        grasp = self.centred(grasp, tangent, width)
        return self.sighting(on_axis, inward, grasp, tangent, 1.0 / (1.0 + clutter))

    def middle(self, p: np.ndarray, bow: float = MIDDLE_BOW):
        """A Sighting to take the wire by its middle at centre-line point p, or None (refused):
        its line must bow from its tangent by no more than `bow` of the disc's radius."""
        mm = self.wppm
        reach = (CLEARANCE_MM + 2.0) * mm  # past the fingers' disc (and so the frame's margin)
        if min(p[0], p[1], self.h - 1 - p[0], self.w - 1 - p[1]) < reach or self.off_tray(p[None, :], reach)[0]:
            return None  # the disc for the fingers would run off the frame or the tray
        skel = self.g.skeleton
        r0, c0 = int(p[0]), int(p[1])
        rad = int(math.ceil(reach))
        win = skel[r0 - rad:r0 + rad + 1, c0 - rad:c0 + rad + 1]
        from scipy import ndimage

        pieces, _ = ndimage.label(win, np.ones((3, 3)))
        own = np.column_stack(np.nonzero(pieces == pieces[rad, rad])).astype(float) + (p - rad)
        near = own[((own - p) ** 2).sum(axis=1) <= (TANGENT_MM * mm) ** 2]
        if len(near) < 3:
            return None
        tangent = principal_direction(near)
        # the local centre line through p, ordered along the tangent: it must run on through the
        # disc round p both ways and bend no more than a wire does (a small thing's outline, a
        # printed line's broken grid does not)
        along = (own - p) @ tangent
        across = np.abs((own - p) @ np.array([-tangent[1], tangent[0]]))
        if along.min() > -MIDDLE_THROUGH * reach or along.max() < MIDDLE_THROUGH * reach \
                or across.max() > bow * reach:
            return None
        line = own[np.argsort(along)]
        level = float(np.median(self.sample(line)))
        board = max(BOARD_FLOOR, BOARD_SHARE * level)
        width = self.width(line, board)
        seen = self._seen(self.fingers_room(p, own, width))
        if np.count_nonzero(seen >= board) >= DISC_HITS:
            return None
        room = float(np.percentile(seen, ROOM_PERCENTILE)) / board if len(seen) else 0.0
        return self.sighting(p, tangent, p, tangent, 1.0 / (1.0 + room))

    def casts_shadow(self, line: np.ndarray, width: float) -> bool:
        """Whether the wire casts a shadow that can be told from it: its own centre line does not
        look like board in shadow, and the board along one side of it does, much more than along
        the other (a light from one side)."""
        if len(line) < 5:
            return False
        n = _normals(line)
        offs = width / 2 + np.array([0.6, 1.0]) * self.wppm  # past the blur of the wire's edge
        offs = np.concatenate([-offs, offs])  # one side, then the other
        pts = (line[:, None, :] + offs[None, :, None] * n[:, None, :]).reshape(-1, 2)
        f, _, shade = self.shade(np.vstack([line, pts]))
        if float(shade[:len(line)].mean()) >= SHADOW_LIKE_WIRE:
            return False
        looks = (shade & (f >= BOARD_FLOOR))[len(line):].reshape(len(line), 2, 2)
        share = looks.mean(axis=(0, 2))
        # a blurred edge looks like shadow on both sides alike
        return bool(share.max() >= SHADOW_SIDE and share.min() <= 0.5 * share.max())

    def conductor(self, end: np.ndarray, out: np.ndarray, width: float) -> np.ndarray:
        """The tip of a faint conductor or ferrule running on straight past the insulation's end
        (end), or end itself if there is none. It runs while the contrast on the axis (the most
        of three samples across it), averaged over CONDUCTOR_WINDOW_MM, stands CONDUCTOR_CONTRAST
        above the board beside it; its tip is where that contrast falls to TIP_SHARE of its own."""
        from scipy import ndimage

        mm = self.wppm
        steps = np.arange(0.5, TIP_MAX_MM * mm, 0.5)
        side = np.array([-out[1], out[0]])
        lateral = np.array([-0.2 * width, 0.0, 0.2 * width, -(width / 2 + mm), width / 2 + mm, -0.45 * width,
                            0.45 * width])
        pts = end + steps[:, None, None] * out + lateral[None, :, None] * side
        flat_pts = pts.reshape(-1, 2)
        if self.shadows:  # board in shadow beyond the tip is no conductor, unless a sharp ridge runs on it
            v, free, shade = self.shade(flat_pts)
            v = np.where(shade & (self.sample(flat_pts, self.FINE) < CONDUCTOR_RIDGE), free, v)
        else:
            v = self.sample(flat_pts)
        v = v.reshape(len(steps), len(lateral))
        board = v[:, 3:5].mean(axis=1)
        rise = v[:, :3].max(axis=1) - board  # a thin conductor may lie off the axis
        n = max(round(CONDUCTOR_WINDOW_MM * mm * 2), 1)
        mean = ndimage.uniform_filter1d(rise, n, mode="nearest")  # over the window centred on each step
        # a dip shorter than half the window is no gap: a line thinner than two pixels comes and
        # goes as it crosses the pixel grid (and strands or JPEG blocks break it up)
        held = ndimage.maximum_filter1d(rise, max(n // 2, 1), mode="nearest")
        on = (mean >= CONDUCTOR_CONTRAST) & (held >= 0.5 * CONDUCTOR_CONTRAST)
        off = np.flatnonzero(~on)
        run = int(off[0]) if off.size else len(on)
        if run < n or steps[run - 1] < CONDUCTOR_MIN_MM * mm:
            return end  # nothing that runs on far enough: the blur of the end itself, or its shadow
        if np.median(v[:run, 5:7].mean(axis=1) - board[:run]) > CONDUCTOR_NARROW * np.median(rise[:run]):
            return end  # as wide as the wire: the end's shadow or the blur of a rounded end
        # its tip, as the insulation's: where its own contrast falls to TIP_SHARE of what it is
        # along it; over half the window, as the dips are no gap (an average over a centred
        # window crosses a step's half height where it steps)
        short = ndimage.uniform_filter1d(rise, max(n // 2, 1), mode="nearest")
        own = float(np.median(short[:run]))
        edge = max(CONDUCTOR_CONTRAST, TIP_SHARE * own)
        low = np.flatnonzero(short[:run] < edge)
        low = low[low >= n]  # not in the tip's own first window
        i = int(low[0]) if low.size else run
        if i >= run:
            return end + out * steps[run - 1]
        a, b = short[i - 1], short[i]
        frac = float(np.clip((a - edge) / max(a - b, 1e-6), 0, 1))
        return end + out * (steps[i - 1] + frac * 0.5)

    def recentred(self, line: np.ndarray, width: float) -> np.ndarray:
        """The centre line moved across the wire to the middle of its contrast (sub-pixel); the
        first point, the tip, put on the centred line's extension."""
        from scipy import ndimage

        if len(line) < 5:
            return line
        n = _normals(line)
        offs = np.linspace(-0.8 * width, 0.8 * width, 9)
        pts = line[:, None, :] + offs[None, :, None] * n[:, None, :]
        prof = self.sample(pts.reshape(-1, 2), self.FLAT).reshape(len(line), len(offs))
        wts = np.clip(prof - 0.5 * prof.max(axis=1, keepdims=True), 0, None)
        total = wts.sum(axis=1)
        shift = np.where(total > 0, (wts * offs).sum(axis=1) / np.maximum(total, 1e-9), 0.0)
        shift = ndimage.median_filter(np.clip(shift, -0.5 * width, 0.5 * width), 5, mode="nearest")
        shift = ndimage.uniform_filter1d(shift, 5, mode="nearest")
        out = line + shift[:, None] * n
        # the tip: on the centred line's own extension, as far out as the tip search put it
        ahead = out[1] - out[min(4, len(out) - 1)]
        ahead /= max(float(np.linalg.norm(ahead)), 1e-9)
        out[0] = out[1] + ahead * float(np.linalg.norm(line[0] - line[1]))
        return out

    def width(self, line: np.ndarray, board: float) -> float:
        """The wire's width (working px): across it at five places, how far its contrast stands
        above the board (and above 0.4 of its peak) without a break, the median."""
        if len(line) < 8:
            return 2.0
        idx = np.linspace(len(line) // 4, len(line) - 2, 5).astype(int)
        t = line[np.minimum(idx + 2, len(line) - 1)] - line[np.maximum(idx - 2, 0)]
        t /= np.maximum(np.linalg.norm(t, axis=1, keepdims=True), 1e-9)
        n = np.column_stack([-t[:, 1], t[:, 0]])
        offs = np.arange(-4.0 * self.wppm, 4.0 * self.wppm + 0.01, 0.5)
        prof = self.sample((line[idx][:, None, :] + offs[None, :, None] * n[:, None, :]).reshape(-1, 2))
        prof = prof.reshape(len(idx), len(offs))
        mid = len(offs) // 2
        peak = prof[:, mid - 4:mid + 5].max(axis=1, keepdims=True)
        above = prof >= np.maximum(0.4 * peak, board)
        # a break narrower than BRIDGE_MM is no edge: the specular line along a glossy wire (it may
        # be as light as the board), or a grain
        above = _bridged(above, int(round(BRIDGE_MM * self.wppm / 0.5)))
        # in each row, the run of `above` through the sample nearest the centre line that is in it
        window = above[:, mid - 3:mid + 4]
        seen = window.any(axis=1)
        if not seen.any():
            return 2.0
        m = mid - 3 + np.argmin(np.where(window, np.abs(np.arange(7) - 3), 99), axis=1)[:, None]
        at = np.arange(above.shape[1])[None, :]
        lo = np.where(~above & (at < m), at, -1).max(axis=1) + 1
        hi = np.where(~above & (at > m), at, above.shape[1]).min(axis=1) - 1
        widths = (hi - lo + 1)[seen] * 0.5
        return float(np.clip(np.median(widths), 1.0, 4.0 * self.wppm))

    def span(self, full, grasp, width) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """What the free test and the room round an end look beside: the centre line along the
        span (its first SPAN_MM and the slack: what lies beside the wire further on is no
        matter) at 1 px steps, its normals, and the points of the CLEARANCE_MM disc round the
        grasp point less the wire itself (clear of its centre line near the grasp point)."""
        mm = self.wppm
        dense = _resample(full, 1.0)
        ds = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(dense, axis=0), axis=1))])
        along = ds <= (SPAN_MM + SPAN_SLACK_MM) * mm
        local = dense[np.abs(ds - GRASP_MM * mm) <= (CLEARANCE_MM + 3.0) * mm]
        disc = self.fingers_room(grasp, local, width)
        return dense[along], _normals(dense)[along], disc

    def fingers_room(self, at: np.ndarray, line: np.ndarray, width: float) -> np.ndarray:
        """The points of the CLEARANCE_MM disc round `at` less the wire itself: those farther
        than its half width (and a little) from the centre-line points `line` near there."""
        mm = self.wppm
        disc = _disc(CLEARANCE_MM * mm) + at
        if not len(line):
            return disc
        d2 = ((disc * disc).sum(axis=1)[:, None] + (line * line).sum(axis=1)[None, :]
              - 2.0 * disc @ line.T).min(axis=1)
        return disc[d2 > (width / 2 + 0.6 * SIDE_FREE_MM * mm) ** 2]

    def crowded(self, span, tip, out, width, board, level) -> str:
        """Why the wire near its end is not free (board must show around it), or ''."""
        mm = self.wppm
        half = width / 2
        line, n, disc = span
        # beside the span, both sides
        offs = half + np.array([0.6, 0.9, 1.2]) * SIDE_FREE_MM * mm
        band = (line[:, None, None, :] + (np.array([-1, 1])[None, :, None, None] * offs[None, None, :, None])
                * n[:, None, None, :]).reshape(-1, 2)
        # beyond the tip
        dirs = _fan(out)
        cap = (tip[None, None, :] + (half + np.array([0.7, 1.0, 1.4, 2.0, 2.8]) * SIDE_FREE_MM * mm)[None, :, None]
               * dirs[:, None, :]).reshape(-1, 2)
        values = self._seen(np.vstack((band, cap, disc)))
        hit = values >= board
        nb, nc = len(band), len(cap)
        # straight on past the tip, even a faint contrast that goes on is the wire going on into
        # light or a colour that hides it, not its end
        ahead = values[nb:nb + nc].reshape(len(_FAN), -1)[len(_FAN) // 2 - 1:len(_FAN) // 2 + 2]
        if np.count_nonzero(ahead >= max(FADE_FLOOR, FADE_SHARE * level)) >= ahead.size // 2:
            return "its contrast fades but goes on past its end"
        # beside the span, something that goes on for RUN_MM along it (a speck of the board's
        # texture or a thin printed line does not)
        runs = hit[:nb].reshape(len(line), -1)
        need = max(round(RUN_MM * mm), 2)
        if runs.shape[0] >= need:  # a run of `need` hits down any one column
            c = np.cumsum(np.vstack([np.zeros((1, runs.shape[1]), int), runs]), axis=0)
            if int((c[need:] - c[:-need]).max()) >= need:
                return "another wire or something lies beside it"
        if np.count_nonzero(hit[nb:nb + nc]) >= CAP_HITS:
            return "something lies just beyond its end"
        if np.count_nonzero(hit[nb + nc:]) >= DISC_HITS:
            return "no room for the fingers at the grasp point"
        return ""

    def clutter(self, span, tip, out, width, board) -> float:
        """How near something comes to a free end: the most contrast, relative to the board's
        threshold, in bands ROOM_BAND_MM out from the wire's edges along its span (each band's
        ROOM_PERCENTILE), on arcs ROOM_CAP_MM beyond its tip (the most), and in the disc round
        the grasp point (its ROOM_PERCENTILE). 1 or more: something as strong as the threshold
        for a thing there comes that near (within the free test's bands only if it is too
        small or too short to count there)."""
        mm = self.wppm
        half = width / 2
        line, n, disc = span
        worst = []
        for d in ROOM_BAND_MM:
            off = half + d * mm
            band = np.vstack((line + off * n, line - off * n))
            worst.append(np.percentile(self._seen(band), ROOM_PERCENTILE))
        cap = (tip[None, None, :] + (half + np.array(ROOM_CAP_MM) * mm)[:, None, None] * _fan(out)[None, :, :])
        worst.append(self._seen(cap.reshape(-1, 2)).max())
        if len(disc):
            worst.append(np.percentile(self._seen(disc), ROOM_PERCENTILE))
        return float(max(worst)) / board

    def _seen(self, pts: np.ndarray) -> np.ndarray:
        """around() at the points; nothing where they fall off the image or within RIM_EDGE_MM of a
        rim or the bench round the tray (which is neither board nor a thing there)."""
        inside = (pts[:, 0] >= 0) & (pts[:, 1] >= 0) & (pts[:, 0] <= self.h - 1) & (pts[:, 1] <= self.w - 1)
        if self.rim is not None:
            inside &= ~self.off_tray(pts, RIM_EDGE_MM * self.wppm)
        return np.where(inside, self.around(pts), 0.0)

    def centred(self, grasp, tangent, width) -> np.ndarray:
        """The grasp point moved across the wire to the middle of its contrast."""
        n = np.array([-tangent[1], tangent[0]])
        offs = np.arange(-width, width + 0.01, 0.25)
        prof = self.sample(grasp + offs[:, None] * n)
        wts = np.clip(prof - 0.5 * prof.max(), 0, None)
        if wts.sum() <= 0:
            return grasp
        shift = float((wts * offs).sum() / wts.sum())
        return grasp + np.clip(shift, -0.5 * width, 0.5 * width) * n

    def sighting(self, tip, inward, grasp, tangent, score) -> Sighting:
        k = self.k

        def to_input(p):
            return ((p[1] + 0.5) * k - 0.5, (p[0] + 0.5) * k - 0.5)

        end_angle = math.degrees(math.atan2(inward[0], inward[1]))
        grasp_angle = math.degrees(math.atan2(tangent[0], tangent[1])) % 180.0
        return Sighting(to_input(tip), end_angle, to_input(grasp), grasp_angle, score)


def tip_axis(head: np.ndarray, tip: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The unit direction into the wire at its tip, the chord of the centre line's head (the
    first few mm past the tip), and the tip put on that axis (a hooked ridge end is off it)."""
    chord = principal_direction(head)
    if chord @ (head[-1] - head[0]) < 0:
        chord = -chord
    middle = head.mean(axis=0)
    return chord, middle + chord * float((tip - middle) @ chord)


_FAN = np.radians(np.linspace(-70, 70, 9))


def _fan(out: np.ndarray) -> np.ndarray:
    """Unit directions within 70 degrees either side of out."""
    c, s = np.cos(_FAN), np.sin(_FAN)
    return np.column_stack([out[0] * c - out[1] * s, out[0] * s + out[1] * c])


@lru_cache(maxsize=16)
def _disc_template(radius10: int) -> np.ndarray:
    radius = radius10 / 10.0
    grid = np.arange(-radius, radius + 0.01, 0.75)
    a, b = np.meshgrid(grid, grid)
    inside = a * a + b * b <= radius * radius
    return np.column_stack([a[inside], b[inside]])


def _disc(radius: float) -> np.ndarray:
    """Points 0.75 px apart filling a disc of the radius (px) round the origin."""
    return _disc_template(round(radius * 10))


def _bridged(rows: np.ndarray, gap: int) -> np.ndarray:
    """Each row with its runs of False no longer than gap, between two Trues, made True: a
    binary closing along the rows (away from their ends)."""
    at = np.arange(rows.shape[1])
    before = np.maximum.accumulate(np.where(rows, at, -1), axis=1)
    after = np.minimum.accumulate(np.where(rows, at, rows.shape[1])[:, ::-1], axis=1)[:, ::-1]
    return rows | ((before >= 0) & (after < rows.shape[1]) & (after - before - 1 <= gap))


def _normals(line: np.ndarray) -> np.ndarray:
    """The unit normal (row, col) at each point of a polyline, from its central differences."""
    t = np.gradient(line, axis=0)
    t /= np.maximum(np.linalg.norm(t, axis=1, keepdims=True), 1e-9)
    return np.column_stack([-t[:, 1], t[:, 0]])


def _resample(pts: np.ndarray, step: float) -> np.ndarray:
    """A polyline sampled every `step` along it, up to (not past) its length: unlike
    synth.resample it never repeats the last point, so directions along it stay defined."""
    seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    s = np.arange(0.0, cum[-1] + 1e-9, step)
    return np.column_stack([np.interp(s, cum, pts[:, 0]), np.interp(s, cum, pts[:, 1])])
