"""The paper's binary vision system: threshold, thin, and read wire ends off the skeleton.

1. Block averaging by k x k (k = 4 for a 512 image at 4 px/mm: 128 x 128, about 1 px/mm).
2. The threshold is the mean grey level at the zero crossings of the image's
   Laplacian of Gaussian: the level half way up the wires' edges.
3. Polarity: the wires are the minority class (dark on light or light on dark).
4. Thinning: passes that each remove the border pixels of one orientation (N, S,
   E, W in turn), never a critically connected pixel nor an arc end, until four
   passes in a row change nothing. Each pass is a lookup in a 256-entry table
   indexed by the 3x3 neighbourhood (thin()).
5. Skeleton analysis: arc ends whose first GRASP_MM + 3 mm of skeleton meet no
   crossing and do not touch the image border; the grasp point GRASP_MM along
   the skeleton, the wire's tangent there, the end's direction, and the
   clearance to the neighbouring wires across the grasp point.

Deviations (each needed on harder scenes; docs/vision.md says why): critical
connectivity is Hilditch's 8-connected crossing number, not the paper's printed
expression (papers_expression), which cuts thin lines; the Laplacian's sigma is
0.7 averaged pixels, not 2, and only zero crossings with a real edge count
(log_threshold); spurs shorter than SPUR_MM are pruned; the block size follows
the scale; the end is the far edge of the mask nearest the skeleton's end (the
thinning wears thick ends away), refined at full resolution (across the wire's
middle, at the half level between the wire and the tray beyond it), with a
stripped conductor's tip beyond it; the directions are fitted over 2 * END_PX
skeleton points and TANGENT_PX either side of the grasp point instead of the
paper's 3 and 2 (at ~1 mm a pixel those quantise to tens of degrees); nothing but
the wire may lie within FINGER_CLEARANCE_MM of the grasp point, on any side; and along
the end's first TOUCH_SPAN_MM, the mask TOUCH_PX past the wire's half width must be its
own (another wire, or the wire looping back, may lie against its end and merge with it in
the mask, the skeleton running on without a crossing).
"""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from ..camera.images import as_grey
from .common import (
    FINGER_CLEARANCE_MM,
    FRAME_MARGIN_MM,
    GRASP_MM,
    Clock,
    block_average,
    conductor_tip,
    principal_direction,
    to_input,
    tray_level,
)
from .sighting import Sighting

SPUR_MM = 3.0
EDGE_FACTOR = 4.0
TANGENT_PX = 4  # the paper takes +-2 skeletal points; at ~1 mm per pixel that quantises to tens of degrees
END_PX = 4  # likewise the end direction: fitted over the first 8 px (the paper: from the end to 3 px in)
BORDER_PX = 2  # skeleton ends this close to the border of the averaged image are cut by it
TOUCH_SPAN_MM = GRASP_MM + 5.0  # along the end's first 20 mm (the ground truth's span), the mask
TOUCH_PX = 1.5  # ... this far past the wire's half width must be the wire's own

# The 3x3 neighbours, numbered as in the paper: 1 = E, then anticlockwise to 8 = SE.
# (row, column) offsets; rows grow downwards, so N is row - 1.
NEIGHBOURS = ((0, 1), (-1, 1), (-1, 0), (-1, -1), (0, -1), (1, -1), (1, 0), (1, 1))


def critically_connected(code: int) -> bool:
    """Whether deleting the centre pixel would split its neighbours (8-connected) apart.

    x1..x8 are the neighbours (1 = E, anticlockwise). This is Hilditch's crossing
    number: the count of k in 1, 3, 5, 7 with x_k clear and x_k+1 or x_k+2 set,
    critical when two or more. (A deviation: papers_expression() below, the
    paper's printed sum of products with its last term corrected, treats E and N
    as joined only through NE; used as the thinning criterion it lets a pass cut
    one-pixel diagonal and straight lines, since it has no term for a pixel whose
    neighbours are NE and SW only, or N and S only.)
    """
    x = [code >> k & 1 for k in range(8)] + [code & 1]  # x[0] = neighbour 1 (E); x[8] wraps to it
    crossings = sum(1 for k in (0, 2, 4, 6) if not x[k] and (x[k + 1] or x[k + 2]))
    return crossings >= 2


