"""The tray of loose wires: what lies where, in which layer, and its picture.

Positions are tray millimetres: (0, 0) is the tray's corner at the world point
`origin`, x and y run along the world's X and Y. Wires keep the number they
were given when the tray was made, whatever happens to them later.

How the tray looks is drawn by the randomized tray generator
(rcl.vision.scenes) from the tray's own seed: the board and its texture, each
wire's shape, thickness, insulation and ends, the lamp and its shadows, blur,
noise. `look` names a slice of the generator to draw from instead of all of it
("plain_dark": the paper's dark wires on a plain light board).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..vision import scenes
from ..vision.synth import Wire, resample

PICTURE_PX_PER_MM = 4.0  # the tray picture the camera looks at; the camera resamples it
DRAPE_SPLAY = 0.6  # a dropped wire's halves fall this far (radians, sd) from opposite ways ...
DRAPE_CURVE = 0.01  # ... each with a steady bend of this (radians per 0.5 mm, sd) ...
DRAPE_BEND = 0.03  # ... and this much random turning per 0.5 mm


@dataclass
class Touch:
    """The wire nearest a point: its number, distance (mm) from its centre line, the nearest
    centre-line point and the wire's unit tangent there."""

    wire: int
    distance: float
    point: np.ndarray
    tangent: np.ndarray


