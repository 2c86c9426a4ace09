"""The simulated work cell (issue 7, in progress): the tray of wires, the camera over it,
the arm, gripper, press and bath that the RCL built-ins drive as they would real hardware.
Nothing here knows RCL."""
from __future__ import annotations

from .optics import TrayView

__all__ = ["TrayView"]
