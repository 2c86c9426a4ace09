"""Synthetic trays of loose wires, with ground truth: seeded, fast, every scene kind.

A tray is an image (float in [0, 1], grey or colour) of wires lying in layers,
with each wire's centre line in millimetres and which of its ends a gripper
could take. Image coordinates: u = column, v = row, px = mm * px_per_mm.

Scene kinds: sparse, crossing (2-3 layers), low_contrast (uneven lighting),
bright_on_dark, stripped (thinner, shinier tips), colour, edge (wires running
off the image: an edge is not a wire end).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .common import FINGER_CLEARANCE_MM, GRASP_MM  # the ground truth's, as every finder's

KINDS = ("sparse", "crossing", "low_contrast", "bright_on_dark", "stripped", "colour", "edge")
END_MARGIN_MM = 3.0  # an end this close to the image border counts as cut by it
TOUCH_MM = 0.5  # wires closer than this, edge to edge, touch: taking one drags the other
UNSEEN_STEP_MM = 0.1  # Tray.unseen's grid


@dataclass
class Wire:
    centre: np.ndarray  # (N, 2) mm, the centre line from end 0 to end 1
    width: float  # mm
    layer: int  # higher lies on top
    level: tuple  # grey or RGB level of the insulation
    tip: float = 0.0  # mm of stripped conductor at each end (0: none)

    def point_at(self, end: int, s: float) -> np.ndarray:
        """The centre-line point s mm from the given end."""
        pts = self.centre if end == 0 else self.centre[::-1]
        seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
        cum = np.concatenate([[0.0], np.cumsum(seg)])
        s = min(max(s, 0.0), cum[-1])
        return np.array([np.interp(s, cum, pts[:, 0]), np.interp(s, cum, pts[:, 1])])


@dataclass
class End:
    wire: int
    end: int  # 0 or 1
    point: np.ndarray  # mm
    direction: np.ndarray  # unit vector from the end into the wire
    graspable: bool
    why: str = ""  # why not, when not


@dataclass
class Tray:
    image: np.ndarray
    px_per_mm: float
    wires: list[Wire]
    ends: list[End] = field(default_factory=list)
    kind: str = ""
    things: list = field(default_factory=list)  # what else lies on the tray (Thing)


    def judge(self, pick) -> tuple[str, float | None, float | None]:
        """(verdict, end error mm, direction error deg) for a finder's first pick (a Sighting or None).

        correct: the end within 1.5 mm of a graspable true end, its direction into the wire
        within 20 degrees, the grasp point on that wire 11-19 mm from the end and the
        tangent there within 15 degrees; no pick is correct only when nothing is graspable.
        foul: any other pick. miss: no pick although something was graspable."""
        if pick is None:
            return ("correct" if not any(e.graspable for e in self.ends) else "miss"), None, None
        m = self._measure(pick)
        return ("correct" if _correct(m) else "foul"), m["err"], m["ang"]

    def foul_cause(self, pick) -> str:
        """What makes a pick foul, in a few words ('' if it is correct, 'no pick' for a miss), the
        first that holds of: the end is not graspable (the ground truth's reason); the pick lies
        on that wire short of its end or past it by more than 1.5 mm (a conductor not followed
        to its tip, or a shadow or the board's print taken for wire); it is at no wire end at
        all; the direction into the wire is off by more than 20 degrees; the grasp point is off
        the wire, or not 11-19 mm along it; the tangent there is off by more than 15 degrees."""
        if pick is None:
            return "no pick" if any(e.graspable for e in self.ends) else ""
        m = self._measure(pick)
        if _correct(m):
            return ""
        truth, wire = m["truth"], self.wires[m["truth"].wire]
        if m["err"] > 1.5:
            if abs(m["across"]) <= wire.width / 2 + 0.75 and abs(m["along"]) <= 15.0:
                return "short of the end along its wire" if m["along"] > 0 else "past the end, on from its wire"
            return "at no wire end"
        if not truth.graspable:
            return f"an end not graspable: {truth.why}"
        if m["ang"] > 20:
            return "the direction into the wire is off"
        if not m["on_wire"]:
            return "the grasp point is off the wire"
        if not 11 <= m["arc"] <= 19:
            return "the grasp point is not 11-19 mm along"
        return "the tangent at the grasp point is off"

    def unseen(self, pick) -> float | None:
        """How much of the other wires that make a foul pick's true end not graspable no camera
        could see: the share (0-1) of their material inside the rule's region that wires drawn
        over them hide (0: all of it in view; 1: a wire lying wholly under the picked one there).
        The region: the FINGER_CLEARANCE_MM disc round the true grasp point, where the end leaves
        no room for the fingers; the strip within the wire's half width and TOUCH_MM of its first
        GRASP_MM + 5 mm, where another wire touches, crosses or lies on top of it. None for a
        pick that is correct or not at a true end, for an end that fails for another reason (the
        border, a thing on the tray), or where no other wire lies inside the region (the wire
        itself coming back)."""
        if pick is None:
            return None
        m = self._measure(pick)
        truth = m["truth"]
        if m["err"] > 1.5 or truth.graspable:  # (a correct pick's end is graspable)
            return None
        i, w = truth.wire, self.wires[truth.wire]
        step = UNSEEN_STEP_MM
        if "no room for the fingers" in truth.why:
            centre = w.point_at(truth.end, GRASP_MM)
            a = np.arange(-FINGER_CLEARANCE_MM + step / 2, FINGER_CLEARANCE_MM, step)  # (cells' centres)
            grid = np.stack(np.meshgrid(a, a), axis=-1).reshape(-1, 2)
            grid = grid[(grid * grid).sum(axis=1) <= FINGER_CLEARANCE_MM ** 2] + centre
        elif "another wire" in truth.why:
            from scipy.spatial import cKDTree

            span = np.array([w.point_at(truth.end, s) for s in np.arange(0.0, GRASP_MM + 5.0 + step / 2, step)])
            reach = w.width / 2 + TOUCH_MM
            lo, hi = span.min(axis=0) - reach, span.max(axis=0) + reach
            grid = np.stack(np.meshgrid(np.arange(lo[0] + step / 2, hi[0], step),
                                        np.arange(lo[1] + step / 2, hi[1], step)), axis=-1).reshape(-1, 2)
            grid = grid[cKDTree(span).query(grid)[0] <= reach]
        else:
            return None
        covers = [material_distance(o, grid) <= 0.0 for o in self.wires]
        top = np.full(len(grid), -1)
        for j in sorted(range(len(self.wires)), key=lambda j: self.wires[j].layer):  # as drawn: top layers last
            top[covers[j]] = j
        others = np.zeros(len(grid), bool)
        for j, cover in enumerate(covers):
            if j != i:
                others |= cover
        if not others.any():
            return None
        return float(np.count_nonzero(others & (top == i)) / np.count_nonzero(others))

    def margin(self, end: End) -> float:
        """end_margin of one of this tray's ends (mm: how far from the other side of the rule)."""
        extent = np.array([self.image.shape[1], self.image.shape[0]]) / self.px_per_mm
        return end_margin(self.wires, end.wire, end.end, extent, self.things)

    def nearness(self, pick) -> float | None:
        """How near the ground truth's rules the verdict on a first pick lies: the least change
        (mm) of the tray or the pick that would turn it over. A correct pick: the least of the
        end's room (margin) and how far its tip and its grasp point may still move (the tip 1.5
        mm less its error; the grasp point along the wire to 11 or 19 mm, across it to where it
        leaves it); a foul: the most by which any of those is over (all must be mended); a
        miss: the room of the roomiest graspable end; no pick where nothing is graspable: how far
        the nearest end is from being graspable. None for a foul whose direction or tangent is
        off (a matter of degrees, not millimetres)."""
        if pick is None:
            if any(e.graspable for e in self.ends):
                return max(self.margin(e) for e in self.ends if e.graspable)
            return -max((self.margin(e) for e in self.ends), default=-math.inf)
        m = self._measure(pick)
        rooms = [self.margin(m["truth"]), 1.5 - m["err"], 19.0 - m["arc"], m["arc"] - 11.0, m["on_wire_by"]]
        if _correct(m):
            return min(rooms)
        if m["ang"] > 20 or m["tan_err"] > 15:
            return None
        return -min(rooms)

    def _measure(self, pick) -> dict:
        """The pick against the true end nearest it: that end (truth), the end's error (err, mm)
        and its components along the true direction into the wire and across it (along, across),
        the direction's error (ang, degrees), whether the grasp point is on that wire (on_wire),
        how far along it (arc, mm) and the tangent's error there (tan_err, degrees)."""
        ppm = self.px_per_mm
        end = np.array(pick.end) / ppm
        truth = min(self.ends, key=lambda e: np.linalg.norm(e.point - end))
        off = end - truth.point
        err = float(np.linalg.norm(off))
        d = np.array([math.cos(math.radians(pick.end_angle)), math.sin(math.radians(pick.end_angle))])
        ang = math.degrees(math.acos(max(-1.0, min(1.0, float(d @ truth.direction)))))
        wire = self.wires[truth.wire]
        grasp = np.array(pick.grasp) / ppm
        pts = wire.centre if truth.end == 0 else wire.centre[::-1]
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])
        i = int(np.argmin(np.linalg.norm(pts - grasp, axis=1)))
        on_wire_by = wire.width / 2 + 0.75 - float(np.linalg.norm(pts[i] - grasp))  # (mm to spare)
        t = pts[min(i + 4, len(pts) - 1)] - pts[max(i - 4, 0)]
        tangent = math.degrees(math.atan2(t[1], t[0])) % 180.0
        tan_err = abs((pick.grasp_angle - tangent + 90.0) % 180.0 - 90.0)
        u = truth.direction
        return {"truth": truth, "err": err, "ang": ang, "on_wire": on_wire_by > 0, "on_wire_by": on_wire_by,
                "arc": float(arc[i]), "tan_err": tan_err,
                "along": float(off @ u), "across": float(off @ np.array([-u[1], u[0]]))}


