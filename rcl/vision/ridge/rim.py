"""A tray's rim, or the bench round the tray, along the frame's sides: neither board nor a
thing on it."""
from __future__ import annotations

import numpy as np

RIM_SCAN_MM = 25.0  # a tray's rim (or the bench round the tray) is looked for this far in from each side,
RIM_SCAN_SHARE = 0.1  # ... or this share of the frame across it where that is more (a fifth at most)
RIM_MIN_MM = 1.5  # ... at least this wide
RIM_SEGMENT_MM = 8.0  # ... in segments of the side this long: each its own profile (a median across it)
RIM_BOARD_MM = 3.0  # ... against this much board next to it
RIM_STEP = 0.03  # ... differing from the board by this much (0-1 colour)
RIM_BOARD_LOW, RIM_BOARD_HIGH = 20, 80  # ... whose spread is judged between these percentiles
RIM_CLEAR = 4.0  # ... this many times more than the band or the board varies
RIM_SHARE = 0.6  # ... along this share of the side's segments
RIM_SHARE_SQUARE = 0.4  # ... or along this share, where their edges lie on one straight line square to the
RIM_SQUARE_SLOPE = 0.01  # ... frame (sloping by no more than this): a wire along the rim, or a printed
# board's patches next to it, hide the step in the other segments
RIM_BEND_PX = 1.5  # ... on one smooth curve (a lens bows a straight rim) to within this
RIM_BOW = 0.02  # ... bowing no more than this share of the side's length off a straight line
RIM_EDGE_MM = 1.0  # the blur of a rim's edge: samples this near it say nothing of what lies round an end


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
        depth = min(int(0.2 * m), max(int(RIM_SCAN_MM * wppm), int(RIM_SCAN_SHARE * m)))
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
        centres = np.arange(nseg) * seg + seg / 2
        coef = _smooth_curve(centres, edges, ok, n)
        if coef is None:
            coef = _square_line(centres, edges, ok)
        if coef is None:
            continue
        k = np.clip(np.polyval(coef, np.arange(n)) + 1.0, 0, depth)
        mask = side(outside)
        mask |= np.arange(m)[None, :] < k[:, None]
    return outside


def _smooth_curve(centres: np.ndarray, edges: np.ndarray, ok: np.ndarray, n: int) -> np.ndarray | None:
    """The quadratic through the edges found (`ok`) that RIM_SHARE of the side's segments lie on
    to within RIM_BEND_PX, or None: fitted to them all, then refitted without the one furthest
    off while any is further than that (one segment's edge found on a wire or the board's print
    across the band must not pull the curve off all the others). A lens bows a straight rim a
    little; a curve bowing more than RIM_BOW of the side's length (n px) is no rim but light
    falling off towards the frame's edge, or what lies beyond a tray seen aslant."""
    coef = _fit_edges(centres, edges, ok, RIM_SHARE, 2, 0)
    return coef if coef is not None and abs(coef[0]) * n * n / 4 <= RIM_BOW * n else None  # (the bow off the chord)


def _square_line(centres: np.ndarray, edges: np.ndarray, ok: np.ndarray) -> np.ndarray | None:
    """The straight line (as a quadratic's coefficients) that RIM_SHARE_SQUARE of the side's
    segments lie on to within RIM_BEND_PX, sloping by RIM_SQUARE_SLOPE at most, or None: fewer
    segments than a curve needs, but a step at one depth along the side is a tray's edge seen
    square on, not a board's print or light (those slope or bow)."""
    coef = _fit_edges(centres, edges, ok, RIM_SHARE_SQUARE, 1, 3)
    return None if coef is None or abs(coef[0]) > RIM_SQUARE_SLOPE else np.concatenate([[0.0], coef])


def _fit_edges(centres: np.ndarray, edges: np.ndarray, ok: np.ndarray, share: float, degree: int,
               least: int) -> np.ndarray | None:
    """The polynomial of that degree through the edges found (`ok`) that `share` of the
    segments, and `least` of them, lie on to within RIM_BEND_PX: fitted to them all, then
    refitted without the one furthest off while any is further than that; None once fewer remain."""
    ok = ok.copy()
    while ok.mean() >= share and ok.sum() >= least:
        coef = np.polyfit(centres[ok], edges[ok], degree)
        off = np.where(ok, np.abs(np.polyval(coef, centres) - np.nan_to_num(edges)), 0.0)
        if off.max() <= RIM_BEND_PX:
            return coef
        ok[int(off.argmax())] = False
    return None


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
    low, b, high = _percentiles(windows, (RIM_BOARD_LOW, 50, RIM_BOARD_HIGH))  # each (nseg, K, ch)
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


def _percentiles(a: np.ndarray, qs: tuple) -> list[np.ndarray]:
    """np.percentile(a, q, axis=-1) for each q (its linear method, computed as it computes it),
    from one sort of the last axis: on the rim's many short windows a sort is several times
    quicker than np.percentile's partitions."""
    s = np.sort(a, axis=-1)
    n = s.shape[-1]
    out = []
    for q in qs:
        virtual = (n - 1) * (np.float64(q) / 100.0)
        lo = int(virtual)  # (q in 0-100: 0 <= virtual <= n - 1)
        gamma = virtual - lo
        below, above = s[..., lo], s[..., min(lo + 1, n - 1)]
        diff = above - below
        out.append(above - diff * (1.0 - gamma) if gamma >= 0.5 else below + diff * gamma)
    return out