class WireTray:
    """Wires lying on a square tray of side size_mm; top layers are drawn last."""

    def __init__(self, size_mm: float, origin_xy, rng: np.random.Generator, count: int, layers: int,
                 look: str = "random") -> None:
        self.size = float(size_mm)
        self.origin = np.array(origin_xy, float)
        self.rng = rng
        px = round(self.size * PICTURE_PX_PER_MM)
        self.scene = scenes.tray_scene(rng, px, px, PICTURE_PX_PER_MM, count, layers,
                                       None if look == "random" else look)
        extent = np.array([self.size, self.size])
        self.wires: dict[int, Wire] = {}
        self.looks: dict[int, scenes.WireLook] = {}
        for i in range(count):
            w = scenes.random_wire(rng, self.scene, extent, i)
            lk = scenes.wire_look(rng, self.scene)
            w.level, w.tip = lk.colour, max(lk.tip_mm)
            self.wires[i + 1], self.looks[i + 1] = w, lk
        self._board_seed = int(rng.integers(2**63))
        self._board: np.ndarray | None = None
        self._dense: dict[int, np.ndarray] = {}
        self._picture: np.ndarray | None = None
        self.changes = 0  # how many times a wire has been taken, laid, pushed or shaken

    def __len__(self) -> int:
        return len(self.wires)

    # What lies where --------------------------------------------------------------

    def dense(self, number: int) -> np.ndarray:
        """The wire's centre line sampled every 0.25 mm."""
        d = self._dense.get(number)
        if d is None:
            d = self._dense[number] = resample(self.wires[number].centre, 0.25)
        return d

    def touch(self, number: int, p) -> Touch:
        pts = self.dense(number)
        d = np.hypot(pts[:, 0] - p[0], pts[:, 1] - p[1])
        i = int(np.argmin(d))
        a, b = pts[max(i - 4, 0)], pts[min(i + 4, len(pts) - 1)]
        t = (b - a) / max(float(np.linalg.norm(b - a)), 1e-9)
        return Touch(number, float(d[i]), pts[i].copy(), t)

    def nearest(self, p, within: float = math.inf) -> list[Touch]:
        """Every wire whose centre line passes within `within` mm of p, nearest first."""
        found = [t for n in self.wires if (t := self.touch(n, p)).distance <= within]
        return sorted(found, key=lambda t: t.distance)

    def inside(self, p, margin: float = 0.0) -> bool:
        return bool(margin <= p[0] <= self.size - margin and margin <= p[1] <= self.size - margin)

    def to_tray(self, xy) -> np.ndarray:
        return np.asarray(xy, float)[..., :2] - self.origin

    # Changes ----------------------------------------------------------------------

    def remove(self, number: int) -> Wire:
        self._changed(number)
        return self.wires.pop(number)

    def put(self, number: int, centre: np.ndarray, wire: Wire) -> None:
        """A wire laid (back) on the tray along centre (tray mm), on top of every other."""
        top = max((w.layer for w in self.wires.values()), default=0) + 1
        self.wires[number] = Wire(np.asarray(centre, float), wire.width, top, wire.level, wire.tip)
        if number not in self.looks:  # a wire new to the tray: it looks like the others
            self.looks[number] = scenes.wire_look(self.rng, self.scene)
        self._changed(number)

    def drape(self, number: int, wire: Wire, at, arc: float) -> None:
        """A wire that hung from the fingers by a point `arc` mm along it, let go at tray point
        `at`: its two halves fall from there, each in a gentle random curve (DRAPE_BEND), in
        directions about opposite, and it lies on top of the others in that new shape (a loop
        it had is gone)."""
        length = float(np.sum(np.linalg.norm(np.diff(wire.centre, axis=0), axis=1)))
        heading = self.rng.uniform(0.0, 2 * math.pi)
        halves = []
        for run, head in ((arc, heading), (length - arc, heading + math.pi + self.rng.normal(0.0, DRAPE_SPLAY))):
            steps = max(int(round(run / 0.5)), 1)
            turns = head + np.cumsum(self.rng.normal(self.rng.normal(0.0, DRAPE_CURVE), DRAPE_BEND, steps))
            halves.append(np.cumsum(0.5 * np.column_stack([np.cos(turns), np.sin(turns)]), axis=0))
        centre = np.vstack([halves[0][::-1], [[0.0, 0.0]], halves[1]]) + np.asarray(at, float)[:2]
        self.put(number, self.kept_on(centre), wire)

    def nudge(self, p, radius: float, push_mm: float, turn_deg: float) -> list[int]:
        """The wires passing within radius of p pushed aside (fingers closing on the wrong spot)."""
        moved = [t.wire for t in self.nearest(p, radius)]
        for n in moved:
            w = self.wires[n]
            shift = self.rng.normal(0.0, push_mm / 2, 2)
            w.centre = self.kept_on(_turned(w.centre, p, self.rng.normal(0.0, turn_deg / 2)) + shift)
            self._changed(n)
        return moved

    def shake(self) -> None:
        """The tray vibrated: every wire slides and turns a little and the pile settles anew."""
        numbers = list(self.wires)
        order = self.rng.permutation(len(numbers))
        for rank, n in zip(order, numbers):
            w = self.wires[n]
            centre = _turned(w.centre, w.centre.mean(axis=0), self.rng.uniform(-40.0, 40.0))
            centre = centre + self.rng.uniform(-20.0, 20.0, 2)
            w.centre = self.kept_on(centre)
            w.layer = int(rank)
            self._changed(n)

    def kept_on(self, centre: np.ndarray) -> np.ndarray:
        lo, hi = centre.min(axis=0), centre.max(axis=0)
        shift = np.clip(lo, 4.0, None) - lo + np.clip(hi, None, self.size - 4.0) - hi
        return centre + shift

    def _changed(self, number: int) -> None:
        self.changes += 1
        self._dense.pop(number, None)
        self._picture = None

    # The picture ------------------------------------------------------------------

    def picture(self) -> np.ndarray:
        """The tray lit and seen from straight above, (h, w, 3), PICTURE_PX_PER_MM px per mm,
        before the camera (its lens, light falloff, blur and noise) makes an image of it."""
        if self._picture is None:
            if self._board is None:
                self._board = scenes.backdrop(self.scene, np.random.default_rng(self._board_seed))
            numbers = list(self.wires)
            self._picture = scenes.paint(self.scene, [self.wires[n] for n in numbers],
                                         [self.looks[n] for n in numbers], self._board)
        return self._picture


def _turned(points: np.ndarray, about, deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    d = points - np.asarray(about, float)
    return np.asarray(about, float) + d @ np.array([[c, s], [-s, c]])