def _correct(m: dict) -> bool:
    """Tray.judge's rule, on a pick's measurement (Tray._measure)."""
    return bool(m["truth"].graspable and m["err"] <= 1.5 and m["ang"] <= 20 and m["on_wire"] and 11 <= m["arc"] <= 19
                and m["tan_err"] <= 15)


def make_tray(kind: str = "sparse", seed: int = 0, size: int = 512, px_per_mm: float = 4.0,
              wires: int | None = None) -> Tray:
    """A tray of the given kind; the same seed gives the same tray."""
    if kind not in KINDS:
        raise ValueError(f"unknown scene kind {kind!r} (one of {', '.join(KINDS)})")
    rng = np.random.default_rng([seed, KINDS.index(kind)])
    extent = size / px_per_mm
    n = wires if wires is not None else {"sparse": 4, "crossing": 7, "edge": 5}.get(kind, 5)
    colour = kind == "colour"
    dark_tray = kind == "bright_on_dark"
    ws = []
    layers = 3 if kind == "crossing" else 1
    for i in range(n):
        ws.append(random_wire(rng, extent, kind, layer=int(rng.integers(layers)) if layers > 1 else i,
                               colour=colour, dark_tray=dark_tray))
    if kind == "sparse":
        ws = keep_apart(ws)
    image = render(ws, size, px_per_mm, kind, rng)
    tray = Tray(image, px_per_mm, ws, kind=kind)
    tray.ends = ground_truth(ws, extent)
    return tray


