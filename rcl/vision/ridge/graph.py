"""The centre lines as a graph: ends, crossings, spurs pruned, gaps bridged; the ends worth
reading, and places to take a wire by its middle."""
from __future__ import annotations

import math

import numpy as np

from .lines import MIN_LINE_MM, NEIGHBOURS, _cut_corners, _trim_crosses, end_rings, minimal, small_holes, thin_sparse

SPAN_MM = 20.0  # wire that must be free from the tip: the grasp point and 5 mm beyond
SPUR_MM = 3.0  # branches this short that end at a crossing are whiskers
GAP_MM = 2.5  # a break in a centre line this long, straight ahead, is bridged
GAP_CONE_DEG = 30.0
JOG_SIDE_MM = 2.0  # ... or a line end this far to the side of it, going on the same way (JOG_CONE_DEG), from
JOG_BACK_MM = 1.5  # this far back (the two pieces side by side) to GAP_MM ahead: a centre line stepped sideways
JOG_CONE_DEG = 30.0
MIDDLE_AWAY_MM = 8.0  # a middle grasp: this far from every crossing of the centre lines
MIDDLE_END_MM = 20.0  # ... and this far along its line from every end of the lines: held by its middle, it hangs
UNDER_MM = 6.0  # ... two line ends this near, facing each other (UNDER_CONE_DEG), are where a wire goes under another
UNDER_CONE_DEG = 35.0
MIDDLE_STEP_MM = 3.0  # ... tried at points this far apart
MIDDLE_MAX = 60  # ... at most this many
_COS_CONE = math.cos(math.radians(GAP_CONE_DEG))
_COS_UNDER = math.cos(math.radians(UNDER_CONE_DEG))
_COS_JOG = math.cos(math.radians(JOG_CONE_DEG))