def papers_expression(code: int) -> bool:
    """The paper's Boolean expression for a critically connected pixel, its last term
    corrected: 1(3+4+5+6+7)~2~8 + 3(5+6+7+8+1)~4~2 + 5(7+8+1+2+3)~6~4 + 7(1+2+3+4+5)~6~8."""
    x = [None] + [code >> (k - 1) & 1 for k in range(1, 9)]

    def term(a: int, some: tuple, b: int, c: int) -> bool:
        return bool(x[a] and any(x[k] for k in some) and not x[b] and not x[c])

    return (term(1, (3, 4, 5, 6, 7), 2, 8) or term(3, (5, 6, 7, 8, 1), 4, 2)
            or term(5, (7, 8, 1, 2, 3), 6, 4) or term(7, (1, 2, 3, 4, 5), 6, 8))


@lru_cache(maxsize=1)
def deletion_tables() -> np.ndarray:
    """(4, 256) booleans: for the orientations N, S, E, W, whether a pixel with that
    neighbourhood is a border pixel of the orientation that may be deleted."""
    outside = {"N": 3, "S": 7, "E": 1, "W": 5}  # the neighbour that must be background
    tables = np.zeros((4, 256), bool)
    for code in range(256):
        count = bin(code).count("1")
        if count < 2 or critically_connected(code):
            continue  # arc ends and isolated points stay; so do critically connected pixels
        for i, side in enumerate("NSEW"):
            tables[i, code] = not code >> (outside[side] - 1) & 1
    return tables


def neighbour_codes(mask: np.ndarray) -> np.ndarray:
    """For each pixel, the 8-bit code of its neighbours (bit k-1 set when neighbour k is)."""
    padded = np.pad(mask, 1).astype(np.uint8)
    h, w = mask.shape
    code = np.zeros((h, w), np.uint8)
    for k, (dr, dc) in enumerate(NEIGHBOURS):
        code |= padded[1 + dr:1 + dr + h, 1 + dc:1 + dc + w] << k
    return code


def thin(mask: np.ndarray, max_passes: int = 400) -> np.ndarray:
    """The paper's thinning of a binary image to 8-connected arcs one pixel wide."""
    tables = deletion_tables()
    skeleton = mask.astype(bool).copy()
    quiet = 0
    for p in range(max_passes):
        table = tables[p % 4]
        remove = skeleton & table[neighbour_codes(skeleton)]
        if remove.any():
            skeleton &= ~remove
            quiet = 0
        else:
            quiet += 1
            if quiet == 4:
                break
    return skeleton


def log_threshold(image: np.ndarray, sigma: float = 0.7) -> float:
    """The mean grey level at the zero crossings of the Laplacian of Gaussian.

    Only crossings with a real edge count: a flat, noisy tray crosses zero
    everywhere, and those crossings would pull the mean to the tray's own level
    (a deviation from the paper, needed on noisy images): a crossing counts when
    the Laplacian's jump across it is above EDGE_FACTOR times the median jump.
    """
    from scipy import ndimage

    lap = ndimage.gaussian_laplace(image, sigma)
    sign = lap > 0
    jump = np.zeros_like(lap)
    h = (sign[:, :-1] != sign[:, 1:])
    v = (sign[:-1, :] != sign[1:, :])
    jh = np.abs(lap[:, :-1] - lap[:, 1:]) * h
    jv = np.abs(lap[:-1, :] - lap[1:, :]) * v
    jump[:, :-1] = np.maximum(jump[:, :-1], jh)
    jump[:-1, :] = np.maximum(jump[:-1, :], jv)
    crossings = jump > 0
    if not crossings.any():
        return float(image.mean())
    strong = jump > EDGE_FACTOR * np.median(jump[crossings])
    if not strong.any():
        return float(image.mean())
    return float(image[strong].mean())


