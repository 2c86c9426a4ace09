"""The ridge finder's centre lines: multi-scale ridges of the contrast (the Hessian of a
Gaussian), hysteresis, and thinning to one-pixel lines."""
from __future__ import annotations

import numpy as np

SCALES_MM = (0.35, 0.7, 1.2)  # Gaussian sigmas matched to wire diameters ~0.8, 1.6 and 3 mm
MIN_SIGMA_PX = 0.8  # below this a Gaussian on the working grid is no longer one
RIDGE_HIGH = 2.0  # hysteresis on the ridge strength, in units of the contrast's spread
RIDGE_LOW = 0.9
FAINT_SHARE = 0.85  # a picture with no ridge at RIDGE_HIGH (a two-tone board's pattern makes the spread the tones'
FAINT_FLOOR = 1.4  # difference): the high threshold falls to this share of its strongest ridge, not below the floor
MIN_LINE_MM = 10.0  # shorter centre-line pieces are noise, texture or too short to take
HOLE_PX = 4  # a ring round a hole of no more pixels than this may hide a line's end (end_rings)
# 8-neighbour offsets (row, col), clockwise from E
NEIGHBOURS = ((0, 1), (1, 1), (1, 0), (1, -1), (0, -1), (-1, -1), (-1, 0), (-1, 1))


def ridges(f: np.ndarray, wppm: float) -> tuple[np.ndarray, list, np.ndarray, list]:
    """(strength, smoothed, scale, each): the best scale's ridge strength of F at each pixel
    (-sigma^2 times the Hessian's most negative eigenvalue), F smoothed at each scale, the index
    of the best scale per pixel, and each scale's strength, finest first (the finest marks thin
    conductors)."""
    from scipy import ndimage

    best = np.zeros_like(f)
    which = np.zeros(f.shape, np.uint8)
    grr = np.zeros_like(f)
    gcc = np.zeros_like(f)
    grc = np.zeros_like(f)
    each = []
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
        each.append(strength)
        if n == 0:
            best = strength.copy()
        else:
            better = strength > best
            np.maximum(best, strength, out=best)
            which[better] = n
    return best, smoothed, which, each


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


def centre_lines(strength: np.ndarray, smoothed: list, which: np.ndarray, wppm: float,
                 each: list | None = None) -> np.ndarray:
    """The ridges' centre lines: non-maximum suppression across each ridge, hysteresis, thinning.
    Given each scale's strength, a wire where this finds no line is looked for again by each
    pixel's own scale (see below)."""
    h, w = strength.shape
    W = w + 2
    flat = np.pad(strength, 1).ravel()
    cand = np.flatnonzero(flat > RIDGE_LOW)
    rows, cols = np.divmod(cand, W)
    ok = (rows >= 1) & (rows <= h) & (cols >= 1) & (cols <= w)
    cand, rows, cols = cand[ok], rows[ok] - 1, cols[ok] - 1
    # the neighbour across the ridge, the normal rounded to one of the 8 directions
    nr, nc = normals(smoothed, which, rows, cols)
    step = np.rint(nr * 1.2).clip(-1, 1).astype(np.int64) * W + np.rint(nc * 1.2).clip(-1, 1).astype(np.int64)
    top = float(strength.max())
    high = RIDGE_HIGH if top >= RIDGE_HIGH else max(FAINT_FLOOR, FAINT_SHARE * top)  # rather than see nothing
    keep = _crest(flat, cand, step)
    lines = _strong(_mask(rows[keep], cols[keep], (h, w)), strength, high, wppm)
    if each is not None:
        # The best strength over the scales has no crest across a wide wire whose contrast is
        # highest at its edges or in its stripes (a white wire's dark flanks, a striped wire):
        # off its centre the finest scale answers as strongly as a coarse one at it, and the
        # suppression above leaves scattered pixels, too short to be a line. Compared at each
        # pixel's own scale, the crest is there. Only where no line was found (more than 2 px
        # from one): used everywhere, it rescued four wires on trays 4000-4799 but moved lines
        # elsewhere, and five picks became fouls and five misses.
        rest = ~_near(lines, 2)[rows, cols]
        cand, rows, cols, step = cand[rest], rows[rest], cols[rest], step[rest]
        own = np.zeros(len(cand), bool)
        scale = which[rows, cols]
        for n, s in enumerate(each):
            m = scale == n
            if m.any():
                own[m] = _crest(np.pad(s, 1).ravel(), cand[m], step[m])
        if (strength[rows[own], cols[own]] > high).any():
            lines |= _strong(_mask(rows[own], cols[own], (h, w)), strength, high, wppm)
    # a ridge's end may fork round a pixel (a rounded cap): fill such one-pixel holes, or thinning
    # keeps them as a tiny loop and the end is lost
    hole = ~lines[1:-1, 1:-1] & lines[:-2, 1:-1] & lines[2:, 1:-1] & lines[1:-1, :-2] & lines[1:-1, 2:]
    lines[1:-1, 1:-1] |= hole
    return minimal(thin_sparse(lines))


