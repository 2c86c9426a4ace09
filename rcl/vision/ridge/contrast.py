"""The ridge finder's contrast: the image on its working grid, and how far each pixel stands out
from the board round it, in units of the board's spread (shadows told apart)."""
from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ...camera.images import ImageError
from ..common import block_average, two_thirds_average
from .lattice import without_lattice

THIRDS_FROM = 3.0  # px/mm from which an image is worked on in blocks 1.5 px wide, not as it is (2-2.7 px/mm)
SHADOW_LIGHT = (0.55, 0.97)  # a shadow leaves this share of the board's light: darker is a thing, lighter is board
SHADOW_TINT = 2.0  # ... and adds no more other colour than this (spreads)
MIN_SPREAD = 0.012  # the least board spread believed (3 grey levels): JPEG and sensor noise at the least
BOARD_BLOCK_MM = 8.0  # blocks in which the board's colour is estimated
TONE_WHEN = (99.5, 6.0)  # the board is tried as two tones when this percentile of F is less than this
TONE_SPLIT = 3.0  # two tones: this many of their own spreads apart
TONE_THICK_MM = 2.0  # ... each in places this far from the other (no wire is so wide)
TONE_SHARE = 0.05  # ... in this share of the tray each
TONE_EDGE_MM = 1.0  # ... and within this of a patch's edge, a colour between the two is board
TONE_SPREAD = 0.3  # ... F's spread then no less than this share of the spread of the board as one colour
TONE_DARK = 0.02  # ... the ratio of their colours (0-1) taken no nearer black than this
TONE_SAMPLE = 6000  # ... told apart on about so many pixels, evenly spread
TONE_TIGHT = 0.6  # two tones are taken when the board's spread from them is less than this share of it as one colour
TONE_F = 4.0  # where wires stand out, a board is tried as two tones if places where F exceeds this
TONE_PATCHY = 0.005  # ... fill this share of the tray TONE_THICK_MM inside them (broad patches),
TONE_GAIN = 0.5  # ... and taken so if it leaves less than this share of those places above TONE_F


def unit(a: np.ndarray) -> float:
    """What one level of an image of a's type is in colours 0-1: 8-bit and 16-bit levels scaled,
    floats taken as they are."""
    return 1.0 / 255.0 if a.dtype == np.uint8 else 1.0 / 65535.0 if a.dtype == np.uint16 else 1.0


