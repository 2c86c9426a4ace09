"""A work cell for a session: its parts made from a cell description, and its RCL module.

    cell = open_cell()                      # the built-in simulated cell
    cell = open_cell("mycell.toml", seed=3)
    s = Session(cell=cell)                  # robot, camera, camera model and IMPORT 'cell'

The module a program gets with ``IMPORT 'cell'`` is RCL made from the
description: the frames Z^ (world -> base) and E^ (t5 -> tool), one frame per
station (PRESS^, BATH^, ...: world -> wire), and the constants TRAY_X, TRAY_Y
(the tray's centre), TRAY_Z (its surface), TRAY_SIZE and WARP_FILE ('' when
the description names no warp file).
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .cell import CellConfig, SimCell, load_config


@dataclass
class Cell:
    config: CellConfig
    robot: Any  # rcl.robots.Robot
    camera: Any  # grab() -> image, or None
    sim: SimCell | None  # the simulation behind robot and camera, when they are simulated

    @property
    def tray_z(self) -> float:
        return float(self.config["tray"]["z"])

    def module_source(self) -> str:
        return cell_module(self.config)


class CellSetupError(Exception):
    """A part of the cell that cannot be had (a serial port, an image folder); the message says which."""


def open_cell(path: str | Path | CellConfig | None = None, seed: int = 0,
              wires: Sequence[int] | None = None, realtime: bool = False) -> Cell:
    """The cell a description (a file, a loaded CellConfig, or None: the built-in) stands for.
    seed and wires (low, high) make the simulated tray; CellConfigError or CellSetupError say
    what is wrong."""
    config = path if isinstance(path, CellConfig) else load_config(path)
    from .robots import RobotError

    if config.simulated:
        try:
            sim = SimCell(config, seed=seed, wires=wires)
        except RobotError as e:
            raise CellSetupError(f"{config.source}: robot: {e}") from None
        _check_reach(config, sim.arm.inner.model)
        sim.arm.inner.realtime = realtime
        return Cell(config, sim.arm, sim.camera, sim)
    from .camera import ImageError, ImageFiles
    from .robots import SimRobot

    robot_cfg = config["robot"]
    folder = config.path(config["camera"]["folder"])
    assert folder is not None  # load_config refuses a files camera without its folder
    robot: Any
    try:
        camera = ImageFiles(folder)
    except ImageError as e:
        raise CellSetupError(f"{config.source}: camera: {e}") from None
    try:
        if robot_cfg["kind"] == "sim":  # recorded images with a simulated arm: no tray to act on
            robot = SimRobot(config.model(), realtime=realtime)
        else:
            from .robots.serial_arm import SerialRobot

            robot = SerialRobot(robot_cfg["port"], config.model(), int(robot_cfg["baud"]) or None)
    except RobotError as e:
        raise CellSetupError(f"{config.source}: robot: {e}") from None
    return Cell(config, robot, camera, None)


TRAY_MARGIN_MM, ABOVE_MM = 4.0, 30.0  # stdlib/wires.rcl: CALIBRATE's grid margin, CLEARANCE
STATION_CLEARANCE_MM = 25.0  # stdlib/wires.rcl: STATION_CLEARANCE, where TOSTATION waits before going in


def _check_reach(config: CellConfig, model) -> None:
    """Before anything moves: the arm must reach the tray's corners as the tasks go there (the
    calibration grid's, at the tray and CLEARANCE above it, the fingers pointing down), else
    CellSetupError names the corner and why."""
    from .frame import Frame
    from .robots import RobotError
    from .robots.kinematics import solve

    tray = config["tray"]
    half = float(tray["size_mm"]) / 2 - TRAY_MARGIN_MM
    cx, cy = (float(c) for c in tray["centre"])
    z0 = float(tray["z"])
    base_inv, tool_inv = config.frame("Z").inv(), config.frame("E").inv()
    q = list(model.home)
    for dx in (-half, half):
        for dy in (-half, half):
            for z in (z0, z0 + ABOVE_MM):
                fingers = Frame.trans(cx + dx, cy + dy, z) * Frame.rotx(180)
                try:
                    solve(model, np.asarray((base_inv * fingers * tool_inv).matrix), q)
                except RobotError as e:
                    raise CellSetupError(
                        f"{config.source}: the {model.name} arm cannot reach the tray's corner "
                        f"({cx + dx:g}, {cy + dy:g}, {z:g}) mm: {e}. This cell is laid out for another arm: "
                        f"give a cell file laid out for {model.name} (--cell), or leave --model out") from None
    for name in config.stations():
        _check_station(config, model, name, q)


def _check_station(config: CellConfig, model, name: str, q: list) -> None:
    """The arm must bring a wire's end to the station as stdlib TOSTATION does (STATION_CLEARANCE
    back along the wire, then in), holding a straight wire as FINDWIRE's grasp holds it either
    way it may lie on the tray (the grasp's tangent is known only to within a half turn, so
    the fingers take the wire one way or the other); else CellSetupError names the station."""
    from .builtins.vision import wire_frames
    from .frame import Frame
    from .robots import RobotError
    from .robots.kinematics import solve
    from .vision import Sighting
    from .vision.common import GRASP_MM

    class Flat:  # a camera model seeing the tray 1 px a mm
        @staticmethod
        def warp(u, v):
            return (u, v, 0.0)

    base_inv, tool_inv = config.frame("Z").inv(), config.frame("E").inv()
    station = config.frame(name)
    for way, tangent in (("one way", 0.0), ("the other way", 180.0)):
        _, grasp = wire_frames(Flat, Sighting((0.0, 0.0), 0.0, (GRASP_MM, 0.0), tangent))
        for back in (STATION_CLEARANCE_MM, 0.0):
            pose = _radial(base_inv * station * Frame.trans(0, 0, back) * grasp) * tool_inv
            try:
                solve(model, np.asarray(pose.matrix), q)
            except RobotError as e:
                x, y, z = config["frames"][name]["xyz"]
                raise CellSetupError(
                    f"{config.source}: the {model.name} arm cannot bring a wire's end to the station {name} "
                    f"at ({x:g}, {y:g}, {z:g}) mm held {way} round (as the fingers may take it off the tray): "
                    f"{e}. Give a cell file with {name} where the {model.name} arm reaches it (--cell)") from None


def _radial(g):
    """stdlib/frames.rcl RADIAL^: the tool pose g (base coordinates) turned about the vertical
    through its origin until its approach points at or away from the base's Z axis."""
    from .frame import Frame

    m = np.asarray(g.matrix)
    ax, ay = m[0, 2], m[1, 2]
    px, py, pz = m[:3, 3]
    if math.hypot(ax, ay) < 1e-9:
        return g
    turn = math.degrees(math.atan2(py, px) - math.atan2(ay, ax))
    while turn > 90.0:
        turn -= 180.0
    while turn < -90.0:
        turn += 180.0
    return Frame.trans(px, py, pz) * Frame.rotz(turn) * Frame.trans(-px, -py, -pz) * g


