"""RecordingArm: a minimal simulated arm that records what it is told to do.

It has no kinematics: every pose is taken as reachable and joint motions do
not change the Cartesian pose it reports. It is the default backend until a
kinematic simulator is configured, and the test double for motion built-ins.
"""
from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .base import Robot, RobotError, checked_speed

HOME_POSE = np.array([[1.0, 0.0, 0.0, 300.0],
                      [0.0, -1.0, 0.0, 0.0],
                      [0.0, 0.0, -1.0, 300.0],
                      [0.0, 0.0, 0.0, 1.0]])


class RecordingArm(Robot):
    """Records ('move', pose), ('moves', pose), ('jmove', joints), ('open',), ... in self.log."""

    def __init__(self, axes: int = 5) -> None:
        self.axes = axes
        self.log: list[tuple] = []
        self._pose = HOME_POSE.copy()
        self._joints = [0.0] * axes
        self.gripper_open = True
        self.speed_percent = 100.0
        self.clock = 0.0  # simulated seconds
        self.halted = False

    def move(self, t5: np.ndarray) -> None:
        self._pose = np.array(t5, dtype=float)
        self.log.append(("move", self._pose.copy()))

    def moves(self, t5: np.ndarray) -> None:
        self._pose = np.array(t5, dtype=float)
        self.log.append(("moves", self._pose.copy()))

    def jmove(self, joints: Sequence[float]) -> None:
        if len(joints) != self.axes:
            raise RobotError(f"this arm has {self.axes} joints, not {len(joints)}")
        self._joints = [float(q) for q in joints]
        self.log.append(("jmove", tuple(self._joints)))

    def here(self) -> np.ndarray:
        return self._pose.copy()

    def joints(self) -> list[float]:
        return list(self._joints)

    def home(self) -> None:
        self._pose = HOME_POSE.copy()
        self._joints = [0.0] * self.axes
        self.log.append(("home",))

    def open(self) -> None:
        self.gripper_open = True
        self.log.append(("open",))

    def close(self) -> None:
        self.gripper_open = False
        self.log.append(("close",))

    def speed(self, percent: float) -> None:
        self.speed_percent = checked_speed(percent)
        self.log.append(("speed", self.speed_percent))

    def delay(self, seconds: float) -> None:
        self.clock += seconds
        self.log.append(("delay", float(seconds)))

    def halt(self) -> None:
        self.halted = True
        self.log.append(("halt",))