class BinaryResult:
    """What the binary system saw: candidates best-first, the stages' times, and its pictures."""

    def __init__(self) -> None:
        self.candidates: list[Sighting] = []
        self.timings: dict[str, float] = {}
        self.mask: np.ndarray | None = None
        self.skeleton: np.ndarray | None = None
        self.scale = 1  # averaged pixels per input pixel
        self.dark_wires = True


def find_wires_binary(image: np.ndarray, px_per_mm: float = 4.0) -> BinaryResult:
    """Graspable wire ends in an image (any size; px_per_mm gives the scale)."""
    result = BinaryResult()
    clock = Clock(result.timings)
    grey = as_grey(image)
    k = max(1, int(round(px_per_mm)))
    small = block_average(grey, k)
    result.scale = k
    clock("average")
    if small.shape[0] < 8 or small.shape[1] < 8 or float(small.std()) < 1e-3:
        return result  # too small, or no contrast at all: nothing to see
    t = log_threshold(small)
    below = small < t
    dark = bool(below.mean() < 0.5)  # the wires are the smaller class
    mask = below if dark else ~below
    result.dark_wires = dark
    result.mask = mask
    clock("threshold")
    skeleton = thin(mask)
    clock("thin")
    skeleton = _prune_spurs(skeleton, max(1, int(round(SPUR_MM * px_per_mm / k))))
    result.skeleton = skeleton
    clock("prune")
    mm = k / px_per_mm  # mm per averaged pixel
    looks = _FullImage(grey, t, dark)
    result.candidates = _analyse(skeleton, mask, mm, k, looks, px_per_mm)
    clock("analyse")
    result.timings["total"] = sum(result.timings.values())
    return result


def _neighbour_count(skeleton: np.ndarray) -> np.ndarray:
    codes = neighbour_codes(skeleton)
    return _POPCOUNT[codes] * skeleton


_POPCOUNT = np.array([bin(i).count("1") for i in range(256)], np.uint8)


def _trace(skeleton: set, start: tuple[int, int], limit: int) -> tuple[list[tuple[int, int]], bool]:
    """Follow the skeleton (a set of (row, column)) from an end for up to limit pixels:
    (path, reached a crossing)."""
    path = [start]
    seen = {start}
    r, c = start
    for _ in range(limit):
        nxt = [p for p in ((r + dr, c + dc) for dr, dc in NEIGHBOURS) if p in skeleton and p not in seen]
        if not nxt:
            return path, False
        if len(nxt) > 1:
            # an edge neighbour and the diagonal next to it are one step of the same arc
            edge = [p for p in nxt if abs(p[0] - r) + abs(p[1] - c) == 1]
            if len(nxt) == 2 and len(edge) == 1 and max(abs(nxt[0][0] - nxt[1][0]), abs(nxt[0][1] - nxt[1][1])) == 1:
                nxt = edge
            else:
                return path, True
        r, c = nxt[0]
        path.append((r, c))
        seen.add((r, c))
    return path, False


def _prune_spurs(skeleton: np.ndarray, length: int) -> np.ndarray:
    """Remove short branches that end at a crossing: the thinning's whiskers."""
    sk = skeleton.copy()
    pixels = set(zip(*(a.tolist() for a in np.nonzero(sk))))
    counts = _neighbour_count(sk)
    for r, c in zip(*(a.tolist() for a in np.nonzero(counts == 1))):
        path, crossing = _trace(pixels, (r, c), length)
        if crossing and len(path) <= length:
            for p in path:
                sk[p] = False
                pixels.discard(p)
    return sk