def working_image(image: np.ndarray, px_per_mm: float, k: float | None = None) -> tuple[np.ndarray, float]:
    """(the image averaged to 2-3 px/mm as float32 (rows, cols, channels), the input pixels per
    working pixel k): k x k blocks, k = px/mm // 2, and blocks 1.5 px wide at 3-4 px/mm (each 3 x 3
    pixels become 2 x 2); below 3 px/mm, the image as it is. Given k (1, 1.5 or a whole number),
    blocks that wide whatever px/mm is."""
    a = np.asarray(image)
    scale = unit(a)
    if a.ndim == 2:
        a = a[:, :, None]
    if a.ndim != 3 or a.shape[2] not in (1, 3, 4) or not np.issubdtype(a.dtype, np.number):
        raise ImageError(f"an image is rows x columns (x 3 colours) of numbers, not shape {np.shape(image)}")
    a = a[:, :, :3]
    n = max(1, int(k if k is not None else px_per_mm // 2.0))
    thirds = k == 1.5 if k is not None else n == 1 and px_per_mm >= THIRDS_FROM
    if a.shape[0] < 16 * n or a.shape[1] < 16 * n:
        raise ImageError(f"the image ({a.shape[1]} x {a.shape[0]} px) is too small to find wires in")
    if thirds:
        out, k = two_thirds_average(a), 1.5
    else:
        out, k = block_average(a, n), n
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
    lattice: bool = False  # a printed lattice was found and taken out
    tones: bool = False  # the board was taken as printed in two tones


def contrast(work: np.ndarray, wppm: float, outside: np.ndarray | None = None, k: float = 1,
             like: Contrast | None = None) -> Contrast:
    """The contrast F: the board's colour estimated per BOARD_BLOCK_MM block (the median, then the
    median of 3 x 3 blocks, so blocks full of wire are outvoted), subtracted, a printed lattice on
    the board (a cutting mat's grid) taken out of the difference (lattice.py; k: input pixels per
    working pixel), each channel divided by its own robust spread, then the root mean square over
    the channels. Pixels `outside` the tray (a rim, the bench round it) have no say in the board
    and no contrast.

    The board may be printed in two tones (camouflage) whose mixture in each block makes the
    spread as large as a wire's contrast; so it is also tried as two tones (_two_tones), with F
    taken from the tone under each pixel, and taken so when nothing stands out of it as one
    colour (F's TONE_WHEN percentile is low), when its spread from the two tones is less than
    TONE_TIGHT of its spread as one colour (the tones are what varies: a wire of a third colour
    drowned in their mixture stands out of them), or when things broader than any wire stand out
    (_patchy) and the tones leave less than TONE_GAIN of the pixels that stood out above TONE_F
    (the patches of a board printed in tones far apart).

    like: the contrast of the same picture at another working scale, whose findings about the
    board are taken, not sought again: no lattice where it found none, one colour where it took
    the board as one (what the picture is printed with does not change with the sampling)."""
    lattice = like is None or like.lattice
    under = _board(work, wppm, outside)
    diff, pairs = without_lattice(work - under, wppm, k) if lattice else (work - under, 0)
    f, unit, spread = _in_spreads(diff, outside)
    inside = _on_tray(f, outside)
    # nothing stands out of the board: a board printed in two tones may drown the wires; or the
    # tones are what varies; or wires stand out, but so do broad patches: tones far apart
    quiet = bool(inside.size) and np.percentile(inside, TONE_WHEN[0]) < TONE_WHEN[1]
    tones = _two_tones(work, wppm, outside) if inside.size and (like is None or like.tones) else None
    if tones is not None:
        diff, pairs2 = without_lattice(work - tones, wppm, k) if lattice else (work - tones, 0)
        own = _spread(diff, outside)
        tight = float(np.sqrt((own ** 2).sum() / (spread ** 2).sum())) < TONE_TIGHT
        f2, unit2, _ = _in_spreads(diff, outside, np.maximum(TONE_SPREAD * spread, MIN_SPREAD), own)
        if quiet or tight or (_patchy(f, wppm, outside) and np.count_nonzero(_on_tray(f2, outside) > TONE_F)
                              < TONE_GAIN * np.count_nonzero(inside > TONE_F)):
            return Contrast(f2, work, tones, unit2, pairs2 > 0, True)
    return Contrast(f, work, under, unit, pairs > 0, False)


def _on_tray(f: np.ndarray, outside: np.ndarray | None) -> np.ndarray:
    """Every fourth pixel's F (each way) on the tray: a sample to judge the whole by."""
    return f[::4, ::4] if outside is None else f[::4, ::4][~outside[::4, ::4]]


def _patchy(f: np.ndarray, wppm: float, outside: np.ndarray | None) -> bool:
    """Whether TONE_PATCHY of the tray or more lies TONE_THICK_MM inside places where F exceeds
    TONE_F (a square's half side): broad patches standing out, as no wire is so wide."""
    from scipy import ndimage

    r = max(int(round(TONE_THICK_MM * wppm / 2)), 1)  # on every second pixel
    thick = ndimage.minimum_filter(f[::2, ::2] > TONE_F, size=2 * r + 1)
    if outside is not None:
        thick &= ~outside[::2, ::2]
    n = thick.size if outside is None else max(int(np.count_nonzero(~outside[::2, ::2])), 1)
    return bool(np.count_nonzero(thick) >= TONE_PATCHY * n)


def _in_spreads(diff: np.ndarray, outside: np.ndarray | None, least: float | np.ndarray = MIN_SPREAD,
                own: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(F: the difference from the board with each channel in units of its own robust spread (no
    less than `least`; `own`, if the caller has measured it), the root mean square over the
    channels; the factor per channel; the spreads). diff is scaled in place."""
    ch = diff.shape[2]
    spread = np.maximum(_spread(diff, outside) if own is None else own, least)
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
    return f, unit, spread


def _board(work: np.ndarray, wppm: float, outside: np.ndarray | None) -> np.ndarray:
    """The board's colour under each pixel: the median per BOARD_BLOCK_MM block of the pixels on
    the tray, the median of 3 x 3 blocks (blocks full of wire are outvoted), enlarged bilinearly."""
    blocks, grid = _block_medians(work, wppm, outside)
    if np.isnan(blocks[..., 0]).all():  # (no tray in sight: all the frame's blocks)
        blocks, grid = _block_medians(work, wppm, None)
    return _enlarged(_filled(blocks), grid, work)


def _block_medians(work: np.ndarray, wppm: float,
                   skip: np.ndarray | None) -> tuple[np.ndarray, tuple[int, int, int, int]]:
    """(the median colour per BOARD_BLOCK_MM block of the pixels not in `skip`, NaN where there
    are none; the blocks' geometry)."""
    h, w, ch = work.shape
    b = max(round(BOARD_BLOCK_MM * wppm), 4)
    nby, nbx = max(h // b, 1), max(w // b, 1)
    bh, bw = h // nby, w // nbx
    within_r, within_c = np.arange(0, bh, 3), np.arange(0, bw, 3)  # every third pixel of a block, from its corner
    rows = (np.arange(nby)[:, None] * bh + within_r).ravel()
    cols = (np.arange(nbx)[:, None] * bw + within_c).ravel()
    sh, sw = len(within_r), len(within_c)

    def blocked(a: np.ndarray) -> np.ndarray:
        """Every third pixel of each block: (nby, nbx, samples, channels)."""
        sub = a[rows[:, None], cols[None, :]]
        return sub.reshape(nby, sh, nbx, sw, -1).transpose(0, 2, 1, 3, 4).reshape(nby, nbx, sh * sw, -1)

    blocks = blocked(work)
    if skip is not None and skip.any():
        off = blocked(skip[..., None])[..., 0]
        with warnings.catch_warnings():  # a block wholly skipped has no median: NaN
            warnings.simplefilter("ignore", RuntimeWarning)
            board = np.nanmedian(np.where(off[..., None], np.nan, blocks), axis=2)
    else:
        board = np.median(blocks, axis=2)
    return board, (nby, nbx, bh, bw)


def _filled(board: np.ndarray) -> np.ndarray:
    """Blocks with no median (not all) take the nearest block's, then the median of 3 x 3 blocks."""
    from scipy import ndimage

    empty = np.isnan(board[..., 0])
    if empty.any():
        idx = ndimage.distance_transform_edt(empty, return_distances=False, return_indices=True)
        board = board[idx[0], idx[1]]
    if board.shape[0] >= 3 and board.shape[1] >= 3:
        board = ndimage.median_filter(board, size=(3, 3, 1), mode="nearest")
    return board


def _enlarged(board: np.ndarray, grid: tuple[int, int, int, int], work: np.ndarray) -> np.ndarray:
    """Block values enlarged bilinearly to the working grid (two small matrix products per channel)."""
    nby, nbx, bh, bw = grid
    h, w, ch = work.shape
    ay = _interp_matrix(h, nby, bh)
    ax = _interp_matrix(w, nbx, bw)
    under = np.empty_like(work)
    for c in range(ch):
        under[:, :, c] = ay @ board[:, :, c] @ ax.T
    return under


def _two_tones(work: np.ndarray, wppm: float, outside: np.ndarray | None) -> np.ndarray | None:
    """The board's colour under each pixel if the board is printed in two tones (camouflage: blobs
    of two colours, many wider than any wire), else None.

    The light across the tray is fitted as a smooth surface (a quadratic in each channel); what
    is left is split along its main colour direction into a darker and a lighter tone (Otsu's
    threshold on the middle 90 %, so that wires do not pull it). The board is two tones if they
    lie TONE_SPLIT of their own spreads apart and each fills TONE_SHARE of the tray with places
    TONE_THICK_MM from the other (no wire is so wide). Each tone's colour is then taken per block
    from those places (where a block shows one tone only, the other is the same light on the
    other's colour); the patches (those places grown back to their edges) take their tone, any
    other pixel the tone nearer its colour, and within TONE_EDGE_MM of a patch's edge a colour
    between the two (a blurred edge) is board."""
    from scipy import ndimage

    h, w, ch = work.shape
    inside = np.ones((h, w), bool) if outside is None else ~outside
    step = max(4, int(np.ceil(np.sqrt(h * w / TONE_SAMPLE))))  # every 4th pixel, or fewer on a large image
    keep = inside[::step, ::step]
    if keep.sum() < 200:
        return None
    rows, cols = np.mgrid[0:h:step, 0:w:step]
    y, x = rows[keep] / h - 0.5, cols[keep] / w - 0.5
    terms = np.column_stack([np.ones_like(x), x, y, x * x, x * y, y * y])
    sample = work[::step, ::step][keep]
    coef, *_ = np.linalg.lstsq(terms, sample, rcond=None)
    rest = sample - terms @ coef
    spread = np.maximum(1.4826 * np.median(np.abs(rest - np.median(rest, axis=0)), axis=0), MIN_SPREAD)
    if ch > 1:
        _, vecs = np.linalg.eigh(np.cov((rest / spread).T))
        d = vecs[:, -1] / spread
    else:
        d = 1.0 / spread
    u = rest @ d
    p5, p95 = np.percentile(u, (5, 95))
    middle = u[(u > p5) & (u < p95)]
    if len(middle) < 40:  # a blank board: nothing between its 5th and 95th percentiles to split
        return None
    t = _otsu(middle)
    lo, hi = middle[middle < t], middle[middle >= t]
    if len(lo) < 20 or len(hi) < 20:
        return None
    ml, mh = float(np.median(lo)), float(np.median(hi))
    sl, sh = 1.4826 * np.median(np.abs(lo - ml)), 1.4826 * np.median(np.abs(hi - mh))
    if mh - ml < TONE_SPLIT * float(np.sqrt(0.5 * (sl * sl + sh * sh))):
        return None
    # each pixel's tone: what is left of it after the light, along d, smoothed a little (noise
    # must not hole a patch)
    yy = (np.arange(h, dtype=np.float32) / h - 0.5)[:, None, None]
    xx = (np.arange(w, dtype=np.float32) / w - 0.5)[None, :, None]
    c = coef.astype(np.float32)
    light = c[0] + xx * c[1] + yy * c[2] + xx * xx * c[3] + xx * yy * c[4] + yy * yy * c[5]
    tone = ndimage.uniform_filter((work - light) @ d.astype(np.float32), 3)
    low = (tone < t) & inside
    high = (tone >= t) & inside
    r = TONE_THICK_MM * wppm
    n = max(int(inside.sum()), 1)
    # the tone with fewer pixels first: where it has too few places deep inside it (most often,
    # as Otsu splits a board of one colour unevenly), the other need not be looked at
    first_low = int(low.sum()) <= int(high.sum())
    thick_first = _deep_in(low if first_low else high, r)
    if thick_first.sum() < TONE_SHARE * n:
        return None
    thick_second = _deep_in(high if first_low else low, r)
    if thick_second.sum() < TONE_SHARE * n:
        return None
    thick_low, thick_high = (thick_first, thick_second) if first_low else (thick_second, thick_first)
    patch_low = low & _near(thick_low, r)
    patch_high = high & _near(thick_high, r)
    lows, grid = _block_medians(work, wppm, ~thick_low)
    highs, _ = _block_medians(work, wppm, ~thick_high)
    both = ~np.isnan(lows[..., 0]) & ~np.isnan(highs[..., 0])
    if both.sum() < 3:
        return None
    # (a colour near black has no ratio to speak of: JPEG's black is 0, and a ratio to it would
    # make the lighter tone, where only the darker shows, brighter than white)
    ratio = np.median(np.maximum(highs[both], TONE_DARK) / np.maximum(lows[both], TONE_DARK), axis=0)
    lows = np.where(np.isnan(lows), highs / ratio, lows)
    highs = np.where(np.isnan(highs), lows * ratio, highs)
    a = _enlarged(_filled(lows), grid, work)
    b = _enlarged(_filled(highs), grid, work)
    nearer_low = ((work - a) ** 2).sum(axis=2) < ((work - b) ** 2).sum(axis=2)
    under = np.where((patch_low | (nearer_low & ~patch_high))[..., None], a, b)
    e = TONE_EDGE_MM * wppm
    edge = (_near(patch_low, e) | _near(patch_high, e)) & _near(~patch_low, e) & _near(~patch_high, e)
    if edge.any():
        seg = b[edge] - a[edge]
        f = np.clip(((work[edge] - a[edge]) * seg).sum(axis=1) / np.maximum((seg * seg).sum(axis=1), 1e-9), 0, 1)
        under[edge] = a[edge] + f[:, None] * seg
    return under


def _disc_of(radius: float, strict: bool) -> np.ndarray:
    """The pixels whose distance from the middle one is less than radius (strict), or no more."""
    n = int(np.floor(radius))
    y, x = np.mgrid[-n:n + 1, -n:n + 1]
    d2 = x * x + y * y
    return d2 < radius * radius if strict else d2 <= radius * radius


def _deep_in(mask: np.ndarray, radius: float) -> np.ndarray:
    """The pixels of mask whose nearest pixel not in it lies radius or more away (the frame's
    edge not counted as one): distance_transform_edt(mask) >= radius, as an erosion by a disc,
    several times quicker for a radius of a few pixels."""
    return _by_disc(mask, _disc_of(radius, True), True)


def _near(mask: np.ndarray, radius: float) -> np.ndarray:
    """The pixels within radius of a pixel of mask: distance_transform_edt(~mask) <= radius, as
    a dilation by a disc."""
    return _by_disc(mask, _disc_of(radius, False), False)


def _by_disc(mask: np.ndarray, disc: np.ndarray, erode: bool) -> np.ndarray:
    """mask eroded by the disc (what lies beyond the frame counted in the mask) or dilated by it,
    as scipy's binary_erosion and binary_dilation: row by row of the disc, each row a run of pixels
    (a minimum or maximum filter along the image's rows, one per run length), shifted by the row's
    offset and combined; two to three times quicker than the disc's many pixels taken one by one."""
    from scipy import ndimage

    h = mask.shape[0]
    n = disc.shape[0] // 2
    src = np.ascontiguousarray(mask, dtype=bool).view(np.uint8)
    along = ndimage.minimum_filter1d if erode else ndimage.maximum_filter1d
    runs: dict[int, np.ndarray] = {}
    out = np.full(mask.shape, erode, bool)
    for i, row in enumerate(disc):
        run, dy = int(np.count_nonzero(row)), i - n
        if not run or abs(dy) >= h:  # (a row wholly beyond the frame: the frame's edge, no change)
            continue
        if run not in runs:
            runs[run] = along(src, run, axis=1, mode="constant", cval=int(erode)).view(bool)
        m = runs[run]
        at, of = (out[:h - dy], m[dy:]) if dy >= 0 else (out[-dy:], m[:h + dy])
        if erode:
            at &= of
        else:
            at |= of
    return out


def _spread(diff: np.ndarray, outside: np.ndarray | None) -> np.ndarray:
    """Each channel's robust spread of a difference from the board (on the tray)."""
    sample = diff[::4, ::4].reshape(-1, diff.shape[2])
    if outside is not None and outside.any() and not outside.all():
        sample = sample[~outside[::4, ::4].ravel()]
    return 1.4826 * np.median(np.abs(sample), axis=0)


def _otsu(u: np.ndarray) -> float:
    """Otsu's threshold of the values u: the one of 128 bins that most separates the means of the
    two sides, weighted by their counts."""
    if not len(u) or u.min() == u.max():
        return float(u[0]) if len(u) else 0.0  # nothing to split
    hist, e = np.histogram(u, 128)
    c = 0.5 * (e[:-1] + e[1:])
    wsum = np.cumsum(hist)
    msum = np.cumsum(hist * c)
    W, M = wsum[-1], msum[-1]
    with np.errstate(divide="ignore", invalid="ignore"):
        between = (M * wsum / W - msum) ** 2 / (wsum * (W - wsum))
    return float(c[np.nanargmax(between[:-1])])


def shadow_free(con: Contrast, p: np.ndarray, b: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(F with what looks like the board in shadow counted as board, which points look so), given
    the image's colour p, the board's b and F at the same points.

    A shadow darkens the board and keeps its colour: a pixel that is SHADOW_LIGHT of the board's
    colour under it, give or take SHADOW_TINT (spreads) of other colour, is board in shadow; its
    contrast is then only that other colour. In a grey image every such darkening looks so."""
    light, tint = light_and_tint(con, p, b)
    shade = (light >= SHADOW_LIGHT[0]) & (light <= SHADOW_LIGHT[1]) & (tint < SHADOW_TINT)
    return np.where(shade, tint, f), shade


def light_and_tint(con: Contrast, p: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(light, tint) of the colours p over the board's b (each (N, channels)): the share of the
    board's light (p projected on b), and what other colour is left when b scaled to that light
    is taken out, in spreads (0 in a grey image)."""
    light = (p * b).sum(axis=1) / np.maximum((b * b).sum(axis=1), 1e-9)
    return light, np.sqrt((((p - light[:, None] * b) * con.unit) ** 2).sum(axis=1))


def bilinear(layers: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """The values of a (rows, cols) or (rows, cols, layers) array at N (row, col) points,
    interpolated linearly: (N,) or (N, layers). Points outside take the nearest edge's values
    (as map_coordinates' mode nearest); one gather serves every layer."""
    return _mix(layers, *_corners(layers.shape[0], layers.shape[1], pts))


def _corners(h: int, w: int, pts: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For bilinear() on an h x w grid: each point's top-left neighbour (flat index) and its
    fractional offsets from it (rows, cols); computed once, they serve several arrays."""
    r = np.minimum(np.maximum(pts[:, 0], 0.0), h - 1.0)  # (np.clip's values, at less cost)
    c = np.minimum(np.maximum(pts[:, 1], 0.0), w - 1.0)
    r0 = np.minimum(r.astype(np.intp), h - 2)
    c0 = np.minimum(c.astype(np.intp), w - 2)
    return r0 * w + c0, (r - r0).astype(np.float32), (c - c0).astype(np.float32)


def _mix(layers: np.ndarray, i: np.ndarray, fr: np.ndarray, fc: np.ndarray) -> np.ndarray:
    h, w = layers.shape[:2]
    at = (i, i + 1, i + w, i + w + 1)  # the four neighbours, gathered once from the flattened layers
    if layers.ndim == 3:
        fr, fc = fr[:, None], fc[:, None]
        rows = layers.reshape(h * w, -1)
        a, b, c, d = (rows.take(j, axis=0) for j in at)
    else:
        flat = layers.reshape(-1)
        a, b, c, d = (flat.take(j) for j in at)
    gc = 1 - fc
    return (a * gc + b * fc) * (1 - fr) + (c * gc + d * fc) * fr


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