def random_wire(rng, extent: float, kind: str, layer: int, colour: bool, dark_tray: bool) -> Wire:
    length = rng.uniform(45.0, 90.0)
    margin = 8.0 if kind != "edge" else -25.0
    start = rng.uniform(margin, extent - margin, size=2) if margin > 0 else rng.uniform(-15, extent + 15, size=2)
    heading = rng.uniform(0, 2 * math.pi)
    bend = rng.normal(0.0, 0.007)
    steps = int(length / 0.5)
    pts = [start]
    for _ in range(steps):
        heading += bend + rng.normal(0.0, 0.006)
        pts.append(pts[-1] + 0.5 * np.array([math.cos(heading), math.sin(heading)]))
    centre = np.array(pts)
    if kind != "edge":  # keep the wire on the tray
        lo, hi = centre.min(axis=0), centre.max(axis=0)
        shift = np.clip(lo, 6.0, None) - lo + np.clip(hi, None, extent - 6.0) - hi
        centre = centre + shift
    if colour:
        level = tuple(float(x) for x in rng.choice([(0.75, 0.15, 0.1), (0.1, 0.55, 0.15), (0.15, 0.2, 0.7),
                                                    (0.8, 0.7, 0.1), (0.1, 0.1, 0.1)]))
    elif dark_tray:
        level = (float(rng.uniform(0.75, 0.95)),)
    elif kind == "low_contrast":
        level = (float(rng.uniform(0.45, 0.55)),)
    else:
        level = (float(rng.uniform(0.1, 0.3)),)
    tip = float(rng.uniform(4.0, 7.0)) if kind == "stripped" else 0.0
    return Wire(centre, float(rng.uniform(1.6, 2.4)), layer, level, tip)


