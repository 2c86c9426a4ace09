"""SimCell: the simulated work cell: tray, camera, arm, gripper, press and solder bath.

The arm and the camera it hands out implement the same interfaces as real
hardware (rcl.robots.Robot, grab() -> image), so whatever drives a real cell
drives this one. What the cell adds is the physics a task meets:

- the arm's real position strays smoothly from the commanded one by 1-3 mm
  (the paper's "manipulator inaccuracy"), plus a little random scatter;
- the camera renders a fresh picture of the tray as it now is, through a
  tilted lens with radial distortion, and shows the calibration disc on the
  closed fingertips when they are low over the tray (the arm itself is not
  drawn: a task looks with the arm out of the way);
- the tray stands on a load cell that tells whether any wire is left;
- closing the gripper takes a wire only when the fingers close within about
  1 mm of its centre line, square to it, where it lies on top with room for
  the fingers; a miss pushes the wires there aside. The fingers centre the
  wire between them but do not turn it. A taken wire may slip out on the way;
- the press crimps when the held wire's end sits in the die, near its axis,
  along it and deep enough; the bath tins an end dipped to the right depth for
  long enough; a wire released away from the tray leaves the cell (done if
  crimped or tinned, rejected otherwise); released over the tray it lies there
  again.

The stations are where the cell file says, as taught: the die and the solder
surface lie where the arm really takes a wire end when it is sent to the
station's frame holding the wire 15 mm from its end, so the arm's inaccuracy
there is already allowed for, as it is when a real station is taught by
leading the arm to it.
"""
from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from ..camera.simulated import PinholeCamera, render_disc
from ..frame import Frame
from ..robots import Robot, SimRobot
from ..vision.scenes import finish
from ..vision.synth import Wire, resample
from .config import CellConfig
from .optics import TrayView
from .tray import PICTURE_PX_PER_MM, WireTray

BENCH = (0.35, 0.35, 0.36)  # the bench round the tray
MARKER_RADIUS_MM = 3.0  # the calibration marker: a white disc of this radius ...
MARKER_PAD_MM = 6.0  # ... on a black pad of this radius, so that it is seen on any board and over wires
MARKER_LEVEL, MARKER_PAD_LEVEL = 0.97, 0.06
MARKER_SEEN_BELOW_MM = 20.0  # the disc on the closed fingertips is seen when they are this low over the tray
PICK_BELOW_MM = 50.0  # closing the fingers lower than this over the tray is a pick
NOMINAL_GRASP_MM = 15.0  # how far from the end a station's frame assumes the wire is held
RELEASE_ON_TRAY_BELOW_MM = 80.0
SHAKE_SECONDS = 2.0
MIDDLE_HOLD_MM = 20.0  # a wire held this far or more from both its ends hangs from the fingers


class Inaccuracy:
    """The arm's smooth position error: a fixed offset of 0.9 `size` mm in a seeded direction
    plus a ripple of 0.3 `size` mm along each axis (0.1 `size` vertically) with wavelengths of
    100-160 mm over the workspace: for size 2, 1-2.7 mm in all, varying by up to ~1.5 mm over
    the tray in a way no linear camera model can follow."""

    def __init__(self, size: float, seed: int) -> None:
        rng = np.random.default_rng([seed, 7])
        heading = rng.uniform(0, 2 * math.pi)
        self.offset = 0.9 * size * np.array([math.cos(heading), math.sin(heading), 0.0])
        self.ripple = np.array([0.3, 0.3, 0.1]) * size
        dirs = rng.normal(size=(3, 3))
        waves = rng.uniform(100.0, 160.0, 3)
        self.k = 2 * math.pi * dirs / np.linalg.norm(dirs, axis=1, keepdims=True) / waves[:, None]
        self.phase = rng.uniform(0, 2 * math.pi, 3)

    def __call__(self, p) -> np.ndarray:
        """The error (mm) at commanded position p (mm)."""
        return self.offset + self.ripple * np.sin(self.k @ np.asarray(p, float)[:3] + self.phase)


@dataclass
class Held:
    wire: int
    body: Wire
    shape: np.ndarray  # (4, N) the centre line in the tool frame, homogeneous
    crimped: bool = False
    tinned: bool = False
    burnt: bool = False
    dipped: float = 0.0  # seconds in the solder at the right depth
    note: str = ""  # why the last station visit did not work
    carried: bool = False  # has moved since it was taken