class _FullImage:
    """The full-resolution image, to place a wire's end exactly (the averaged image is ~1 mm/px)."""

    def __init__(self, grey: np.ndarray, threshold: float, dark: bool) -> None:
        self.grey = grey
        self.threshold = threshold
        self.dark = dark
        self.tray, noise = tray_level(grey, 4)
        self.shine = max(4 * noise, 0.05)

    def extend_end(self, u: float, v: float, du: float, dv: float, limit_px: float, width: float) -> float:
        """How far (px) the wire goes on beyond (u, v) in the direction (du, dv); less than
        0 when it ends before that point.

        The wire is read across its middle half (the darkest, or for light wires the
        lightest, of three lines along it), so a glossy wire's highlight does not end it.
        The global threshold gives a first end; the end is then where the grey first
        crosses half way between the wire (a width inside) and the tray just beyond that
        first end: the global threshold can lie on the wrong side of a wire's soft shadow
        or of uneven light."""
        span = max(width, 2.0)
        s = np.arange(-1.5 * span, limit_px, 0.5)
        g, inside = self._band(u, v, du, dv, s, width)
        first = self._run_end(s, g, inside, self.threshold, s >= 0.5)
        if first is None:
            return 0.0
        interior = g[(s >= -1.5 * span) & (s <= -0.5 * span)]
        beyond = g[(s >= first + 1.0) & (s <= first + span) & inside]
        if not interior.size or not beyond.size:
            return first
        level_in = float(interior.min()) if self.dark else float(interior.max())
        level_out = float(beyond.max()) if self.dark else float(beyond.min())
        refined = self._run_end(s, g, inside, 0.5 * (level_in + level_out), s >= -0.5 * span)
        return first if refined is None else refined

    def _run_end(self, s: np.ndarray, g: np.ndarray, inside: np.ndarray, level: float, start: np.ndarray):
        """The last wire sample before 1.5 px of background begin (anti-aliased edges leave
        single gaps), counting from the first sample where start holds; None if the line
        starts on background."""
        wire = (g < level if self.dark else g > level) & inside
        i0 = int(np.argmax(start))
        wire = wire[i0:]
        run = np.convolve(~wire, np.ones(3, int), mode="valid") == 3
        stop = int(np.argmax(run)) if run.any() else len(wire)
        on = np.flatnonzero(wire[:stop])
        return float(s[i0 + on[-1]]) if on.size else None

    def _band(self, u: float, v: float, du: float, dv: float, s: np.ndarray, width: float):
        """The grey along a line, the darkest (light wires: lightest) of three parallel
        lines 0.25 of the wire's width apart; and which samples lie inside the image."""
        h, w = self.grey.shape
        best, inside = None, None
        for off in (-0.25 * width, 0.0, 0.25 * width):
            cols = np.round(u + s * du - off * dv).astype(int)
            rows = np.round(v + s * dv + off * du).astype(int)
            ok = (cols >= 0) & (cols < w) & (rows >= 0) & (rows < h)
            g = np.where(ok, self.grey[np.clip(rows, 0, h - 1), np.clip(cols, 0, w - 1)], self.tray)
            if best is None:
                best, inside = g, ok
            else:
                best = np.minimum(best, g) if self.dark else np.maximum(best, g)
                inside &= ok
        return best, inside