def keep_apart(ws: list[Wire]) -> list[Wire]:
    """For sparse trays: the wires that stay 6 mm clear of every earlier one kept."""
    from scipy.spatial import cKDTree

    kept: list[Wire] = []
    for w in ws:
        if all(cKDTree(k.centre).query(w.centre)[0].min() > (w.width + k.width) / 2 + 6.0 for k in kept):
            kept.append(w)
    return kept or ws[:1]


def render(ws: list[Wire], size: int, px_per_mm: float, kind: str, rng, noise: float = 0.02) -> np.ndarray:
    """The image of wires on a tray of the kind's background (top layers drawn last), with noise."""
    from scipy import ndimage

    channels = 3 if kind == "colour" else 1
    background = {"bright_on_dark": 0.15, "low_contrast": 0.62, "colour": 0.85}.get(kind, 0.8)
    img = np.full((size, size, channels), background)
    for w in sorted(ws, key=lambda w: w.layer):
        pts = w.centre * px_per_mm
        r = w.width * px_per_mm / 2
        lo = np.floor(pts.min(axis=0) - r - 2).astype(int)
        hi = np.ceil(pts.max(axis=0) + r + 2).astype(int)
        c0, r0 = max(lo[0], 0), max(lo[1], 0)
        c1, r1 = min(hi[0], size), min(hi[1], size)
        if c0 >= c1 or r0 >= r1:
            continue
        # the centre line, densely sampled, on a 2x finer local grid; distances by EDT
        fine = np.zeros((2 * (r1 - r0), 2 * (c1 - c0)), bool)
        dense = resample(pts, 0.25)
        fu = np.round((dense[:, 0] - c0) * 2 + 0.5).astype(int)
        fv = np.round((dense[:, 1] - r0) * 2 + 0.5).astype(int)
        ok = (fu >= 0) & (fu < fine.shape[1]) & (fv >= 0) & (fv < fine.shape[0])
        fine[fv[ok], fu[ok]] = True
        dist = ndimage.distance_transform_edt(~fine) / 2.0
        cover = np.clip(r - dist + 0.5, 0.0, 1.0)
        cover = cover * _inside_ends(w, fine.shape, (r0, c0), px_per_mm)  # cut wires end flat
        cover = cover.reshape(r1 - r0, 2, c1 - c0, 2).mean(axis=(1, 3))
        shade = np.array(w.level, float).reshape(1, 1, -1)
        if kind == "bright_on_dark":
            profile = np.clip(1.0 - dist / max(r, 1e-6), 0.0, 1.0).reshape(r1 - r0, 2, c1 - c0, 2).mean(axis=(1, 3))
            shade = shade * (0.8 + 0.2 * profile[..., None])  # a round, shiny wire
        if w.tip > 0:
            cover, shade = _stripped_tips(w, cover, shade, dist, r, px_per_mm, (r0, c0))
        region = img[r0:r1, c0:c1]
        region[:] = region * (1 - cover[..., None]) + np.broadcast_to(shade, region.shape) * cover[..., None]
    if kind == "low_contrast":
        yy, xx = np.mgrid[0:size, 0:size] / size
        light = 0.75 + 0.45 * (0.6 * xx + 0.4 * yy) + 0.1 * np.sin(3 * xx + 1.0)
        img = img * light[..., None]
    if noise > 0:
        img = img + rng.normal(0.0, noise, img.shape)
    img = np.clip(img, 0.0, 1.0)
    return img[..., 0] if channels == 1 else img


