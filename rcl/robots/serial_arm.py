"""SerialRobot: a real arm on a serial port, through a controller Driver (default: the SSC-32).

Moves are planned and checked exactly as in the simulator before anything is
sent; straight lines go out as a series of short coordinated moves. The port
is opened with pyserial (`serial_for_url`), so a device path, a pty or
`loop://` all work.
"""
from __future__ import annotations

import math
import threading
from collections.abc import Sequence

import numpy as np

from .base import Robot, RobotError, checked_speed
from .kinematics import ArmModel, fk, load_model, solve
from .planner import Planner
from .ssc32 import SSC32, Driver

MAX_LINE_SEGMENTS = 25
READ_TIMEOUT = 0.1  # one pyserial read; the driver's answer_timeout bounds a whole answer


class SerialRobot(Robot):
    def __init__(self, url: str, model: ArmModel | str = "al5d", baud: int | None = None,
                 driver: type[Driver] = SSC32, answer_timeout: float = 2.0) -> None:
        import serial

        self.model = load_model(model) if isinstance(model, str) else model
        self.axes = self.model.axes
        baud = baud or int(self.model.ssc32.get("baud", 115200))
        try:
            self.port = serial.serial_for_url(url, baudrate=baud, timeout=READ_TIMEOUT, write_timeout=2.0)
        except (serial.SerialException, ValueError, OSError) as e:
            raise RobotError(f"cannot open the serial port {url}: {e}") from None
        self.driver = driver(self.port, self.model, answer_timeout)
        try:
            self.driver.connect()
            measured = self.driver.read_joints()
        except RobotError:
            self.port.close()
            raise
        self.q = [m if m is not None and j.min <= m <= j.max else h
                  for m, h, j in zip(measured, self.model.home, self.model.joints)]
        self.planner = Planner(self.model)
        self.speed_percent = 100.0
        self.halted = False
        self._stop = threading.Event()

    def _go(self, path: list[list[float]], seconds: float) -> None:
        if self.halted:
            self.halted = False
            self._stop.clear()
        self.driver.move_joints(path[-1], seconds)
        self.driver.wait(seconds)
        self.q = list(path[-1])

    def move(self, t5: np.ndarray) -> None:
        target = solve(self.model, np.asarray(t5, float), self.q)
        path = self.planner.joint_path(self.q, target)
        self._go(path, self.planner.joint_seconds(path, self.speed_percent))

    def moves(self, t5: np.ndarray) -> None:
        path = self.planner.line_path(self.q, np.asarray(t5, float))
        seconds = self.planner.line_seconds(path, self.speed_percent)
        step = max(1, math.ceil((len(path) - 1) / MAX_LINE_SEGMENTS))
        waypoints = path[step::step]
        if waypoints[-1] is not path[-1]:
            waypoints.append(path[-1])
        for q in waypoints:
            self._go([self.q, q], seconds / len(waypoints))

    def jmove(self, joints: Sequence[float]) -> None:
        if len(joints) != self.axes:
            raise RobotError(f"the {self.model.name} arm has {self.axes} joints, not {len(joints)}")
        path = self.planner.joint_path(self.q, [float(x) for x in joints])
        self._go(path, self.planner.joint_seconds(path, self.speed_percent))

    def home(self) -> None:
        path = self.planner.joint_path(self.q, self.model.home)
        self._go(path, self.planner.joint_seconds(path, self.speed_percent))

    def here(self) -> np.ndarray:
        return fk(self.model, self.q)

    def joints(self) -> list[float]:
        return list(self.q)

    def open(self) -> None:
        self.driver.gripper(False, self.model.gripper_seconds)
        self.driver.wait(self.model.gripper_seconds)

    def close(self) -> None:
        self.driver.gripper(True, self.model.gripper_seconds)
        self.driver.wait(self.model.gripper_seconds)

    def speed(self, percent: float) -> None:
        self.speed_percent = checked_speed(percent)

    def delay(self, seconds: float) -> None:
        if self._stop.wait(seconds):
            raise RobotError("the arm was halted")

    def halt(self) -> None:
        self.halted = True
        self._stop.set()
        try:
            self.driver.halt()
        except RobotError:
            pass  # the controller may be the thing that failed; the attempt is what we can do

    def close_port(self) -> None:
        self.port.close()
