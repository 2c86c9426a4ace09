"""The interface every robot backend implements."""
from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Sequence

import numpy as np


class RobotError(Exception):
    """A motion the arm cannot or must not make, or a fault of the arm itself."""


def checked_speed(percent: float) -> float:
    """A speed as every backend and SPEED take it, in percent of the maximum: 1 to 100."""
    if not 1.0 <= percent <= 100.0:
        raise RobotError(f"SPEED takes 1 to 100 percent, not {percent:g}")
    return float(percent)


class Robot(ABC):
    """A manipulator with a gripper.

    Every motion is checked whole before it starts; a RobotError leaves the
    arm where it was. halt() must be safe to call at any time, repeatedly.
    """

    axes: int

    @abstractmethod
    def move(self, t5: np.ndarray) -> None:
        """Joint-interpolated motion to the pose t5."""

    @abstractmethod
    def moves(self, t5: np.ndarray) -> None:
        """Straight-line motion to the pose t5."""

    @abstractmethod
    def jmove(self, joints: Sequence[float]) -> None:
        """Motion to joint angles (degrees), one per axis."""

    @abstractmethod
    def here(self) -> np.ndarray:
        """The current pose of T5."""

    @abstractmethod
    def joints(self) -> list[float]:
        """The current joint angles (degrees)."""

    @abstractmethod
    def home(self) -> None:
        """Motion to the home position."""

    @abstractmethod
    def open(self) -> None:
        """Open the gripper."""

    @abstractmethod
    def close(self) -> None:
        """Close the gripper."""

    @abstractmethod
    def speed(self, percent: float) -> None:
        """Set the speed of later motions, 1 to 100 percent of the maximum."""

    @abstractmethod
    def delay(self, seconds: float) -> None:
        """Wait (in the robot's time: simulated or real)."""

    @abstractmethod
    def halt(self) -> None:
        """Stop all motion now."""