@dataclass
class Event:
    what: str  # pick (a slip on the way up is a failed pick too), press, bath, release, putback, drop, shake
    ok: bool
    wire: int | None
    look: int  # the number of the image the task looked at last (1-based; 0: none yet)
    why: str = ""
    time_s: float = 0.0
    off_mm: float | None = None  # a pick: how far from the wire's centre line the fingers closed
    slip: bool = False  # a failed pick that is no new attempt: the wire taken slipped out on the way

    def as_dict(self) -> dict:
        d = {"what": self.what, "ok": self.ok, "wire": self.wire, "look": self.look, "why": self.why,
             "time_s": round(self.time_s, 3)}
        if self.off_mm is not None:
            d["off_mm"] = round(self.off_mm, 3)
        return d


@dataclass
class Die:
    """A station as the cell really has it: the point the wire end must reach and the way in."""

    target: np.ndarray
    axis: np.ndarray  # unit, the direction the end travels in


class SimCell:
    """The simulated cell of a description, with a tray made from seed (wires: (low, high) to
    override the description's count)."""

    def __init__(self, config: CellConfig, seed: int = 0, wires: Sequence[int] | None = None) -> None:
        self.config = config
        cam, tray, robot = config["camera"], config["tray"], config["robot"]
        self.rng = np.random.default_rng([seed, 1])
        low, high = wires if wires is not None else tray["wires"]
        size = float(tray["size_mm"])
        centre = np.array(tray["centre"], float)
        self.tray_z = float(tray["z"])
        self.tray = WireTray(size, centre - size / 2, np.random.default_rng([seed, 2]),
                             int(self.rng.integers(low, high + 1)), int(tray["layers"]), tray["look"])
        self.optics = dataclasses.replace(self.tray.scene, noise=float(cam["noise"]))
        self.wires_total = len(self.tray)
        lens = PinholeCamera.over_tray(centre_xy=tuple(centre), height_mm=cam["height_mm"], fov_mm=cam["fov_mm"],
                                       width=int(cam["width"]), tilt_deg=cam["tilt_deg"], k1=cam["k1"], k2=cam["k2"])
        self.lens = dataclasses.replace(lens, pose=(Frame.trans(0.0, 0.0, self.tray_z) * Frame(lens.pose)).matrix)
        self._view: TrayView | None = None
        self.Z = config.frame("Z").matrix
        self.E = config.frame("E").matrix
        self.error = Inaccuracy(float(robot["inaccuracy_mm"]), int(robot["seed"]))
        self.scatter = float(robot["repeatability_mm"])
        self.jitter = np.zeros(3)
        self.g, self.press_cfg, self.bath_cfg = config["gripper"], config["press"], config["bath"]
        self.press = self._station("PRESS") if "PRESS" in config["frames"] else None
        self.bath = self._station("BATH") if "BATH" in config["frames"] else None
        self.arm = CellArm(SimRobot(config.model()), self)
        self.camera = CellCamera(self)
        self.held: Held | None = None
        self.attempts = 0
        self.events: list[Event] = []
        self.last_taken: int | None = None  # the wire the fingers' last close on the tray took
        self.last_failure = ""  # what failed last, in the words of the events
        self.results: dict[int, str] = {}  # wire -> crimped, tinned, rejected, lost
        self.on_event: Callable[[Event], None] | None = None  # told of every event, once it is recorded

    @property
    def view(self) -> TrayView:
        if self._view is None:  # computed at the first look: a cell that never looks does not pay
            self._view = TrayView(self.lens, self.tray_z)
        return self._view

    def _station(self, name: str) -> Die:
        f = self.config.frame(name)
        tool = (f * Frame.trans(0, 0, NOMINAL_GRASP_MM) * Frame.roty(-90)).matrix
        wire_over_tool = 1.0 * -tool[:3, 2]  # a 2 mm wire lies 1 mm beyond the fingertips
        target = f.matrix[:3, 3] + self.error(tool[:3, 3]) + wire_over_tool
        return Die(target, -f.matrix[:3, 2])

    # Where the tool really is ---------------------------------------------------------

    def tool(self) -> np.ndarray:
        """The real pose of the tool (fingertips) in the world."""
        t = self.Z @ self.arm.inner.here() @ self.E
        t[:3, 3] += self.error(t[:3, 3]) + self.jitter
        return t

    def _event(self, what: str, ok: bool, wire: int | None, why: str = "") -> Event:
        e = Event(what, ok, wire, self.camera.grabs, why, self.arm.inner.clock)
        self.events.append(e)
        if not ok:
            self.last_failure = f"{what} failed: {why}"
        if self.on_event is not None:
            self.on_event(e)
        return e

    # The camera ---------------------------------------------------------------------

    def grab(self) -> np.ndarray:
        """What the camera sees now: the tray through the lens, the marker on the closed
        fingertips when they are low over the tray, then the scene's light falloff, blur, noise
        (the cell file's), grey or colour and JPEG."""
        img = self.view.look(self.tray.picture(), tuple(self.tray.origin), PICTURE_PX_PER_MM, BENCH)
        t = self.tool()
        p = t[:3, 3]
        height = p[2] - self.tray_z
        if not self.arm.inner.gripper_open and t[2, 2] < -0.9 and -1.0 <= height <= MARKER_SEEN_BELOW_MM:
            u, v = self.lens.project(*p)
            scale = self.lens.focal_px / float(self.lens.depth(*p))
            for radius, level in ((MARKER_PAD_MM, MARKER_PAD_LEVEL), (MARKER_RADIUS_MM, MARKER_LEVEL)):
                cover = render_disc(img.shape[:2], (float(u), float(v)), radius * scale, 1.0, 0.0)[..., None]
                img = img * (1.0 - cover) + level * cover
        return finish(self.optics, img, self.rng).astype(np.float32)

    # The gripper --------------------------------------------------------------------

    def closed(self) -> None:
        if self.held is not None:
            return
        t = self.tool()
        p = self.tray.to_tray(t[:3, 3])
        height = t[2, 3] - self.tray_z
        if not self.tray.inside(p) or height > PICK_BELOW_MM:
            return  # closing in the air: not a pick
        self.attempts += 1
        touches = self.tray.nearest(p)  # every wire, nearest first
        nearest = touches[0] if touches and touches[0].distance <= 6.0 else None
        taken = self._grasp(t, p, height, touches)
        if isinstance(taken, str):  # why not
            self.last_taken = None
            event = self._event("pick", False, nearest.wire if nearest else None, taken)
            if height <= self.g["height_mm"]:
                self.tray.nudge(p, 4.0, 2.0, 6.0)
            event.off_mm = nearest.distance if nearest else None
        else:
            self.held, self.last_taken = taken, taken.wire
            self._event("pick", True, taken.wire).off_mm = next(k.distance for k in touches if k.wire == taken.wire)

    def _grasp(self, t: np.ndarray, p: np.ndarray, height: float, touches: list) -> Held | str:
        """Close the fingers at the real tool pose t (p: its tray point): the wire taken (off the
        tray now), else why not."""
        g = self.g
        if t[2, 2] > -math.cos(math.radians(30)):
            return "the fingers did not point down into the tray"
        if height > g["height_mm"]:
            return f"the fingers closed {height:.1f} mm above the tray, over the wires"
        if height < -1.0:
            return f"the fingers were driven {-height:.1f} mm into the tray"
        near = [k for k in touches if k.distance <= g["tolerance_mm"]]
        if not near:
            far = f"{touches[0].distance:.1f} mm" if touches else "nothing"
            return f"the fingers closed on nothing: the nearest centre line was {far} away"
        touch = max(near, key=lambda k: self.tray.wires[k.wire].layer)
        wire = self.tray.wires[touch.wire]
        closing = t[:2, 1] / max(float(np.linalg.norm(t[:2, 1])), 1e-9)
        off_square = 90.0 - _angle_deg(closing, touch.tangent, sign=False)
        if off_square > g["angle_deg"]:
            return f"the fingers met wire {touch.wire} {off_square:.0f} degrees off square"
        for n, other in self.tray.wires.items():
            if n == touch.wire:
                continue
            d = self.tray.touch(n, touch.point).distance
            if other.layer > wire.layer and d < (wire.width + other.width) / 2 + 0.5:
                return f"wire {touch.wire} lies under wire {n} there"
            if d < g["room_mm"] + other.width / 2:
                return f"no room for the fingers: wire {n} lies {d:.1f} mm from wire {touch.wire} there"
        # Taken: the fingers centre the wire between them (along the closing direction).
        self.tray.remove(touch.wire)
        shift = float((p - touch.point) @ closing) * closing
        pts = resample(wire.centre, 0.25) + shift
        world = np.vstack([pts[:, 0] + self.tray.origin[0], pts[:, 1] + self.tray.origin[1],
                           np.full(len(pts), self.tray_z + wire.width / 2), np.ones(len(pts))])
        return Held(touch.wire, wire, np.linalg.inv(t) @ world)

    def held_points(self, h: Held | None = None) -> np.ndarray:
        """The held wire's centre line in the world, (N, 3)."""
        h = h or self.held
        assert h is not None, "no wire is held"
        return (self.tool() @ h.shape)[:3].T

    def moved(self) -> None:
        self.jitter = self.rng.normal(0.0, self.scatter, 3) if self.scatter > 0 else np.zeros(3)
        h = self.held
        if h is None or h.carried:
            return
        h.carried = True
        if self.rng.random() < self.g["drop_rate"]:
            e = self._fall("pick", "slipped out of the fingers")
            if e.what == "pick":
                e.slip = True

    def _fall(self, what: str, how: str, meant: bool = False) -> Event:
        """The held wire falls: onto the tray if it is over it, else out of the cell. meant: it
        was let go there on purpose (laid back to be taken afresh), which is no failure. The
        event it makes."""
        h = self.held
        assert h is not None, "no wire is held to fall"
        self.held = None
        pts = self.tray.to_tray(self.held_points(h))
        if self.tray.inside(pts.mean(axis=0)):
            held_at = _held_at(h)
            if held_at is not None:  # held by its middle, it hung from the fingers: it lands anew
                self.tray.drape(h.wire, h.body, pts[held_at], held_at * 0.25)
                return self._event("drop", True, h.wire)
            self.tray.put(h.wire, self.tray.kept_on(pts[::2]), h.body)
            if meant:
                return self._event("putback", True, h.wire)
            return self._event(what, False, h.wire, f"wire {h.wire} {how} and fell back on the tray")
        self.results[h.wire] = "lost"
        return self._event(what, False, h.wire, f"wire {h.wire} {how} and fell off the tray")

    def opened(self) -> None:
        h = self.held
        if h is None:
            return
        t = self.tool()
        p = self.tray.to_tray(t[:3, 3])
        if self.tray.inside(p) and t[2, 3] - self.tray_z < RELEASE_ON_TRAY_BELOW_MM:
            self._fall("release", "was let go over the tray", meant=True)
            return
        self.held = None
        if h.crimped or h.tinned:
            self.results[h.wire] = "crimped" if h.crimped else "tinned"
            self._event("release", True, h.wire)
        else:
            self.results[h.wire] = "rejected"
            why = h.note or ("neither crimped nor tinned" if not h.burnt else "its insulation was burnt")
            self._event("release", False, h.wire, f"wire {h.wire} was let go {why}")

    # The stations ---------------------------------------------------------------------

    def _end(self, near: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The held wire's end nearest a point, and the direction it points (from 2 mm back)."""
        pts = self.held_points()
        if np.linalg.norm(pts[0] - near) > np.linalg.norm(pts[-1] - near):
            pts = pts[::-1]
        d = pts[0] - pts[min(8, len(pts) - 1)]
        return pts[0], d / max(float(np.linalg.norm(d)), 1e-9)

    def crimp(self) -> bool:
        """Cycle the press. It closes only with a wire end in the die, and then crimps it."""
        if self.press is None:
            raise CellError("this cell has no press")
        self.arm.inner.delay(0.5)
        h = self.held
        if h is None:
            self._event("press", False, None, "the press found no wire in the die")
            return False
        end, direction = self._end(self.press.target)
        a = self.press.axis
        cfg = self.press_cfg
        mouth = self.press.target - a * (sum(cfg["depth_mm"]) / 2)
        rel = end - mouth
        depth = float(rel @ a)
        lateral = float(np.linalg.norm(rel - depth * a))
        angle = _angle_deg(direction, a)
        low, high = cfg["depth_mm"]
        why = ""
        if lateral > cfg["tolerance_mm"]:
            why = f"its end was {lateral:.1f} mm off the die's axis"
        elif angle > cfg["angle_deg"]:
            why = f"it met the die {angle:.0f} degrees off its axis"
        elif depth < low:
            why = f"its end was only {depth:.1f} mm into the die"
        elif depth > high:
            why = f"its end was pushed {depth:.1f} mm into a die {high:g} mm deep"
        h.note = why and f"uncrimped: {why}"
        h.crimped = h.crimped or not why
        self._event("press", not why, h.wire, why and f"wire {h.wire} not crimped: {why}")
        return not why

    def waited(self, seconds: float) -> None:
        h = self.held
        if h is None or self.bath is None:
            return
        end, direction = self._end(self.bath.target + np.array([0.0, 0.0, -100.0]))
        cfg = self.bath_cfg
        centre = self.bath.target
        if np.hypot(*(end[:2] - centre[:2])) > cfg["radius_mm"]:
            return
        depth = float(centre[2] - end[2])
        if depth <= 0:
            return
        low, high = cfg["depth_mm"]
        angle = _angle_deg(direction, np.array([0.0, 0.0, -1.0]))
        if depth > high:
            h.burnt = True
            h.note = f"burnt: dipped {depth:.1f} mm, deeper than the {high:g} mm stripped"
        elif depth < low:
            h.note = f"untinned: dipped only {depth:.1f} mm"
        elif angle > cfg["angle_deg"]:
            h.note = f"untinned: dipped {angle:.0f} degrees off vertical"
        else:
            h.dipped += seconds
            h.note = "" if h.dipped >= cfg["seconds"] else f"untinned: only {h.dipped:.2f} s in the solder"
        h.tinned = not h.burnt and h.dipped >= cfg["seconds"]
        if h.tinned or h.burnt:
            self._event("bath", h.tinned, h.wire, "" if h.tinned else f"wire {h.wire} {h.note}")

    def shake(self) -> None:
        """Vibrate the tray so the wires settle anew."""
        self.arm.inner.delay(SHAKE_SECONDS)
        self.tray.shake()
        self._event("shake", True, None)

    # Reporting ------------------------------------------------------------------------

    @property
    def wires_done(self) -> int:
        return sum(1 for r in self.results.values() if r in ("crimped", "tinned"))

    def summary(self) -> dict:
        return {
            "wires_total": self.wires_total,
            "wires_done": self.wires_done,
            "wires_left": len(self.tray),
            "attempts": self.attempts,
            "results": {str(k): v for k, v in sorted(self.results.items())},
            "failures": [e.as_dict() for e in self.events if not e.ok],
            "robot_time_s": round(float(self.arm.inner.clock), 3),
        }


def _held_at(h: Held) -> int | None:
    """Where along its centre line (index of the 0.25 mm samples) the fingers hold the wire,
    if that is MIDDLE_HOLD_MM or more from both its ends (it hangs from there), else None."""
    i = int(np.argmin(np.linalg.norm(h.shape[:3].T, axis=1)))
    n = h.shape.shape[1]
    return i if min(i, n - 1 - i) * 0.25 >= MIDDLE_HOLD_MM else None


def _angle_deg(u: np.ndarray, v: np.ndarray, sign: bool = True) -> float:
    """The angle between unit vectors u and v, degrees (sign=False: between their lines, 0-90)."""
    c = float(u @ v)
    c = c if sign else abs(c)
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


class CellError(RuntimeError):
    """A station or sensor the cell does not have."""


@dataclass
class CellCamera:
    """The cell's camera: every grab renders the tray as it now is."""

    cell: SimCell
    grabs: int = field(default=0)

    def grab(self) -> np.ndarray:
        self.grabs += 1
        return self.cell.grab()


class CellArm(Robot):
    """The cell's arm: a SimRobot whose motions and gripper the cell watches."""

    def __init__(self, inner: SimRobot, cell: SimCell) -> None:
        self.inner = inner
        self.cell = cell
        self.axes = inner.axes

    def __getattr__(self, name):  # clock, log, trajectory, model, save_plot ...
        return getattr(self.inner, name)

    def move(self, t5) -> None:
        self.inner.move(t5)
        self.cell.moved()

    def moves(self, t5) -> None:
        self.inner.moves(t5)
        self.cell.moved()

    def jmove(self, joints) -> None:
        self.inner.jmove(joints)
        self.cell.moved()

    def home(self) -> None:
        self.inner.home()
        self.cell.moved()

    def here(self) -> np.ndarray:
        return self.inner.here()

    def joints(self) -> list[float]:
        return self.inner.joints()

    def open(self) -> None:
        self.inner.open()
        self.cell.opened()

    def close(self) -> None:
        self.inner.close()
        self.cell.closed()

    def speed(self, percent: float) -> None:
        self.inner.speed(percent)

    def delay(self, seconds: float) -> None:
        self.inner.delay(seconds)
        self.cell.waited(seconds)

    def halt(self) -> None:
        self.inner.halt()

    def gripped(self) -> bool:
        """The gripper's sensor: the fingers stopped on a wire."""
        return self.cell.held is not None
