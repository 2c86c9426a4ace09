"""The cell description: a TOML file naming the camera, the robot, the frames and the warp.

The built-in description (sim.toml beside this module) is the simulated cell;
a user's file is read over it, so it need only give what differs. Every value
is checked against the built-in one's type, and unknown names are refused, so
a misspelt key is an error rather than a silent default.
"""
from __future__ import annotations

import copy
import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..frame import Frame
from ..keywords import is_name
from ..vision import MAX_PX_PER_MM, MIN_PX_PER_MM
from ..vision.scenes import SLICES

DEFAULT = Path(__file__).with_name("sim.toml")
FRAME_NAMES_REQUIRED = ("Z", "E")
LOOKS = ("random",) + SLICES


class CellConfigError(ValueError):
    """A cell file that cannot be used; the message names the file and the key."""


BUILT_IN = "the built-in cell"
# the numbers a cell file may hold: what a work cell could have, and what the simulator can draw
RANGES = {
    "robot.baud": (300, 4_000_000), "robot.inaccuracy_mm": (0, 50), "robot.repeatability_mm": (0, 10),
    "robot.seed": (0, 2**32 - 1), "camera.height_mm": (50, 10_000), "camera.fov_mm": (10, 5_000),
    "camera.k1": (-10, 10), "camera.k2": (-10, 10), "camera.noise": (0, 1), "tray.size_mm": (10, 2_000),
    "tray.layers": (1, 10), "tray.z": (-2_000, 2_000), "gripper.tolerance_mm": (0, 100),
    "gripper.angle_deg": (0, 90), "gripper.room_mm": (0, 100), "gripper.height_mm": (0, 100),
    "press.tolerance_mm": (0, 100), "press.angle_deg": (0, 90), "bath.radius_mm": (1, 1_000),
    "bath.angle_deg": (0, 90), "bath.seconds": (0, 3_600),
    "camera.width": (64, 2_048),  # a sim look costs about 130 bytes a pixel: ~550 MB at 2048 (2 GB at 4096)
}


@dataclass
class CellConfig:
    """A checked cell description. data: the merged TOML tables; folder: where relative paths start."""

    data: dict
    source: str
    folder: Path

    def __getitem__(self, section: str) -> dict:
        return self.data[section]

    @property
    def name(self) -> str:
        return self.data["name"]

    @property
    def from_file(self) -> bool:
        """Whether a user's cell file was read (its folder holds the files it names)."""
        return not self.source.startswith(BUILT_IN)

    @property
    def warp(self) -> Path | None:
        return self.path(self.data["warp"])

    def path(self, text: str) -> Path | None:
        """A path named in the file, relative to the file's folder; None for ""."""
        if not text:
            return None
        p = Path(text).expanduser()
        return p if p.is_absolute() else self.folder / p

    def frame(self, name: str) -> Frame:
        f = self.data["frames"][name]
        x, y, z = f["xyz"]
        roll, pitch, yaw = f["rpy"]
        return Frame.trans(x, y, z) * Frame.rotz(yaw) * Frame.roty(pitch) * Frame.rotx(roll)

    def stations(self) -> list[str]:
        """The frames other than Z and E, in file order."""
        return [n for n in self.data["frames"] if n not in FRAME_NAMES_REQUIRED]

    def model(self) -> str:
        """The arm model: a built-in name, or a model file's path."""
        name = self.data["robot"]["model"]
        return str(self.path(name)) if name.lower().endswith(".toml") else name

    @property
    def simulated(self) -> bool:
        return self.data["robot"]["kind"] == "sim" and self.data["camera"]["kind"] == "sim"

    def px_per_mm(self) -> float:
        cam = self.data["camera"]
        return float(cam["px_per_mm"]) or float(cam["width"]) / float(cam["fov_mm"])


def load_config(path: str | Path | None = None, arm: str | None = None) -> CellConfig:
    """The built-in cell, or a user's file read over it; CellConfigError says what is wrong.
    Without a file, arm names the arm model the built-in cell should hold: the cell is then
    laid out for that arm where a layout ships for it (sim-ARM.toml beside sim.toml, read over
    it), else it is the built-in cell with that arm in it, which may not reach."""
    base = _read(DEFAULT)
    if path is None:
        data, source, folder = base, BUILT_IN, Path.cwd()
        key = arm.lower() if arm is not None and is_name(arm) else ""
        layout = DEFAULT.with_name(f"sim-{key}.toml")
        if key and layout.is_file():
            data = copy.deepcopy(base)
            _merge(data, _read(layout), base, str(layout), "")
            source = f"{BUILT_IN} laid out for {key}"
        elif arm:
            data["robot"]["model"] = arm
    else:
        p = Path(path)
        source = str(p)
        user = _read(p)
        data = copy.deepcopy(base)
        _merge(data, user, base, source, "")
        folder = p.resolve().parent
    _check(data, source)
    return CellConfig(data, source, folder)