def cell_module(config: CellConfig) -> str:
    """The RCL text of IMPORT 'cell' for a description."""
    tray = config["tray"]
    warp = config.warp
    lines = [f"{{ cell: the frames of {_comment(config.name)} ({_comment(config.source)}) }}",
             "VAR Z^ : FRAME world -> base",
             "VAR E^ : FRAME t5 -> tool"]
    lines += [f"VAR {name}^ : FRAME world -> wire" for name in config.stations()]
    lines += [f"CONST TRAY_X = {_real(tray['centre'][0])}",
              f"CONST TRAY_Y = {_real(tray['centre'][1])}",
              f"CONST TRAY_Z = {_real(tray['z'])}",
              f"CONST TRAY_SIZE = {_real(tray['size_mm'])}",
              f"CONST WARP_FILE = {_string(str(warp) if warp else '')}"]
    for name in ("Z", "E", *config.stations()):
        f = config["frames"][name]
        x, y, z = (_real(v) for v in f["xyz"])
        r, p, w = (_real(v) for v in f["rpy"])
        lines.append(f"{name}^ := TRANS({x}, {y}, {z}) * RPY({r}, {p}, {w})")
    return "\n".join(lines) + "\n"


def _real(v: float) -> str:
    return repr(float(v))


def _string(text: str) -> str:
    return "'" + text.replace("'", "''") + "'"


def _comment(text: str) -> str:
    return text.replace("}", ")").replace("{", "(")