def end_rings(lines: np.ndarray) -> np.ndarray:
    """The thinned lines with each ring round a hole of up to HOLE_PX pixels filled and thinned
    again where that gives a line an end the ring had hidden: a wire's end whose ridge forked
    there. Rings with no end once filled (a ladder of them along a wire with a specular line, a
    loop) are left as they are."""
    from scipy import ndimage

    holes, n = ndimage.label(~lines)  # (4-connected: the lines are 8-connected)
    small = np.bincount(holes.ravel(), minlength=n + 1) <= HOLE_PX
    small[0] = False
    small[np.concatenate([holes[0], holes[-1], holes[:, 0], holes[:, -1]])] = False  # (open to the frame)
    if not small.any():
        return lines
    ring = small[holes]
    filled = minimal(thin_sparse(lines | ring))
    kernel = np.ones((3, 3))
    kernel[1, 1] = 0

    def ends(mask: np.ndarray) -> np.ndarray:
        return mask & (ndimage.convolve(mask.astype(np.uint8), kernel, mode="constant") == 1)

    before, after = ends(lines), ends(filled)
    out = lines.copy()
    h, w = lines.shape
    for box in ndimage.find_objects(ndimage.label(ring, np.ones((3, 3)))[0]):
        win = (slice(max(box[0].start - 3, 0), min(box[0].stop + 3, h)),
               slice(max(box[1].start - 3, 0), min(box[1].stop + 3, w)))
        if after[win].any() and not before[win].any():
            out[win] = filled[win]
    return out


def _crest(flat: np.ndarray, cand: np.ndarray, step: np.ndarray) -> np.ndarray:
    """Which candidates (flat indices into a padded grid) are a crest across the ridge: no less
    than the neighbour one step across it, more than the one the other way."""
    v = flat[cand]
    return (v >= flat[cand + step]) & (v > flat[cand - step])


def _near(mask: np.ndarray, r: int) -> np.ndarray:
    """The pixels within r (rows and columns both) of a set pixel of mask: a dilation that costs
    what the set pixels do."""
    h, w = mask.shape
    rows, cols = np.nonzero(mask)
    near = np.zeros((h + 2 * r, w + 2 * r), bool)
    for dr in range(2 * r + 1):
        for dc in range(2 * r + 1):
            near[rows + dr, cols + dc] = True
    return near[r:h + r, r:w + r]


def _mask(rows: np.ndarray, cols: np.ndarray, shape: tuple) -> np.ndarray:
    """A mask of the given shape set at the given pixels."""
    mask = np.zeros(shape, bool)
    mask[rows, cols] = True
    return mask


def _strong(peak: np.ndarray, strength: np.ndarray, high: float, wppm: float) -> np.ndarray:
    """Hysteresis: the 8-connected pieces of peak that reach high somewhere and are long enough
    to be a line."""
    from scipy import ndimage

    labels, n = ndimage.label(peak, np.ones((3, 3)))
    if n == 0:
        return peak
    strong = np.zeros(n + 1, bool)
    strong[np.unique(labels[peak & (strength > high)])] = True
    size = np.bincount(labels.ravel(), minlength=n + 1)
    strong &= size >= MIN_LINE_MM * wppm * 0.7
    strong[0] = False
    return strong[labels]


def small_holes(mask: np.ndarray) -> np.ndarray:
    """Holes of one or two pixels (side by side) that the set pixels of mask close round (their
    4-neighbours outside the hole all set): thinning may leave such a ring where a ridge's end
    forks, and then that line has no end pixel."""
    hole = np.zeros_like(mask)
    m = np.pad(mask, 2)
    h, w = mask.shape

    def at(dr: int, dc: int) -> np.ndarray:
        return m[2 + dr:2 + dr + h, 2 + dc:2 + dc + w]

    free = ~mask
    hole |= free & at(-1, 0) & at(1, 0) & at(0, -1) & at(0, 1)
    for dr, dc in ((1, 0), (0, 1)):  # this pixel and the one below it, or right of it
        pair = free & ~at(dr, dc) & at(-dr, -dc) & at(2 * dr, 2 * dc)
        for side in (-1, 1):
            pair &= at(dc * side, dr * side) & at(dr + dc * side, dc + dr * side)
        hole |= pair
        hole[dr:, dc:] |= pair[:h - dr, :w - dc]
    return hole


def minimal(mask: np.ndarray) -> np.ndarray:
    """The thinned lines with their corners cut: a pixel whose two 4-neighbours at a right angle
    are joined diagonally anyway, and that has nothing on the far side, is dropped. Thinning may
    leave such a pixel as a little triangle where lines meet or a ridge end forks, and that reads
    as a crossing."""
    h, w = mask.shape
    grid = np.pad(mask, 1).ravel()
    _cut_corners(grid, w + 2)
    _trim_crosses(grid, w + 2)
    return grid.reshape(h + 2, w + 2)[1:-1, 1:-1].copy()


def _trim_crosses(grid: np.ndarray, W: int) -> None:
    """In place: a pixel whose four edge neighbours are set and whose diagonals are not (a small
    cross, which pruning a ridge end's forked whiskers leaves, or thinning) loses those of the four
    that are stubs (nothing else beside them), but for the stub straight opposite a line's only
    arm: that stub is the line's end. Without this a cross has no end pixel and a wire's end on it
    is never read, and its stubs beside a line read as a crossing."""
    arms = (-W, 1, W, -1)  # N, E, S, W
    diagonals = (-W - 1, -W + 1, W - 1, W + 1)
    on = np.flatnonzero(grid)
    centre = np.ones(len(on), bool)
    for o in arms:
        centre &= grid[on + o]
    for o in diagonals:
        centre &= ~grid[on + o]
    around = [dr * W + dc for dr, dc in NEIGHBOURS]
    for c in on[centre]:
        cross = {c, *(c + a for a in arms)}
        # an arm is a stub when nothing beside it lies beyond the cross
        stub = [not any(grid[c + a + d] for d in around if c + a + d not in cross) for a in arms]
        lines = [a for a, st in zip(arms, stub) if not st]
        if not lines:
            continue  # a cross on its own: too short to be read anyway
        for a, st in zip(arms, stub):
            if st and not (len(lines) == 1 and a == -lines[0]):
                grid[c + a] = False


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
    from ..binary import NEIGHBOURS as PAPER_NEIGHBOURS  # the paper's thinning, where it lives
    from ..binary import deletion_tables

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