def _read(path: Path) -> dict:
    try:
        with open(path, "rb") as f:
            return tomllib.load(f)
    except FileNotFoundError:
        raise CellConfigError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise CellConfigError(f"{path} is a folder, not a cell file") from None
    except OSError as e:
        raise CellConfigError(f"cannot read {path}: {e.strerror or e}") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as e:
        raise CellConfigError(f"{path}: not a valid TOML file: {e}") from None
    except RecursionError:
        raise CellConfigError(f"{path}: arrays or tables nested too deep for a cell file") from None


def _merge(into: dict, user: dict, base: dict, source: str, where: str) -> None:
    for key, value in user.items():
        name = f"{where}{key}"
        if where == "frames." and isinstance(value, dict):
            into[key] = _merge_frame(into.get(key), value, source, name)
            continue
        if key not in base:
            known = ", ".join(sorted(base))
            raise CellConfigError(f"{source}: unknown key '{name}' (known here: {known})")
        if isinstance(base[key], dict):
            if not isinstance(value, dict):
                raise CellConfigError(f"{source}: '{name}' must be a table ([{name}])")
            _merge(into[key], value, base[key], source, name + ".")
        else:
            into[key] = _typed(value, base[key], source, name)


def _merge_frame(old: dict | None, value: dict, source: str, name: str) -> dict:
    frame = copy.deepcopy(old) if old else {"xyz": [0.0, 0.0, 0.0], "rpy": [0.0, 0.0, 0.0]}
    for key, v in value.items():
        if key not in frame:
            raise CellConfigError(f"{source}: unknown key '{name}.{key}' (a frame has xyz and rpy)")
        frame[key] = _typed(v, [0.0, 0.0, 0.0], source, f"{name}.{key}")
    return frame


def _typed(value: Any, like: Any, source: str, name: str) -> Any:
    """value checked to be of the same kind as the built-in value like."""
    def fail(what: str):
        raise CellConfigError(f"{source}: '{name}' must be {what}, not {value!r}")

    if isinstance(like, bool):
        if not isinstance(value, bool):
            fail("true or false")
        return value
    if isinstance(like, (int, float)):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            fail("a number")
        return type(like)(value) if isinstance(like, float) or float(value).is_integer() else fail("a whole number")
    if isinstance(like, str):
        if not isinstance(value, str):
            fail("a string")
        return value
    if isinstance(like, list):
        if not isinstance(value, list) or len(value) != len(like):
            fail(f"a list of {len(like)} numbers")
        return [_typed(v, x, source, name) for v, x in zip(value, like)]
    return value


def _check(data: dict, source: str) -> None:
    def fail(message: str):
        raise CellConfigError(f"{source}: {message}")

    robot, camera, tray = data["robot"], data["camera"], data["tray"]
    if robot["kind"] not in ("sim", "ssc32"):
        fail(f"robot.kind must be \"sim\" or \"ssc32\", not {robot['kind']!r}")
    if robot["kind"] == "ssc32" and not robot["port"]:
        fail("robot.port: an ssc32 arm needs its serial port")
    if camera["kind"] not in ("sim", "files"):
        fail(f"camera.kind must be \"sim\" or \"files\", not {camera['kind']!r}")
    if camera["kind"] == "files" and not camera["folder"]:
        fail("camera.folder: a files camera needs the folder its images are in")
    if camera["kind"] == "sim" and robot["kind"] != "sim":
        fail("the simulated camera sees the simulated tray, which only the simulated arm can reach: "
             "with robot.kind = \"ssc32\" use camera.kind = \"files\"")
    for name, (low, high) in RANGES.items():
        section, key = name.split(".")
        v = data[section][key]
        if not low <= v <= high:
            fail(f"{name} must be {low} to {high}, not {v}")
    if camera["px_per_mm"] != 0 and not MIN_PX_PER_MM <= camera["px_per_mm"] <= MAX_PX_PER_MM:
        fail(f"camera.px_per_mm must be 0 (from the width and fov) or {MIN_PX_PER_MM:g} to {MAX_PX_PER_MM:g}")
    if not 0 <= camera["tilt_deg"] < 45:
        fail(f"camera.tilt_deg must be 0 to 45, not {camera['tilt_deg']}")
    if tray["look"] not in LOOKS:
        fail(f"tray.look must be one of {', '.join(LOOKS)}, not {tray['look']!r}")
    low, high = tray["wires"]
    if not 0 <= low <= high <= 40:
        fail(f"tray.wires must be [low, high] with 0 <= low <= high <= 40, not {tray['wires']}")
    for section, key in (("press", "depth_mm"), ("bath", "depth_mm")):
        a, b = data[section][key]
        if not 0 <= a < b:
            fail(f"{section}.{key} must be [low, high] with 0 <= low < high, not {[a, b]}")
    if not 0 <= data["gripper"]["drop_rate"] <= 1:
        fail("gripper.drop_rate must be 0 to 1")
    for name in FRAME_NAMES_REQUIRED:
        if name not in data["frames"]:
            fail(f"frames.{name} is missing")
    for name in data["frames"]:
        if not is_name(name) or name.endswith("^"):
            fail(f"frames.{name}: a frame's name must be an RCL name (letters, digits, _)")
        if not np.all(np.isfinite(np.array(data["frames"][name]["xyz"] + data["frames"][name]["rpy"]))):
            fail(f"frames.{name}: xyz and rpy must be finite")
