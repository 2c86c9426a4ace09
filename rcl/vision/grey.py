"""The paper's grey-scale vision system: follow wire boundaries, read wire ends off them.

(About 600 lines, over the ~500 we hold modules to: it is kept whole so that it reads top to
bottom as the paper's seven steps below, each a function or method named for its step.)

1. 2 x 2 averaging (512 x 512 -> 256 x 256, about 2 px/mm: the working image) and
   a further 4 x 4 averaging to a 64 x 64 image for planning.
2. Prewitt edges (edges()): magnitude and direction at any point of the working image.
3. The interest operator: the planning image is divided 4 x 4 and its regions are
   visited in order of how much edge they hold, fewest first, skipping regions
   with none: uncluttered areas that still contain wire come first.
4. Dynamic contour following (_Tracer) from the strongest edge point of a region:
   each step goes to the neighbour, of the three ahead, with the largest edge
   magnitude whose edge direction agrees with the step (a change of direction of
   at most 45 degrees a step); over a gap the search looks in two zones 1 and 2 px
   further ahead; when the trace stops it resumes from the start point in reverse;
   the thick edge response normal to the boundary is suppressed as the trace
   passes, so no other trace runs along the same edge. The boundary is kept as a
   Freeman chain code.
5. The wire-end heuristic: a boundary segment of SEGMENT units whose direction at
   one end differs by 180 degrees (within END_TURN_TOL) from its direction at the
   other, with its end points at most GAP units apart: the boundary turning round
   a wire's end.
6. The isolation test: along both sides of the wire, from the end to past the
   grasp point, the edge magnitude normal to the boundary stays below the edge
   threshold for a finger's clearance: no other wire is near.
7. The end point and direction, the grasp point GRASP_MM along the wire and the
   wire's tangent there, from the centre line between the two sides.

Deviations (each needed on harder scenes, see docs/vision.md): the edge threshold is
set from the image's own noise (a robust estimate from the median edge magnitude)
rather than fixed; the isolation test uses the working image's edges, not the
64 x 64 image's (at 2 mm a pixel those cannot tell a finger's clearance); the two
sides of a candidate end must stay parallel and the wire's width constant to the
grasp point (a wire that merges with another is not free); a faint edge beside the
wire across which the grey goes on away from the wire's level is its shadow, not
another wire (SHADOW_EDGE), and in front of an end, its own blurred edge rising to a flat
tray is passed over before the isolation test looks there (END_BLUR_MM); an end whose boundary
turns round in front of a thinner, brighter continuation (a stripped conductor or
ferrule) is moved out to the conductor's tip; the unit lengths scale with the
working image's px/mm when an image is not 2 px/mm after averaging.
"""
from __future__ import annotations

import math
import time

import numpy as np

from ..camera.images import as_grey
from .common import GRASP_MM, Clock, block_average, conductor_tip, principal_direction, to_input, tray_level
from .sighting import Sighting

SPAN_MM = 20.0  # the length of wire, from the end, that must be free (grasp point + 5 mm)
CLEARANCE_MM = 4.5  # from the wire's centre to any other wire, at the grasp point: room for the fingers
FREE_MM = 0.5  # free tray needed beside the rest of the span (past the edge response), and beyond the end
WORK_PX_PER_MM = 2.0  # the working image's scale for a 512 image at 4 px/mm
SEGMENT = 20  # units (working px at 2 px/mm) of boundary in the wire-end heuristic
GAP = 5  # at most this far apart, the segment's two end points
END_TURN_TOL = 40.0  # degrees from an exact reversal that still count as one
ENOUGH = 3  # free ends to find before the search stops
EDGE_NOISE_FACTOR = 3.5  # edge threshold, in units of the noise's edge magnitude
SHADOW_EDGE = 0.2  # beside a wire, an edge fainter than this part of its own, going on away from its level, is its shadow
SIDES_PAST_MM = 4.0  # a wire's sides are followed this far past the span
SIDES_SLACK = 1.2  # ... and this much farther again, as the boundary is longer than the wire (steps, bends)
NEAR_MM = 3.0  # the wire's width is the median over this much either side of the grasp point (and the
# axis fit skips the first this-many mm, where the end face bends the sides)
AXIS_FIT_MM = 6.0  # the wire's axis near its end: fitted over this much of the centre line
MAX_WIDTH_MM = 4.0  # wider than this is no wire (the widest are 3 mm)
SPAN_SEEN = 0.95  # the centre line must reach this share of the span (pixel steps shorten it a little)
PARALLEL_TOL_PX = 1.5  # the sides are parallel while the width stays within this (px) of the wire's ...
PARALLEL_TOL_SHARE = 0.35  # ... or this share of it, whichever is more
TANGENT_MM = 3.0  # the tangent at the grasp point: over the centre line this far either side
BORDER_MM = 3.0  # the end and the span at least this far from the image's border
END_BLUR_MM = 2.0  # in front of an end, its own blurred edge is passed over for up to this far
END_FLAT = 0.2  # ... where past it the grey stays within this share of the step from the wire