class Graph:
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

    def rcs(self, pixels: list[int]) -> np.ndarray:
        """rc() of each pixel, as (N, 2) float (row, col)."""
        return np.column_stack(np.divmod(np.array(pixels), self.W)).astype(float) - 1.0

    def trace(self, start: int, limit_px: float) -> tuple[list[int], str]:
        """Follow the centre line from an end for limit_px of arc: (pixels, how it stopped:
        'crossing', 'end' or 'far')."""
        flat = self.flat.tobytes()  # bytes: a Python index per pixel is cheap
        path = [start]
        prev = -1
        cur = start
        arc = 0.0
        while arc < limit_px:
            nxt = self._onward(flat, cur, prev, path[-3:])
            if not nxt:
                onto = None  # (the pixel jumped to, the one before it on its line, or -1)
                if len(path) > 4:
                    gap = self.across_gap(path)
                    onto = (gap, -1) if gap is not None else self.across_jog(path, flat)
                if onto is None:
                    return path, "end"
                arc += float(np.hypot(*np.subtract(divmod(onto[0], self.W), divmod(cur, self.W))))
                cur, prev = onto
                path.append(cur)
                continue
            if len(nxt) > 1:
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
        _trim_crosses(self.flat, self.W)  # ... or the stub of one next to the stubs of others
        grid = self.skeleton.astype(bool)
        mended = end_rings(grid)
        if mended is not grid:
            self.flat = np.pad(mended, 1).ravel().copy()
        self._count()

    def across_gap(self, path: list[int]) -> int | None:
        """Where the centre line goes on across a short break straight ahead of path's last pixel:
        the nearest other line end within GAP_MM in a GAP_CONE_DEG cone (a break leaves two ends
        facing each other), or None."""
        heading = self._heading(path)
        if heading is None:
            return None
        rr, cc, dist = self._gap_window
        idx, d = self._ends_among(path[-1], rr * heading[1][0] + cc * heading[1][1] >= _COS_CONE * dist)
        recent = set(path[-12:])
        for k in np.argsort(d):
            if int(idx[k]) not in recent:
                return int(idx[k])
        return None

    def across_jog(self, path: list[int], flat: bytes | None = None) -> tuple[int, int] | None:
        """Where the centre line goes on stepped sideways at path's last pixel (a striped wire's
        ridge moving from stripe to stripe, or a metal tip's off the insulation's axis): the end of
        another line within JOG_SIDE_MM of the way ahead, from JOG_BACK_MM back to GAP_MM ahead
        (outside across_gap's cone), whose line goes on the same way (JOG_CONE_DEG). (the pixel of
        that line where it is first level with path's last or ahead of it, the pixel before it on
        that line), or None. flat: the grid as bytes, if at hand."""
        heading = self._heading(path)
        if heading is None:
            return None
        here, ahead = heading
        mm = self.wppm
        rr, cc, dist = self._gap_window
        fwd = rr * ahead[0] + cc * ahead[1]
        near = (np.abs(cc * ahead[0] - rr * ahead[1]) <= JOG_SIDE_MM * mm) & (fwd >= -JOG_BACK_MM * mm) \
            & (fwd < _COS_CONE * dist)
        idx, d = self._ends_among(path[-1], near)
        on_path = set(path)
        for k in np.argsort(d):
            i = int(idx[k])
            if i in on_path:
                continue
            walk = self._walk(i, math.ceil(2.0 * mm) + 1, flat)
            if len(walk) < 3:
                continue
            pts = self.rcs(walk)
            way = pts[-1] - pts[0]
            if way @ ahead < _COS_JOG * float(np.linalg.norm(way)):
                continue  # its line goes back the way the trace came: another wire's end beside it
            level = np.flatnonzero((pts - here) @ ahead >= 0.0)
            if not len(level) or any(q in on_path for q in walk[:level[0] + 1]):
                continue
            j = int(level[0])
            return walk[j], (walk[j - 1] if j else -1)
        return None

    def _heading(self, path: list[int]) -> tuple[np.ndarray, np.ndarray] | None:
        """(path's last pixel (row, col), the unit way ahead along its last 2 mm), or None if
        the path is too short to say."""
        here = self.rcs([path[-1]])[0]
        ahead = here - self.rcs([path[max(len(path) - 1 - int(2.0 * self.wppm), 0)]])[0]
        n = float(np.linalg.norm(ahead))
        return None if n < 1.0 else (here, ahead / n)

    def _ends_among(self, at: int, keep: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The line ends among the offsets of _gap_window where keep is set, from pixel at:
        (their pixels, their distances)."""
        rr, cc, dist = self._gap_window
        idx = at + (rr[keep] * self.W + cc[keep]).astype(np.int64)
        ok = (idx >= 0) & (idx < len(self.flat))
        idx, d = idx[ok], dist[keep][ok]
        hit = (self.degree[idx] == 1) & self.flat[idx]
        return idx[hit], d[hit]

    def _onward(self, flat, cur: int, prev: int, recent: list[int]) -> list[int]:
        """The pixels the centre line goes on to from cur, not back to prev or the recent ones:
        none at an end, one, or more at a crossing (an edge neighbour and the diagonal beside
        it are one step of the same line). flat: the grid as bytes (a Python index per pixel is
        cheap)."""
        nxt = [cur + o for o in self.offsets if flat[cur + o] and cur + o != prev and cur + o not in recent]
        if len(nxt) == 2:
            edge = [q for q in nxt if abs(q - cur) in (1, self.W)]
            if len(edge) == 1 and _adjacent(nxt[0], nxt[1], self.W):
                return edge
        return nxt

    def _walk(self, start: int, steps: int, flat: bytes | None = None) -> list[int]:
        """Up to steps pixels along the centre line from an end, stopping at a crossing (flat:
        the grid as bytes, if at hand)."""
        flat = self.flat.tobytes() if flat is None else flat
        path, prev, cur = [start], -1, start
        for _ in range(steps):
            nxt = self._onward(flat, cur, prev, path[-3:])
            if len(nxt) != 1:
                break
            prev, cur = cur, nxt[0]
            path.append(cur)
        return path

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
        """Points (row, col) on lines MIN_LINE_MM long or more, end_mm or more along their
        line from every end of those lines (a loop's far side is far from its ends, a short
        tail's points are not, however far they lie straight; two ends facing each other across
        a short gap are where a wire goes under another and on) and MIDDLE_AWAY_MM (straight) from every
        crossing, MIDDLE_STEP_MM apart at least, farthest from them (relative to those
        distances) first."""
        from scipy import ndimage
        from scipy.sparse.csgraph import dijkstra

        grid = self.skeleton.astype(bool)
        if not grid.any():
            return []
        deg = self.degree.reshape(self.h + 2, self.W)[1:-1, 1:-1]
        ring = small_holes(grid)
        if ring.any():  # a ring round a hole of a pixel or two at a line's end: that end is found again
            grid = minimal(thin_sparse(grid | ring))
            deg = Graph(grid, self.wppm).degree.reshape(self.h + 2, self.W)[1:-1, 1:-1]
        # the ends and crossings of lines MIN_LINE_MM long or more (a speck of the board's
        # texture leaves a short line whose ends are no wire's)
        pieces, n = ndimage.label(grid, np.ones((3, 3)))
        size = np.bincount(pieces.ravel(), minlength=n + 1)
        size[0] = 0
        lines = size[pieces] >= MIN_LINE_MM * self.wppm
        # arc length along the lines from their nearest end, the ends facing each other across
        # a gap where a wire goes under another joined (no ends of it)
        rr, cc = np.nonzero(lines)
        a, b, w = _pixel_links(lines, rr, cc)
        ends = np.flatnonzero(deg[rr, cc] <= 1)
        under = np.zeros(len(ends), bool)
        if len(ends) > 1:
            i, j, gap = _facing_ends(rr, cc, ends, _links(a, b, w, len(rr)), self.wppm)
            under[i] = under[j] = True
            a, b, w = np.concatenate([a, ends[i]]), np.concatenate([b, ends[j]]), np.concatenate([w, gap])
        crossings = lines & (deg >= 3)
        crossings[rr[ends[under]], cc[ends[under]]] = True
        from_crossing = (ndimage.distance_transform_edt(~crossings) if crossings.any()
                         else np.full(grid.shape, np.inf)) / (MIDDLE_AWAY_MM * self.wppm)
        if len(ends) > under.sum():
            arc = dijkstra(_links(a, b, w, len(rr)), directed=False, indices=ends[~under], min_only=True)
        else:
            arc = np.full(len(rr), np.inf)  # closed loops only
        away = np.minimum(arc / (end_mm * self.wppm), from_crossing[rr, cc])
        keep = away >= 1.0
        order = np.argsort(-away[keep], kind="stable")
        pts = np.column_stack([rr[keep][order], cc[keep][order]]).astype(float)
        step2 = (MIDDLE_STEP_MM * self.wppm) ** 2
        kept: list[np.ndarray] = []
        while len(pts) and len(kept) < MIDDLE_MAX:  # the farthest left, then none near it
            kept.append(pts[0])
            pts = pts[((pts - pts[0]) ** 2).sum(axis=1) >= step2]
        return kept

    def ends_in_order(self, f: np.ndarray) -> list[int]:
        """The ends worth reading, best first: those whose line runs on for at least SPAN_MM
        before it meets another (every other end fails the span test anyway), across a break the
        trace jumps too (GAP_MM), on the longest, strongest lines first."""
        from scipy import ndimage

        ends = self.ends()
        if not len(ends):
            return []
        # the lines cut at every crossing, a pixel round it (a 3 x 3 dilation of a few pixels)
        crossings = np.flatnonzero(self.degree >= 3)
        cut = self.flat.copy()
        cut[(crossings[:, None] + np.array([0, *self.offsets])).ravel()] = False
        pieces, n = ndimage.label(cut.reshape(self.h + 2, self.W), np.ones((3, 3)))
        length = np.bincount(pieces.ravel()[np.flatnonzero(cut)], minlength=n + 1).astype(float)
        piece = pieces.ravel()[ends]
        need = 0.85 * SPAN_MM * self.wppm
        long_enough = length[piece] >= need
        for k in np.flatnonzero(~long_enough):
            # a piece that ends in a break the trace jumps (a ridge broken where a conductor
            # meets the insulation) may go on across it far enough
            if self.trace(int(ends[k]), need)[1] == "far":
                long_enough[k] = True
                length[piece[k]] = max(length[piece[k]], need)
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


def _pixel_links(mask: np.ndarray, rr: np.ndarray, cc: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The set pixels (rr, cc) of mask joined to their 8-neighbours: (from, to, length) by their
    index in rr, cc, each pair once, 1 or sqrt 2 long."""
    index = np.full(mask.shape, -1, np.int64)
    index[rr, cc] = np.arange(len(rr))
    padded = np.pad(index, 1, constant_values=-1)
    a, b, w = [], [], []
    for dr, dc, step in ((0, 1, 1.0), (1, 0, 1.0), (1, 1, math.sqrt(2.0)), (1, -1, math.sqrt(2.0))):
        other = padded[rr + 1 + dr, cc + 1 + dc]
        on = other >= 0
        a.append(np.flatnonzero(on))
        b.append(other[on])
        w.append(np.full(int(on.sum()), step))
    return np.concatenate(a), np.concatenate(b), np.concatenate(w)


def _links(a: np.ndarray, b: np.ndarray, w: np.ndarray, n: int):
    from scipy.sparse import coo_matrix

    return coo_matrix((w, (a, b)), shape=(n, n)).tocsr()


def _facing_ends(rr: np.ndarray, cc: np.ndarray, ends: np.ndarray, links, wppm: float):
    """Pairs of line ends (ends: indices into rr, cc) that face each other (UNDER_CONE_DEG)
    across UNDER_MM or less and are not joined along the lines nearby: where a wire goes under
    another. (i, j, their distance), i and j indices into ends, each pair once."""
    from scipy.sparse.csgraph import dijkstra

    reach = UNDER_MM * wppm
    along = dijkstra(links, directed=False, indices=ends, limit=2.0 * reach + 2.0)
    at = np.column_stack([rr[ends], cc[ends]]).astype(float)
    heading = np.zeros_like(at)  # out of each end: from its line 1-3 mm back
    for k in range(len(ends)):
        back = (along[k] >= wppm) & (along[k] <= 3.0 * wppm)
        if back.any():
            v = at[k] - np.array([rr[back].mean(), cc[back].mean()])
            heading[k] = v / max(float(np.hypot(*v)), 1e-9)
    gap = at[None, :, :] - at[:, None, :]  # [i, j]: from end i to end j
    d = np.hypot(gap[..., 0], gap[..., 1])
    facing = (gap * heading[:, None, :]).sum(axis=2) >= _COS_UNDER * d
    pair = np.triu((d <= reach) & facing & facing.T & ~(along[:, ends] <= 2.0 * d + 2.0))
    i, j = np.nonzero(pair)
    return i, j, d[i, j]
