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
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .base import Robot, RobotError, checked_speed
from .kinematics import ArmModel, fk, load_model, solve
from .planner import Planner


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
        self.planner = Planner(self.model)
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
        path = self.planner.joint_path(self.q, target)
        self._run("move", path, self.planner.joint_seconds(path, self.speed_percent))
        self.log.append(("move", np.array(t5, float)))

    def moves(self, t5: np.ndarray) -> None:
        path = self.planner.line_path(self.q, np.asarray(t5, float))
        self._run("moves", path, self.planner.line_seconds(path, self.speed_percent))
        self.log.append(("moves", np.array(t5, float)))

    def jmove(self, joints: Sequence[float]) -> None:
        target = _joint_vector(self.model, joints)
        path = self.planner.joint_path(self.q, target)
        self._run("jmove", path, self.planner.joint_seconds(path, self.speed_percent))
        self.log.append(("jmove", tuple(target)))

    def home(self) -> None:
        path = self.planner.joint_path(self.q, self.model.home)
        self._run("home", path, self.planner.joint_seconds(path, self.speed_percent))
        self.log.append(("home",))

    def _run(self, kind: str, path: list[list[float]], seconds: float) -> None:
        if self.halted:  # a new program after a halt: the arm may move again
            self.halted = False
            self._stop.clear()
        start = self.clock
        if self.realtime:
            began = time.monotonic()
            if self._stop.wait(seconds):
                self._stop.clear()
                done = min(1.0, (time.monotonic() - began) / seconds) if seconds > 0 else 1.0
                self.q = list(path[min(len(path) - 1, int(done * (len(path) - 1)))])  # where it stopped
                self.clock += done * seconds
                self.trajectory.append(Motion(kind + " (halted)", start, self.clock, path))
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
        self.speed_percent = checked_speed(percent)
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
        """A PNG of the T5 path: top view (x, y) and side view (x, z), base coordinates, each
        motion numbered and coloured by kind."""
        from .plot import plot_path

        motions = [(m.kind, np.array([fk(self.model, q)[:3, 3] for q in m.path])) for m in self.trajectory]
        plot_path(motions, path, f"{self.model.name}: {len(self.trajectory)} motions, {self.clock:.1f} s "
                                 "(T5, the flange, in base coordinates)")


def _joint_vector(model: ArmModel, joints: Sequence[float]) -> list[float]:
    if len(joints) != model.axes:
        raise RobotError(f"the {model.name} arm has {model.axes} joints, not {len(joints)}")
    target = [float(x) for x in joints]
    if not all(math.isfinite(x) for x in target):
        raise RobotError("joint angles must be finite numbers")
    return target