def _analyse(skeleton: np.ndarray, mask: np.ndarray, mm: float, k: int, looks: _FullImage,
             px_per_mm: float) -> list[Sighting]:
    h, w = skeleton.shape
    need = int(math.ceil((GRASP_MM + 3.0) / mm))
    counts = _neighbour_count(skeleton)
    pixels = set(zip(*(a.tolist() for a in np.nonzero(skeleton))))
    out = []
    nearest = _nearest_skeleton(skeleton, mask)
    from scipy import ndimage

    inside = ndimage.distance_transform_edt(mask)  # half the wire's width, on its skeleton
    reach_px = int(math.ceil(FINGER_CLEARANCE_MM / mm)) + 2
    disc = _within(FINGER_CLEARANCE_MM / mm + 0.5)
    for r, c in zip(*(a.tolist() for a in np.nonzero(counts == 1))):
        if r < BORDER_PX or c < BORDER_PX or r >= h - BORDER_PX or c >= w - BORDER_PX:
            continue  # an edge is not a wire end
        path, _ = _trace(pixels, (r, c), need + reach_px)
        if len(path) <= need:
            continue  # a crossing, or the other end, within GRASP_MM + 3 mm
        # the wire's axis near the end, fitted past the end's last few (worn) skeleton points
        near = np.array(path[:2 * END_PX], float)  # (row, column)
        centre = near.mean(axis=0)
        axis = principal_direction(near)
        if (np.array([r, c]) - centre) @ axis < 0:
            axis = -axis  # pointing out of the wire, past the end
        dv, du = float(axis[0]), float(axis[1])
        # thinning wears a thick wire's end away: the end of the wire is the far edge of the
        # part of the mask that lies nearer this skeleton end than any other skeleton point
        cap = np.flatnonzero(nearest == r * w + c)
        reach = float(max(((cap // w - centre[0]) * dv + (cap % w - centre[1]) * du).max(), 0.0)) if cap.size else 0.0
        reach = max(reach - 1.5, 0.0)  # from safely inside the wire, at full resolution:
        u0, v0 = to_input((centre[0] + reach * dv, centre[1] + reach * du), k).tolist()
        width = 2.0 * float(np.median(inside[tuple(np.array(path[:2 * END_PX]).T)])) * k
        beyond = looks.extend_end(u0, v0, du, dv, limit_px=10.0 * px_per_mm, width=width)
        end_uv = (u0 + beyond * du, v0 + beyond * dv)
        if looks.dark:  # a stripped conductor or ferrule beyond the insulation: the end is its tip
            tip = conductor_tip(looks.grey, np.array(end_uv[::-1]), np.array([dv, du]), width, px_per_mm,
                                looks.tray + looks.shine)
            if tip is False:
                continue
            if tip is not None:
                end_uv = (float(tip[1]), float(tip[0]))
                inward = np.array([u0 - end_uv[0], v0 - end_uv[1]])
                du, dv = -inward / max(float(np.linalg.norm(inward)), 1e-9)
        margin = FRAME_MARGIN_MM * px_per_mm  # a deviation from the paper (docs/vision.md): it looked at the border only
        if not (margin <= end_uv[0] < looks.grey.shape[1] - margin and margin <= end_uv[1] < looks.grey.shape[0] - margin):
            continue  # the wire runs on to the border, or may: not an end
        span = np.array(path[:need], float)
        if (span.min() < FRAME_MARGIN_MM / mm or span[:, 0].max() >= h - FRAME_MARGIN_MM / mm
                or span[:, 1].max() >= w - FRAME_MARGIN_MM / mm):
            continue  # the wire near its end may leave the picture and come back: not seen whole
        # how far the end lies beyond the skeleton's end, along the wire
        ru, rv = to_input((r, c), k).tolist()
        beyond_mm = ((end_uv[0] - ru) * du + (end_uv[1] - rv) * dv) / px_per_mm
        steps = np.hypot(*np.diff(np.array(path), axis=0).T)  # diagonal steps are sqrt(2) long
        arc = np.concatenate([[0.0], np.cumsum(steps)]) * mm
        g = int(np.searchsorted(arc, max(GRASP_MM - beyond_mm, 1.0)))
        if g + TANGENT_PX >= len(path):
            continue
        grasp = path[g]
        if min(grasp) < BORDER_PX or grasp[0] >= h - BORDER_PX or grasp[1] >= w - BORDER_PX:
            continue
        t = principal_direction(np.array(path[max(g - TANGENT_PX, 0):g + TANGENT_PX + 1], float))
        tangent = math.degrees(math.atan2(t[0], t[1])) % 180.0
        end_angle = math.degrees(math.atan2(-dv, -du))
        clearance = _clearance(mask, grasp, tangent) * mm
        if clearance < FINGER_CLEARANCE_MM:
            continue
        own = {p[0] * w + p[1] for p in path[max(g - reach_px - 2, 0):]}
        if _other_wire_near(mask, nearest, width / (2 * k), grasp, disc, own):
            continue
        if _touched(mask, nearest, width / (2 * k), path, arc):
            continue  # another wire, or this one looping back, touches it near its end
        out.append(Sighting(end_uv, end_angle, tuple(to_input(grasp, k).tolist()), tangent, score=clearance))
    out.sort(key=lambda s: -s.score)
    return out


def _nearest_skeleton(skeleton: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """For each mask pixel, the flat index of the nearest skeleton pixel (-1 off the mask)."""
    from scipy import ndimage

    if not skeleton.any():
        return np.full(mask.size, -1)
    _, (rows, cols) = ndimage.distance_transform_edt(~skeleton, return_indices=True)
    return np.where(mask, rows * mask.shape[1] + cols, -1).ravel()


def _other_wire_near(mask: np.ndarray, nearest: np.ndarray, half: float, at: tuple[int, int],
                     disc: np.ndarray, own: set) -> bool:
    """Whether anything but this wire (its skeleton pixels own) comes within the disc round a
    grasp point: the fingers close from any side, not only straight across. A mask pixel
    is this wire's when its nearest skeleton pixel is one of own and it lies no farther from
    it than the wire's half width (half, measured near the end) and a pixel: a neighbour
    that merges with the wire in the mask bulges out past that."""
    w = mask.shape[1]
    pts = _on_mask(mask, disc + np.array(at))
    near = nearest[pts[:, 0] * w + pts[:, 1]]
    for (pr, pc), i in zip(pts.tolist(), near.tolist()):
        if i not in own:
            return True
        sr, sc = divmod(i, w)
        if math.hypot(pr - sr, pc - sc) > half + 1.0:
            return True
    return False


def _touched(mask: np.ndarray, nearest: np.ndarray, half: float, path: list, arc: np.ndarray) -> bool:
    """Whether something touches the wire along its first TOUCH_SPAN_MM from its end (path, the
    skeleton from the end, arc: mm along it): a mask pixel within the wire's half width and
    TOUCH_PX of that stretch whose nearest skeleton pixel is not on it (nor within that reach
    past it): another wire merged with it in the mask, or the same wire further on, looping
    back to lie against its end."""
    w = mask.shape[1]
    reach = half + TOUCH_PX
    m = max(int(np.count_nonzero(arc <= TOUCH_SPAN_MM)), 1)
    pts = _on_mask(mask, (np.array(path[:m])[:, None, :] + _within(reach)[None, :, :]).reshape(-1, 2))
    own = np.array([r * w + c for r, c in path[:m + int(math.ceil(reach)) + 1]])
    return bool(not np.isin(nearest[pts[:, 0] * w + pts[:, 1]], own).all())


def _within(radius: float) -> np.ndarray:
    """The (row, column) offsets of the pixels within radius of the origin, row by row."""
    n = int(math.ceil(radius))
    return np.argwhere(np.hypot(*np.mgrid[-n:n + 1, -n:n + 1]) <= radius) - n


def _on_mask(mask: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """The (row, column) points that lie inside the image and on the mask."""
    h, w = mask.shape
    pts = pts[(pts[:, 0] >= 0) & (pts[:, 0] < h) & (pts[:, 1] >= 0) & (pts[:, 1] < w)]
    return pts[mask[pts[:, 0], pts[:, 1]]]


def _clearance(mask: np.ndarray, at: tuple[int, int], tangent_deg: float, reach: int = 40) -> float:
    """Free pixels on the nearer side across the wire at a point (past the wire's own width)."""
    t = math.radians(tangent_deg + 90.0)
    dr, dc = math.sin(t), math.cos(t)
    h, w = mask.shape
    sides = []
    for sign in (1, -1):
        free, left_wire = 0, False
        for step in range(1, reach):
            rr = int(round(at[0] + sign * step * dr))
            cc = int(round(at[1] + sign * step * dc))
            if not (0 <= rr < h and 0 <= cc < w):
                break
            if mask[rr, cc]:
                if left_wire:
                    break
                continue
            left_wire = True
            free += 1
        sides.append(free if left_wire else 0)
    return float(min(sides))


