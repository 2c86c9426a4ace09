"""The Lynxmotion SSC-32 servo controller (the AL5D's), spoken over a serial port.

Protocol (SSC-32 manual): a move group is `#<ch>P<pw>[S<spd>]... T<ms>` ended
by a carriage return; `Q` answers `+` while a move is in progress and `.`
when it is done; `QP<ch>` answers one byte, the pulse width / 10; `VER`
answers the firmware version; ESC cancels a command being sent and
`STOP <ch>` stops a servo where it is. Pulse widths are microseconds, with
joint zero at 1500 us and the model's us_per_degree and direction.

Every read has a timeout: a controller that stops answering, or answers
garbage, raises RobotError within seconds.
"""
from __future__ import annotations

import time
from abc import ABC, abstractmethod
from collections.abc import Sequence

from .base import RobotError
from .kinematics import ArmModel

CENTRE_US = 1500
MIN_US, MAX_US = 500, 2500
POLL_SECONDS = 0.02


class Driver(ABC):
    """What SerialRobot needs from a controller protocol."""

    @abstractmethod
    def __init__(self, port, model: ArmModel, answer_timeout: float) -> None:
        """Speak the protocol on an open port for an arm of the model, waiting answer_timeout s at most."""

    @abstractmethod
    def connect(self) -> None:
        """Check that the controller answers (RobotError if not)."""

    @abstractmethod
    def move_joints(self, q: Sequence[float], seconds: float) -> None:
        """Start a coordinated move of every joint to q (degrees) taking seconds."""

    @abstractmethod
    def gripper(self, closed: bool, seconds: float) -> None:
        """Start opening or closing the gripper."""

    @abstractmethod
    def wait(self, seconds: float) -> None:
        """Return when the last move is done (RobotError if the controller says nothing sensible)."""

    @abstractmethod
    def read_joints(self) -> list[float | None]:
        """The joint angles the controller is driving (None where a servo is off)."""

    @abstractmethod
    def halt(self) -> None:
        """Stop every servo now."""


class SSC32(Driver):
    """The SSC-32 protocol over a pyserial port (or anything with read/write/reset_input_buffer)."""

    def __init__(self, port, model: ArmModel, answer_timeout: float = 2.0) -> None:
        cfg = model.ssc32
        if not cfg:
            raise RobotError(f"the {model.name} model has no [ssc32] section (channels, pulse widths)")
        self.port = port
        self.model = model
        self.channels = [int(c) for c in cfg["channels"]]
        self.us_per_degree = [float(x) for x in cfg["us_per_degree"]]
        self.direction = [int(x) for x in cfg.get("direction", [1] * len(self.channels))]
        self.gripper_channel = int(cfg.get("gripper_channel", -1))
        self.gripper_us = (int(cfg.get("gripper_open_us", CENTRE_US)), int(cfg.get("gripper_closed_us", CENTRE_US)))
        self.answer_timeout = answer_timeout
        if not len(self.channels) == len(self.us_per_degree) == len(self.direction) == model.axes:
            raise RobotError(f"the [ssc32] section of {model.name} must give one channel, us_per_degree and "
                             f"direction per joint ({model.axes})")

    # Conversions

    def pulse(self, joint: int, degrees: float) -> int:
        us = round(CENTRE_US + self.direction[joint] * self.us_per_degree[joint] * degrees)
        if not MIN_US <= us <= MAX_US:
            raise RobotError(f"joint {self.model.joints[joint].name} at {degrees:.1f} degrees needs a pulse of "
                             f"{us} us, outside the SSC-32's {MIN_US}..{MAX_US}")
        means = self.angle(joint, us)
        if abs(means - degrees) > 1.0:  # what is sent must say what was asked
            raise RobotError(f"joint {self.model.joints[joint].name}: the pulse {us} us means "
                             f"{means:.1f} degrees, not the {degrees:.1f} asked for")
        return us

    def angle(self, joint: int, us: int) -> float:
        return (us - CENTRE_US) / (self.direction[joint] * self.us_per_degree[joint])

    # The protocol

    def _send(self, text: str) -> None:
        try:
            self.port.write(text.encode("ascii"))
            self.port.flush()
        except Exception as e:  # pyserial raises SerialException, OSError, or its timeout
            raise RobotError(f"cannot write to the SSC-32: {e}") from None

    def _read(self, n: int, what: str) -> bytes:
        deadline = time.monotonic() + self.answer_timeout
        data = b""
        while len(data) < n and time.monotonic() < deadline:
            try:
                data += self.port.read(n - len(data))
            except Exception as e:
                raise RobotError(f"cannot read from the SSC-32: {e}") from None
        if len(data) < n:
            raise RobotError(f"the SSC-32 did not answer {what} within {self.answer_timeout:g} s")
        return data

    def connect(self) -> None:
        try:
            self.port.reset_input_buffer()
        except Exception:
            pass
        self._send("VER\r")
        line = b""
        while not line.endswith(b"\r"):
            line += self._read(1, "VER (is it an SSC-32, at the right baud rate?)")
            if len(line) > 64:
                break
        if b"SSC32" not in line.replace(b"-", b"").upper():
            raise RobotError(f"the device answered {line[:40]!r} to VER: not an SSC-32")

    def move_joints(self, q: Sequence[float], seconds: float) -> None:
        pulses = [self.pulse(i, x) for i, x in enumerate(q)]
        groups = "".join(f"#{ch}P{us}" for ch, us in zip(self.channels, pulses))
        self._send(f"{groups}T{max(1, round(seconds * 1000))}\r")

    def gripper(self, closed: bool, seconds: float) -> None:
        if self.gripper_channel < 0:
            return
        self._send(f"#{self.gripper_channel}P{self.gripper_us[1 if closed else 0]}T{max(1, round(seconds * 1000))}\r")

    def wait(self, seconds: float) -> None:
        deadline = time.monotonic() + seconds + 5.0
        while True:
            self._send("Q\r")
            answer = self._read(1, "Q")
            if answer == b".":
                return
            if answer != b"+":
                raise RobotError(f"the SSC-32 answered {answer!r} to Q (expected '+' or '.'): garbage on the line")
            if time.monotonic() > deadline:
                raise RobotError(f"the SSC-32 still reports motion {seconds + 5:.1f} s after a {seconds:.1f} s move")
            time.sleep(POLL_SECONDS)

    def read_joints(self) -> list[float | None]:
        out: list[float | None] = []
        for i, ch in enumerate(self.channels):
            self._send(f"QP{ch}\r")
            value = self._read(1, f"QP{ch}")[0] * 10
            out.append(None if value == 0 else self.angle(i, value))
        return out

    def halt(self) -> None:
        stops = "".join(f"STOP {ch}\r" for ch in self.channels)
        self._send("\x1b" + stops)