# Freeman chain code directions: 0 = E, anticlockwise as seen on the screen (row - 1 is up).
STEPS = ((0, 1), (-1, 1), (-1, 0), (-1, -1), (0, -1), (1, -1), (1, 0), (1, 1))
PAD = 4  # the working image is padded with zero edge so traces stop at the border


class GreyResult:
    """What the grey-scale system saw: candidates best-first, stage times, and its boundaries."""

    def __init__(self) -> None:
        self.candidates: list[Sighting] = []
        self.timings: dict[str, float] = {}
        self.contours: list[np.ndarray] = []  # (N, 2) input-pixel (u, v) boundary points
        self.chains: list[tuple[tuple[int, int], bytes]] = []  # working (row, col) start and Freeman codes
        self.threshold = 0.0
        self.scale = 1  # input pixels per working pixel
        self.region_order: list[tuple[int, int]] = []  # planning regions (row, col) in visiting order
        self.looks: _Looks | None = None  # the end reader (its .rejected says which test refused each end)


def edges(image: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Prewitt gradient (d/dcolumn, d/drow) of an image, each normalised to grey levels per px."""
    from scipy import ndimage

    gc = ndimage.prewitt(image, axis=1) / 6.0
    gr = ndimage.prewitt(image, axis=0) / 6.0
    return gc, gr


def edge_at(image: np.ndarray, r: int, c: int) -> tuple[float, float]:
    """The Prewitt gradient at one interior point, computed on demand (the paper's way)."""
    w = image[r - 1:r + 2, c - 1:c + 2]
    gc = (w[:, 2].sum() - w[:, 0].sum()) / 6.0
    gr = (w[2, :].sum() - w[0, :].sum()) / 6.0
    return float(gc), float(gr)


def edge_threshold(magnitude: np.ndarray) -> float:
    """An edge is EDGE_NOISE_FACTOR times the noise's typical edge magnitude.

    Most of a tray is flat, so the median magnitude is the noise's (for Gaussian
    noise the magnitude is Rayleigh: median = 1.18 sigma). A noiseless image gets
    a floor from its strongest edges.
    """
    sample = magnitude[::2, ::2].ravel()  # a quarter of the points estimates as well
    sigma = float(np.median(sample)) / 1.1774
    strong = float(np.partition(sample, int(0.995 * (sample.size - 1)))[int(0.995 * (sample.size - 1))])
    return max(EDGE_NOISE_FACTOR * sigma, 0.08 * strong, 1e-3)


def find_wires_grey(image: np.ndarray, px_per_mm: float = 4.0, enough: int = ENOUGH) -> GreyResult:
    """Graspable wire ends in an image (any size; px_per_mm gives the scale).

    The planning regions are searched in the interest operator's order until
    `enough` free wire ends are found (0: search them all)."""
    result = GreyResult()
    clock = Clock(result.timings)
    grey = as_grey(image)
    k = max(1, int(round(px_per_mm / WORK_PX_PER_MM)))
    work = block_average(grey, k)
    plan = block_average(work, 4)
    result.scale = k
    clock("average")
    if min(plan.shape) < 4 or float(work.std()) < 1e-3:
        return result
    gc, gr = edges(work)
    mag = np.hypot(gc, gr)
    t = edge_threshold(mag)
    result.threshold = t
    clock("edges")
    order = interest_order(plan, t)
    result.region_order = order
    clock("interest")
    ppm = px_per_mm / k  # working px per mm
    unit = ppm / WORK_PX_PER_MM  # the paper's units at this scale
    tracer = _Tracer(gc, gr, mag, t)
    looks = _Looks(work, mag, t, ppm, gc, gr)
    result.looks = looks
    kept: list[Sighting] = []
    ends_ms = 0.0
    rh, rw = work.shape[0] / 4.0, work.shape[1] / 4.0
    for (i, j) in order:
        r0, r1 = int(i * rh), int((i + 1) * rh)
        c0, c1 = int(j * rw), int((j + 1) * rw)
        for start in tracer.starts(r0, r1, c0, c1):
            chain = tracer.follow(start)
            t1 = time.perf_counter()
            if len(chain[1]) < SEGMENT * unit:
                continue
            result.chains.append(chain)
            pts = chain_points(*chain)
            for s in looks.wire_ends(pts, unit):  # one sighting per wire end
                if all(math.dist(s.end, o.end) > 2.0 * ppm for o in kept):
                    kept.append(s)
            ends_ms += time.perf_counter() - t1
        if enough and len(kept) >= enough:
            break  # the interest operator's point: stop once enough free ends are seen
    clock("follow")  # the search: tracing, and the ends read off each boundary as it is traced
    result.timings["follow"] -= ends_ms * 1000.0
    result.timings["ends"] = ends_ms * 1000.0
    kept.sort(key=lambda s: -s.score)
    result.candidates = [Sighting(tuple(to_input(s.end[::-1], k).tolist()), s.end_angle,
                                  tuple(to_input(s.grasp[::-1], k).tolist()), s.grasp_angle, s.score)
                         for s in kept]
    result.contours = [to_input(chain_points(*c), k) for c in result.chains]
    clock("report")
    result.timings["total"] = sum(result.timings.values())
    return result


def interest_order(plan: np.ndarray, threshold: float) -> list[tuple[int, int]]:
    """The 4 x 4 regions of the planning image, those with least edge (but some) first."""
    gc, gr = edges(plan)
    mag = np.hypot(gc, gr)
    h, w = plan.shape
    counts = []
    for i in range(4):
        for j in range(4):
            block = mag[i * h // 4:(i + 1) * h // 4, j * w // 4:(j + 1) * w // 4]
            n = int((block > threshold).sum())
            if n:
                counts.append((n, i, j))
    counts.sort()
    return [(i, j) for _, i, j in counts]


def chain_points(start: tuple[int, int], codes: bytes) -> np.ndarray:
    """(N + 1, 2) float (row, col) points of a Freeman chain from its start."""
    steps = np.array(STEPS, float)
    if not codes:
        return np.array([start], float)
    moves = steps[np.frombuffer(codes, np.uint8)]
    return np.vstack([[start], start + np.cumsum(moves, axis=0)])


class _Tracer:
    """Dynamic contour following on the working image's edges (flat memoryviews: fast in Python)."""

    def __init__(self, gc: np.ndarray, gr: np.ndarray, mag: np.ndarray, threshold: float) -> None:
        h, w = mag.shape
        self.W = w + 2 * PAD
        pad = lambda a: np.pad(a, PAD).ravel()
        self.mag_np = np.pad(mag, PAD)
        # memoryviews: indexing one gives a Python float, as fast as a list and nothing to convert
        self.mag = self.mag_np.astype(np.float64).ravel().data
        n = np.maximum(mag, 1e-12)
        # the boundary's direction: the gradient (dark -> bright) turned 90 degrees,
        # so that the darker side is always on the same hand
        self.tc = pad(-gr / n).astype(np.float64).data
        self.tr = pad(gc / n).astype(np.float64).data
        self.t = threshold
        self.low = 0.6 * threshold  # a boundary, once found, is followed down to this
        self._owner = np.zeros((h + 2 * PAD) * self.W, np.int32)
        self.owner = self._owner.data
        self.offs = [dr * self.W + dc for dr, dc in STEPS]
        self.unit = [(dr / math.hypot(dr, dc), dc / math.hypot(dr, dc)) for dr, dc in STEPS]
        self.count = 0
        self.ride_max = 2 * SEGMENT  # steps a trace may run along another's boundary
        self.ridge = _ridge(mag, gc, gr) & (mag > threshold)

    def starts(self, r0: int, r1: int, c0: int, c1: int):
        """The region's ridge points, strongest first, that no trace has passed."""
        block = self.ridge[r0:r1, c0:c1]
        rr, cc = np.nonzero(block)
        if not rr.size:
            return
        W, owner = self.W, self.owner
        m = self.mag_np[rr + r0 + PAD, cc + c0 + PAD]
        for i in np.argsort(-m, kind="stable").tolist():
            p = (int(rr[i]) + r0 + PAD) * W + int(cc[i]) + c0 + PAD
            if owner[p] or owner[p + 1] or owner[p - 1] or owner[p + W] or owner[p - W]:
                continue
            yield p

    def follow(self, p0: int) -> tuple[tuple[int, int], bytes]:
        """Trace the boundary through p0 both ways: (start (row, col), Freeman codes)."""
        self.count += 1
        me = self.count
        d0 = self._direction(p0, 1)
        self.owner[p0] = me
        ahead, closed = self._run(p0, d0, 1, me)
        back: list[int] = []
        if not closed:
            back, _ = self._run(p0, (d0 + 4) % 8, -1, me)
        # the backward run walked the boundary in reverse: flip it to run forwards
        codes = [(c + 4) % 8 for c in reversed(back)] + ahead
        end = p0
        for c in back:
            end += self.offs[c]
        r, c = divmod(end, self.W)
        return (r - PAD, c - PAD), bytes(codes)

    def _direction(self, p: int, sense: int) -> int:
        a = math.atan2(-sense * self.tr[p], sense * self.tc[p])  # screen angle: row up is positive
        return int(round(a / (math.pi / 4))) % 8

    def _ahead(self, p: int, d: int, sense: int, jump: int, floor: float, agreement: float) -> tuple[int, int]:
        """The best of the three points `jump` steps ahead of p in directions d - 1, d, d + 1:
        the largest edge magnitude (at least floor) times its agreement with the step (at
        least `agreement`); (-1, 0) when none qualifies."""
        mag, tr, tc, offs, unit = self.mag, self.tr, self.tc, self.offs, self.unit
        best, best_d, best_s = -1, 0, 0.0
        for turn in (0, -1, 1):
            k = (d + turn) % 8
            q = p + jump * offs[k]
            if q < 0 or q >= len(mag):
                continue
            m = mag[q]
            if m < floor:
                continue
            ur, uc = unit[k]
            agree = sense * (tr[q] * ur + tc[q] * uc)
            if agree < agreement:
                continue
            if m * agree > best_s:
                best, best_d, best_s = q, k, m * agree
        return best, best_d

    def _run(self, p: int, d: int, sense: int, me: int) -> tuple[list[int], bool]:
        tr, tc, owner = self.tr, self.tc, self.owner
        low = self.low
        codes: list[int] = []
        start = p
        W = self.W
        ride, ride_max = 0, self.ride_max
        for _ in range(40000):
            jump = 1
            best, best_d = self._ahead(p, d, sense, 1, low, 0.3)
            if best < 0:  # a gap: look in the zones 1 and 2 px further ahead
                for jump in (2, 3):
                    best, best_d = self._ahead(p, d, sense, jump, self.t, 0.5)
                    if best >= 0:
                        break
                else:
                    return codes, False
            o = owner[best]
            if o and o != me:
                ride += jump  # on another trace's boundary: through a junction, or a duplicate
                if ride > ride_max:
                    return codes, False
            else:
                ride = 0
            if best == start or (o == me and len(codes) > 8 and _near_start(best, start, W)):
                codes.extend([best_d] * jump)
                return codes, True
            if o == me and len(codes) > 8:
                return codes, False  # met its own trail away from the start: stop
            codes.extend([best_d] * jump)
            p = best
            d = best_d
            if not o:
                owner[p] = me
                # suppress the thick edge response on either side, normal to the boundary
                side = int(round(-tc[p])) * W + int(round(tr[p]))
                if side:
                    if not owner[p + side]:
                        owner[p + side] = me
                    if not owner[p - side]:
                        owner[p - side] = me
        return codes, False


def _near_start(q: int, start: int, W: int) -> bool:
    dr = q // W - start // W
    dc = q % W - start % W
    return abs(dr) <= 1 and abs(dc) <= 1


def _ridge(mag: np.ndarray, gc: np.ndarray, gr: np.ndarray) -> np.ndarray:
    """Points whose edge magnitude is a maximum across the boundary (non-maximum suppression)."""
    ang = np.round(np.arctan2(gr, gc) / (np.pi / 4)).astype(int) % 4  # 0: across columns, 2: rows
    p = np.pad(mag, 1)
    h, w = mag.shape
    c = p[1:h + 1, 1:w + 1]
    out = np.zeros_like(mag, bool)
    for a, (dr, dc) in enumerate(((0, 1), (1, 1), (1, 0), (1, -1))):
        m = ang == a
        fwd = p[1 + dr:h + 1 + dr, 1 + dc:w + 1 + dc]
        bwd = p[1 - dr:h + 1 - dr, 1 - dc:w + 1 - dc]
        out |= m & (c >= fwd) & (c >= bwd)
    return out


class _Looks:
    """Reads wire ends off boundaries and tests them on the working image."""

    def __init__(self, work: np.ndarray, mag: np.ndarray, threshold: float, ppm: float,
                 gc: np.ndarray | None = None, gr: np.ndarray | None = None) -> None:
        self.work = work
        self.mag = mag
        self.gc, self.gr = gc, gr
        self.t = threshold
        self.ppm = ppm
        self.tray, noise = tray_level(work, 2)
        self.shine = max(5 * noise, 0.04)
        self.rejected: list[str] = []  # which test turned each candidate end down (for tuning)

    def _no(self, test: str) -> Sighting | None:
        """Note which test refused an end; None, so that a test reads `return self._no(...)`."""
        self.rejected.append(test)
        return None

    def wire_ends(self, pts: np.ndarray, unit: float) -> list[Sighting]:
        """Sightings (working (row, col) -> stored as (col, row)) for the ends along one boundary."""
        n = len(pts) - 1
        seg = max(int(round(SEGMENT * unit)), 8)
        if n < seg + 2:
            return []
        closed = bool(np.abs(pts[0] - pts[-1]).max() <= 1)
        if closed:
            pts = np.vstack([pts[:-1], pts[:seg + 1]])
        a = max(seg // 6, 2)
        first = pts[a:len(pts) - seg + a] - pts[:len(pts) - seg]
        last = pts[seg:] - pts[seg - a:len(pts) - a]
        cosang = (first * last).sum(axis=1) / (np.linalg.norm(first, axis=1) * np.linalg.norm(last, axis=1) + 1e-12)
        apart = np.linalg.norm(pts[seg:] - pts[:len(pts) - seg], axis=1)
        hit = (cosang < -math.cos(math.radians(END_TURN_TOL))) & (apart <= GAP * unit + 0.5)
        out = []
        for run in _runs(np.flatnonzero(hit)):
            i = run[np.argmin(apart[run])]
            s = self._end(pts, i + seg // 2, unit, closed)
            if s is not None:
                out.append(s)
        return out

    def _end(self, pts: np.ndarray, tip: int, unit: float, closed: bool) -> Sighting | None:
        """The wire end the heuristic found at pts[tip], tested as the paper tests it: its two
        sides followed from the tip, the centre line between them, the end (or its conductor's
        tip), the sides parallel out to the span, the grasp point, and the span free."""
        sides = self._sides(pts, tip, unit, closed)
        if sides is None:
            return self._no("boundary stops short")
        fwd, bwd = sides
        centre, width = _centre_line(fwd, bwd)
        ppm = self.ppm
        near = max(int(NEAR_MM * ppm), 3)
        w0 = float(np.median(width[int(GRASP_MM * ppm) - near:int(GRASP_MM * ppm) + near]))  # at the grasp
        if not 1.0 <= w0 <= MAX_WIDTH_MM * ppm:
            return self._no("no wire width")
        end = self._end_face(pts, tip, unit, closed, centre, near, w0)
        if end is None:
            return self._no("more than a conductor")
        end_rc, inward, conductor, dark = end
        along = (centre - end_rc) @ inward  # distance along the wire from the end (it bends little over the span)
        grasp_s, span_s = GRASP_MM * ppm, SPAN_MM * ppm
        if along.max() < span_s * SPAN_SEEN:
            return self._no("wire too short")
        if not _parallel(width, along, w0, near, span_s, ppm):
            return self._no("sides not parallel")
        at = np.abs(along - grasp_s)
        grasp = centre[at <= max(at.min(), 1.0)].mean(axis=0)
        around = centre[at <= TANGENT_MM * ppm]
        if len(around) < 3:
            return self._no("no tangent")
        tvec = principal_direction(around)
        tangent = math.degrees(math.atan2(tvec[0], tvec[1])) % 180.0
        end_angle = math.degrees(math.atan2(inward[0], inward[1]))
        span_pts, arc = _binned(centre, along, ppm, span_s)
        if conductor is not None:  # the conductor is part of the span that must be free
            span_pts = np.vstack([conductor, span_pts])
            arc = np.concatenate([(conductor - end_rc) @ inward, arc])
        if len(span_pts) < 3:
            return self._no("no centre line")
        if self._near_border(span_pts, end_rc):
            return self._no("too near the border")
        h, w = self.work.shape
        side_pts = np.clip(np.round(np.vstack([fwd, bwd])).astype(int), 0, [h - 1, w - 1])
        own = float(np.median(self.mag[side_pts[:, 0], side_pts[:, 1]]))
        clearance = self._clearance(span_pts, arc, w0, end_rc, inward, own if dark else -own)
        if clearance is None:
            return self._no("not isolated")
        return Sighting((float(end_rc[1]), float(end_rc[0])), end_angle, (float(grasp[1]), float(grasp[0])),
                        tangent, score=clearance)

    def _sides(self, pts: np.ndarray, tip: int, unit: float, closed: bool) -> tuple[np.ndarray, np.ndarray] | None:
        """The boundary followed both ways from the tip far enough to pass the span (the wire's
        two sides), or None where it stops short of that (the wire is not free)."""
        n = len(pts)
        reach = int(math.ceil((SPAN_MM + SIDES_PAST_MM) * self.ppm * SIDES_SLACK))
        if closed:
            ring = pts[:n - int(round(SEGMENT * unit))]
            m = len(ring)
            if m < 2 * reach:
                return None
            return ring[(tip + np.arange(1, reach)) % m], ring[(tip - np.arange(1, reach)) % m]
        if tip + reach > n or tip - reach < 0:
            return None  # before the grasp point
        return pts[tip + 1:tip + reach], pts[tip - 1:tip - reach:-1]

    def _end_face(self, pts, tip, unit, closed, centre, near, w0):
        """(the end (row, col), the unit direction into the wire, the conductor's centre line or
        None, whether the wire is darker than the tray): the wire's axis near the end, the end
        face across it, and past a dark wire's end a stripped conductor or ferrule followed to
        its tip. None where more than a conductor goes on past the end."""
        ppm = self.ppm
        n = len(pts)
        axis_pts = centre[near:near + int(AXIS_FIT_MM * ppm)]
        inward = principal_direction(axis_pts)
        if (axis_pts[-1] - axis_pts[0]) @ inward < 0:
            inward = -inward
        half = seg_half(unit)
        tipzone = pts[(tip + np.arange(-half, half + 1)) % n] if closed else pts[max(tip - half, 0):tip + half + 1]
        end_rc = axis_pts[0] + float(((tipzone - axis_pts[0]) @ inward).min()) * inward  # the end face
        h, w = self.work.shape
        inner = np.clip(np.round(axis_pts).astype(int), 0, [h - 1, w - 1])
        dark = float(np.median(self.work[inner[:, 0], inner[:, 1]])) < self.tray
        tip_rc = conductor_tip(self.work, end_rc, -inward, w0, ppm, self.tray + self.shine) if dark else None
        if tip_rc is False:
            return None
        conductor = None
        if tip_rc is not None:  # a stripped conductor or ferrule: the end is its tip
            conductor = np.linspace(tip_rc, end_rc, max(int(np.linalg.norm(end_rc - tip_rc)), 2))
            inward = end_rc - tip_rc
            inward = inward / np.linalg.norm(inward)
            end_rc = tip_rc
        return end_rc, inward, conductor, dark

    def _near_border(self, span_pts: np.ndarray, end_rc: np.ndarray) -> bool:
        h, w = self.work.shape
        margin = BORDER_MM * self.ppm
        return bool(span_pts.min() < margin or span_pts[:, 0].max() > h - 1 - margin
                    or span_pts[:, 1].max() > w - 1 - margin
                    or min(end_rc) < margin or end_rc[0] > h - 1 - margin or end_rc[1] > w - 1 - margin)

    def _clearance(self, centre: np.ndarray, arc: np.ndarray, width: float, end: np.ndarray,
                   inward: np.ndarray, own: float = 0.0) -> float | None:
        """The isolation test. The smallest free distance (mm) beside the wire near the grasp
        point, or None when another boundary comes too close anywhere along the span.

        own is the wire's own edge magnitude (its sides' median), positive for a wire darker
        than the tray, negative for a lighter one (0: count every edge)."""
        ppm = self.ppm
        c, a = centre, arc
        t = np.gradient(c, axis=0)
        t /= np.linalg.norm(t, axis=1, keepdims=True) + 1e-12
        normal = np.stack([-t[:, 1], t[:, 0]], axis=1)
        # distances (px) from the centre line, from just past the wire's own edge response
        reach = np.arange(width / 2 + 2.5, (CLEARANCE_MM + 1.0) * ppm)
        free = []
        for sign in (1.0, -1.0):
            p = c[:, None, :] + sign * normal[:, None, :] * reach[None, :, None]
            r, q = self._pixels(p)
            hit = self._edge(r, q, sign * normal[:, None, :], own)
            hit[:, :-1] &= hit[:, 1:]  # an edge shows on two samples running; noise rarely does
            first = np.where(hit.any(axis=1), reach[np.argmax(hit, axis=1)], reach[-1] + 1)
            free.append(first / ppm)
        free = np.minimum(*free)  # mm from the centre line to the nearest other edge
        near_grasp = np.abs(a - GRASP_MM * ppm) <= 3.0 * ppm
        if np.any(free[~near_grasp] < (width / 2 + 2.5) / ppm + FREE_MM) or np.any(free[near_grasp] < CLEARANCE_MM):
            return None
        # beyond the end: a short fan in front of the end face
        out = -inward
        side = np.array([-out[1], out[0]])
        offsets = np.arange(2.5, 2.5 + FREE_MM * ppm + 1) + self._end_blur(end, out, own)
        lateral = np.linspace(-width / 2, width / 2, 3)
        p = end[None, None, :] + out[None, None, :] * offsets[:, None, None] + side * lateral[None, :, None]
        r, q = self._pixels(p)
        # in front of the end only half as faint an edge is its shadow: a metal tip too dull to
        # be seen as one (darker than the tray, lighter than the wire) shows a faint edge too
        hit = self._edge(r, q, out, 0.5 * own)
        if (hit[:-1] & hit[1:]).any():
            return None
        return float(free[near_grasp].min())

    def _end_blur(self, end: np.ndarray, out: np.ndarray, own: float) -> float:
        """How much farther (px) than 2.5 px from the end face its own blurred edge goes on, on the
        axis outward (out): the run of edge samples across which the grey moves on away from the
        wire's level (lighter, out from a dark wire), up to END_BLUR_MM; 0 unless the grey from
        the run's end on is flat for 2 mm (within END_FLAT of the step from the wire): the end's own
        edge ends at the tray, while a dull metal tip's first edge ends on a plateau between
        the two, with its own end to follow. own: see _clearance."""
        if not own or self.gc is None or self.gr is None:
            return 0.0

        def at(offsets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            return self._pixels(end[None, :] + out[None, :] * offsets[:, None])

        steps = np.arange(2.5, 2.5 + END_BLUR_MM * self.ppm, 1.0)
        r, q = at(steps)
        rise = self.gr[r, q] * out[0] + self.gc[r, q] * out[1]
        away = (rise > 0 if own > 0 else rise < 0) & (self.mag[r, q] > self.t)
        run = int(np.argmin(away)) if not away.all() else len(away)
        if not run:
            return 0.0
        start = steps[min(run, len(steps) - 1)]  # past the run (or its last sample, if it reaches END_BLUR_MM)
        past = self.work[at(np.arange(start, start + 2.0 * self.ppm, 1.0))]
        wire = float(self.work[at(np.array([-2.0]))][0])
        tray = float(past.max() if own > 0 else past.min())
        if abs(tray - float(past[0])) > END_FLAT * abs(tray - wire):
            return 0.0
        return float(run)

    def _pixels(self, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The working image's pixel (rows, columns) nearest each point of p (..., 2), clipped to it."""
        h, w = self.mag.shape
        return np.clip(np.round(p[..., 0]).astype(int), 0, h - 1), np.clip(np.round(p[..., 1]).astype(int), 0, w - 1)

    def _edge(self, r: np.ndarray, q: np.ndarray, outward: np.ndarray, own: float) -> np.ndarray:
        """Whether each working pixel (r, q) holds an edge that is not the wire's own soft
        shadow: a faint edge across which the grey, going outward (outward: row, col), moves
        on away from the wire's level (lighter, out from a dark wire). Another wire shows an
        edge the other way first, or a strong one. own: see _clearance."""
        hit = self.mag[r, q] > self.t
        if own and self.gc is not None and self.gr is not None:
            rise = self.gr[r, q] * outward[..., 0] + self.gc[r, q] * outward[..., 1]
            away = rise > 0 if own > 0 else rise < 0
            hit &= ~(away & (self.mag[r, q] < SHADOW_EDGE * abs(own)))
        return hit


def seg_half(unit: float) -> int:
    return max(int(round(SEGMENT * unit / 2)), 4)


def _centre_line(fwd: np.ndarray, bwd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(the centre line, the width) between a wire's two sides: each point of one side paired
    with the nearest point of the other."""
    d = np.linalg.norm(fwd[:, None, :] - bwd[None, :, :], axis=2)
    j = np.argmin(d, axis=1)
    return (fwd + bwd[j]) / 2.0, d[np.arange(len(fwd)), j]


def _parallel(width: np.ndarray, along: np.ndarray, w0: float, near: int, span_s: float, ppm: float) -> bool:
    """Whether the sides stay parallel, the width w0, out to the span: nothing joins the wire
    (a stripped conductor or a ferrule may make its first few mm thinner, never wider)."""
    inspan = (along > near) & (along < span_s)
    tol = max(PARALLEL_TOL_PX, PARALLEL_TOL_SHARE * w0)
    thinner = inspan & (width < w0 - tol)
    normal = inspan & ~thinner
    if not normal.any() or np.any(inspan & (width > w0 + tol)):
        return False
    return not (thinner.any() and along[thinner].max() > along[normal].min() + ppm)


def _binned(centre: np.ndarray, along: np.ndarray, ppm: float, upto: float) -> tuple[np.ndarray, np.ndarray]:
    """The centre line from the end to upto, as the mean point of each mm along it."""
    keep = (along >= 0) & (along <= upto)
    bins = (along[keep] / ppm).astype(int)
    n = int(bins.max()) + 1 if bins.size else 0
    count = np.bincount(bins, minlength=n)
    ok = count > 0
    pts = np.stack([np.bincount(bins, centre[keep, 0], n), np.bincount(bins, centre[keep, 1], n)], axis=1)
    arc = np.bincount(bins, along[keep], n)
    return pts[ok] / count[ok, None], arc[ok] / count[ok]


def _runs(idx: np.ndarray) -> list[np.ndarray]:
    if not idx.size:
        return []
    cut = np.flatnonzero(np.diff(idx) > 1) + 1
    return np.split(idx, cut)


