"""The work cell: its description (a TOML file) and the simulated cell the built-in
description stands for: the tray of wires, the camera over it, the arm, gripper,
press and bath that the RCL built-ins drive as they would real hardware.
Nothing here knows RCL."""
from __future__ import annotations

from .config import CellConfig, CellConfigError, load_config
from .optics import TrayView
from .world import CellError, SimCell

__all__ = ["CellConfig", "CellConfigError", "CellError", "SimCell", "TrayView", "load_config"]
