"""SimRobot: a kinematic simulator of an arm model, in simulated time.

Every motion is planned whole and checked before it starts: the inverse
kinematics at every point, the joint limits, and the table plane (no link
frame below it anywhere along the path). A failure raises RobotError and the
arm stays where it was. Time is simulated from the joint speeds (a joint move
takes as long as its slowest joint needs; a straight line at least its length
over the linear speed) unless realtime=True, when motions also take that long
on the clock and halt() cuts them short.
"""
from __future__ import annotations

import math
import threading
from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np

from .base import Robot, RobotError
from .kinematics import ArmModel, frames, fk, load_model, solve

JOINT_STEP_DEG = 2.0  # path sampling for the checks
LINE_STEP_MM = 2.0
LINE_STEP_DEG = 2.0
MAX_JUMP_DEG = 15.0  # a bigger joint change between neighbouring samples of a straight line is a flip


@dataclass
class Motion:
    """One entry of the trajectory log."""

    kind: str  # move, moves, jmove, home
    start: float  # simulated seconds
    end: float
    path: list[list[float]]  # joint samples, first and last included


class SimRobot(Robot):
    """A simulated arm of a given model (default: smartarms), starting at home."""

    def __init__(self, model: ArmModel | str = "smartarms", realtime: bool = False) -> None:
        self.model = load_model(model) if isinstance(model, str) else model
        self.axes = self.model.axes
        self.q = list(self.model.home)
        self.speed_percent = 100.0
        self.clock = 0.0
        self.gripper_open = True
        self.halted = False
        self.realtime = realtime
        self.trajectory: list[Motion] = []
        self.log: list[tuple] = []  # the commands, as RecordingArm logs them
        self._stop = threading.Event()

    # Motions -------------------------------------------------------------------

    def move(self, t5: np.ndarray) -> None:
        target = solve(self.model, np.asarray(t5, float), self.q)
        self._joint_motion("move", target)
        self.log.append(("move", np.array(t5, float)))

    def jmove(self, joints: Sequence[float]) -> None:
        if len(joints) != self.axes:
            raise RobotError(f"the {self.model.name} arm has {self.axes} joints, not {len(joints)}")
        target = [float(x) for x in joints]
        if not all(math.isfinite(x) for x in target):
            raise RobotError("joint angles must be finite numbers")
        self.model.check_limits(target)
        self._joint_motion("jmove", target)
        self.log.append(("jmove", tuple(target)))

    def home(self) -> None:
        self._joint_motion("home", list(self.model.home))
        self.log.append(("home",))

    def moves(self, t5: np.ndarray) -> None:
        path = self._line_path(np.asarray(t5, float))
        self._check_table(path)
        length = float(np.linalg.norm(fk(self.model, path[-1])[:3, 3] - fk(self.model, path[0])[:3, 3]))
        seconds = max(length / self.model.linear_speed, self._joint_seconds(path))
        self._run("moves", path, seconds / (self.speed_percent / 100.0))
        self.log.append(("moves", np.array(t5, float)))

    def _joint_motion(self, kind: str, target: list[float]) -> None:
        start = list(self.q)
        span = max(abs(a - b) for a, b in zip(start, target))
        n = max(1, math.ceil(span / JOINT_STEP_DEG))
        path = [[a + (b - a) * k / n for a, b in zip(start, target)] for k in range(n + 1)]
        self._check_table(path)
        self._run(kind, path, self._joint_seconds([start, target]) / (self.speed_percent / 100.0))

    def _joint_seconds(self, path: list[list[float]]) -> float:
        return max(sum(abs(b[i] - a[i]) for a, b in zip(path, path[1:])) / j.speed
                   for i, j in enumerate(self.model.joints))

    def _line_path(self, t5: np.ndarray) -> list[list[float]]:
        from scipy.spatial.transform import Rotation, Slerp

        here = fk(self.model, self.q)
        p0, p1 = here[:3, 3], t5[:3, 3]
        rots = Rotation.from_matrix(np.stack([here[:3, :3], t5[:3, :3]]))
        turn = math.degrees(float((rots[0].inv() * rots[1]).magnitude()))
        n = max(1, math.ceil(max(np.linalg.norm(p1 - p0) / LINE_STEP_MM, turn / LINE_STEP_DEG)))
        slerp = Slerp([0.0, 1.0], rots)
        path = [list(self.q)]
        for k in range(1, n + 1):
            s = k / n
            t = np.eye(4)
            t[:3, :3] = slerp([s]).as_matrix()[0] if k < n else t5[:3, :3]
            t[:3, 3] = p0 + (p1 - p0) * s
            try:
                q = solve(self.model, t, path[-1])
            except RobotError as e:
                raise RobotError(f"the straight line leaves the arm's reach {100 * s:.0f}% of the way "
                                 f"(at {_point(t)}): {e}") from None
            jump = max(abs(a - b) for a, b in zip(q, path[-1]))
            if jump > MAX_JUMP_DEG:
                raise RobotError(f"the straight line passes a singularity or a change of arm configuration "
                                 f"{100 * s:.0f}% of the way (at {_point(t)}): a joint would jump {jump:.0f} "
                                 f"degrees; use MOVE, or a line that avoids it")
            path.append(q)
        return path

    def _check_table(self, path: list[list[float]]) -> None:
        limit = self.model.table_z
        for q in path:
            for j, f in zip(self.model.joints, frames(self.model, q)):
                if f[2, 3] < limit - 1e-9:
                    raise RobotError(f"the move would take the {j.name} link to z = {f[2, 3]:.1f} mm, below the "
                                     f"table plane z = {limit:g} mm")

    def _run(self, kind: str, path: list[list[float]], seconds: float) -> None:
        if self.halted:  # a new program after a halt: the arm may move again
            self.halted = False
            self._stop.clear()
        start = self.clock
        if self.realtime and self._stop.wait(seconds):
            self._stop.clear()
            raise RobotError("the arm was halted")
        self.clock += seconds
        self.q = list(path[-1])
        self.trajectory.append(Motion(kind, start, self.clock, path))

    # State and the rest of the interface -----------------------------------------

    def here(self) -> np.ndarray:
        return fk(self.model, self.q)

    def joints(self) -> list[float]:
        return list(self.q)

    def open(self) -> None:
        self.clock += self.model.gripper_seconds
        self.gripper_open = True
        self.log.append(("open",))

    def close(self) -> None:
        self.clock += self.model.gripper_seconds
        self.gripper_open = False
        self.log.append(("close",))

    def speed(self, percent: float) -> None:
        if not 1.0 <= percent <= 100.0:
            raise RobotError(f"speed must be 1 to 100 percent, not {percent:g}")
        self.speed_percent = float(percent)
        self.log.append(("speed", self.speed_percent))

    def delay(self, seconds: float) -> None:
        if self.realtime and self._stop.wait(seconds):
            self._stop.clear()
            raise RobotError("the arm was halted")
        self.clock += seconds
        self.log.append(("delay", float(seconds)))

    def halt(self) -> None:
        self.halted = True
        self._stop.set()
        self.log.append(("halt",))

    def save_plot(self, path: str) -> None:
        """A PNG of the T5 path: top view (x, y) and side view (x, z), base coordinates."""
        from .plot import plot_path

        points = [fk(self.model, q)[:3, 3] for m in self.trajectory for q in m.path]
        plot_path(points, path, f"{self.model.name}: {len(self.trajectory)} motions, {self.clock:.1f} s")


def _point(t: np.ndarray) -> str:
    return "(" + ", ".join(f"{c:.1f}" for c in t[:3, 3]) + ")"