def _inside_ends(w: Wire, fine_shape, origin, px_per_mm) -> np.ndarray:
    """Coverage factor (on the 2x grid) that cuts the wire square at both ends."""
    rows, cols = np.mgrid[0:fine_shape[0], 0:fine_shape[1]]
    u = (cols / 2.0 + origin[1]) / px_per_mm
    v = (rows / 2.0 + origin[0]) / px_per_mm
    keep = np.ones(fine_shape)
    for end in (0, 1):
        p = w.point_at(end, 0.0)
        q = w.point_at(end, 1.0)
        inward = (q - p) / max(np.linalg.norm(q - p), 1e-9)
        ahead = (u - p[0]) * inward[0] + (v - p[1]) * inward[1]  # mm past the end face, inwards
        near = np.hypot(u - p[0], v - p[1]) < 2 * w.width
        keep = np.where(near, keep * np.clip(ahead * px_per_mm * 2 + 0.5, 0.0, 1.0), keep)
    return keep


def _stripped_tips(w: Wire, cover, shade, dist, r, px_per_mm, origin):
    """Within w.tip mm of either end, the wire is the thinner, brighter conductor."""
    rows, cols = np.mgrid[0:cover.shape[0], 0:cover.shape[1]]
    u = (cols + origin[1] + 0.5) / px_per_mm
    v = (rows + origin[0] + 0.5) / px_per_mm
    near_tip = np.zeros(cover.shape, bool)
    for end in (0, 1):
        p = w.point_at(end, 0.0)
        q = w.point_at(end, w.tip)
        axis = (q - p) / max(np.linalg.norm(q - p), 1e-9)
        along = (u - p[0]) * axis[0] + (v - p[1]) * axis[1]
        near_tip |= (along < w.tip) & (np.hypot(u - p[0], v - p[1]) < w.tip + w.width)
    thin = np.clip(0.55 * r - dist + 0.5, 0.0, 1.0).reshape(cover.shape[0], 2, cover.shape[1], 2).mean(axis=(1, 3))
    cover = np.where(near_tip, thin, cover)
    copper = np.full_like(shade, 0.95)
    shade = np.where(near_tip[..., None], copper, np.broadcast_to(shade, (*cover.shape, shade.shape[-1])))
    return cover, shade


def resample(pts: np.ndarray, step: float) -> np.ndarray:
    seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    # evenly at most step apart, from end to end: no point past the end (np.interp would repeat the
    # end, and a repeated point has no tangent)
    n = max(math.ceil(cum[-1] / step - 1e-6), 1)
    s = np.linspace(0.0, cum[-1], n + 1)
    return np.stack([np.interp(s, cum, pts[:, 0]), np.interp(s, cum, pts[:, 1])], axis=1)


@dataclass
class Thing:
    """Something on the tray that is not a wire (a screw, a blob of glue, the tray's rim): an end
    that touches it, or a grasp point near it, is not free. A disc (centre, radius) or a box
    (lo, hi corners), in mm."""

    name: str
    centre: np.ndarray | None = None
    radius: float = 0.0
    lo: np.ndarray | None = None
    hi: np.ndarray | None = None

    def distance(self, points: np.ndarray) -> np.ndarray:
        """Each point's distance (mm) to the thing (0 inside)."""
        points = np.atleast_2d(points)
        if self.centre is not None:
            return np.maximum(np.linalg.norm(points - self.centre, axis=1) - self.radius, 0.0)
        assert self.lo is not None and self.hi is not None
        outside = np.maximum(np.maximum(self.lo - points, points - self.hi), 0.0)
        return np.linalg.norm(outside, axis=1)


def ground_truth(ws: list[Wire], extent, things: tuple | list = ()) -> list[End]:
    """Every wire end, and whether a gripper could take it; extent is the image's size in mm
    (a number for a square image, or (width, height)); things are what else lies on the tray."""
    extent = np.broadcast_to(np.asarray(extent, float), (2,))
    ends = []
    for i, w in enumerate(ws):
        for e in (0, 1):
            p = w.point_at(e, 0.0)
            d = w.point_at(e, 1.0) - p
            d = d / max(np.linalg.norm(d), 1e-9)
            ok, why = _graspable(ws, i, e, extent, things)
            ends.append(End(i, e, p, d, ok, why))
    return ends


def material_distance(wire: Wire, points: np.ndarray) -> np.ndarray:
    """Each point's distance (mm) to the wire itself: its centre line widened by half its width,
    cut off at the ends of the centre line (0 inside the wire)."""
    from scipy.spatial import cKDTree

    dense = resample(wire.centre, 0.25)
    keep = np.concatenate([[True], np.linalg.norm(np.diff(dense, axis=0), axis=1) > 1e-6])
    dense = dense[keep]  # resampling may repeat the last point
    d, i = cKDTree(dense).query(points)
    out = np.maximum(d - wire.width / 2, 0.0)
    for idx, nxt in ((0, 1), (len(dense) - 1, len(dense) - 2)):
        at = i == idx
        if not at.any():
            continue
        axis = dense[idx] - dense[nxt]
        axis = axis / max(float(np.linalg.norm(axis)), 1e-9)  # out of the wire
        rel = points[at] - dense[idx]
        axial = rel @ axis
        lateral = np.abs(rel @ np.array([-axis[1], axis[0]]))
        beyond = np.hypot(np.maximum(axial, 0.0), np.maximum(lateral - wire.width / 2, 0.0))
        out[at] = np.where(axial > 0, beyond, out[at])
    return out


def _graspable(ws: list[Wire], i: int, end: int, extent: np.ndarray, things=()) -> tuple[bool, str]:
    for room, why in _rules(ws, i, end, extent, things):
        if room < 0:
            return False, why
    return True, ""


def end_margin(ws: list[Wire], i: int, end: int, extent, things=()) -> float:
    """How far (mm) wire i's end lies from the other side of the ground truth's rule: for a
    graspable end, the least room any of its tests leaves (by how much the nearest other wire,
    thing or border could come nearer before it would not be graspable); for one that is not,
    minus the most by which a test fails (how much nearer than allowed the worst of them is)."""
    extent = np.broadcast_to(np.asarray(extent, float), (2,))
    return min(room for room, _ in _rules(ws, i, end, extent, things))


def _rules(ws: list[Wire], i: int, end: int, extent: np.ndarray, things=()):
    """The ground truth's tests of wire i's end, in order: (room, why) for each, room the mm by
    which it passes (negative: fails), why what a failure means."""
    w = ws[i]
    span = np.array([w.point_at(end, s) for s in np.arange(0.0, GRASP_MM + 5.0, 0.5)])
    yield min(float(span.min()) - END_MARGIN_MM, float((extent - END_MARGIN_MM - span).min())), \
        "off the image or cut by its border"
    grasp = w.point_at(end, GRASP_MM)
    own = resample(w.centre if end == 0 else w.centre[::-1], 0.5)
    skip = int((GRASP_MM + 5.0 + 2 * w.width + FINGER_CLEARANCE_MM) / 0.5)
    if len(own) > skip + 1:  # the same wire, further on, coming back (a loop)
        rest = Wire(own[skip:], w.width, w.layer, w.level)
        yield float(material_distance(rest, span).min()) - w.width / 2 - TOUCH_MM, \
            "it crosses or touches itself near its end"
        yield float(material_distance(rest, grasp[None, :])[0]) - FINGER_CLEARANCE_MM, \
            "no room for the fingers at the grasp point"
    for thing in things:
        yield float(thing.distance(span).min()) - w.width / 2 - TOUCH_MM, f"it touches {thing.name} near its end"
        yield float(thing.distance(grasp[None, :])[0]) - FINGER_CLEARANCE_MM, "no room for the fingers at the grasp point"
    for j, other in enumerate(ws):
        if j == i:
            continue
        gap = float(material_distance(other, span).min()) - w.width / 2  # edge to edge
        if gap < 0 and other.layer > w.layer:
            yield gap - TOUCH_MM, "another wire lies on top of it"
        yield float(material_distance(other, grasp[None, :])[0]) - FINGER_CLEARANCE_MM, \
            "no room for the fingers at the grasp point"
        yield gap - TOUCH_MM, "it crosses or touches another wire near its end"
