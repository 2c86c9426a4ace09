"""Vision built-ins: a fresh camera image in, the chosen wire end out as frames.

The session's wire finder (ctx.wire_finder(image, method) -> Sighting | None)
looks; the session's camera model turns its pixels into the frames of the
language reference: W^ has its origin at the wire end, Z along the wire away
from the end and X up out of the tray; WG^ is the gripper relative to W^,
at the grasp point with its approach (Z) pointing down into the tray and its
fingers closing across the wire.
"""
from __future__ import annotations

import math
from typing import Annotated

import numpy as np

from ..camera import CameraModelError
from ..context import Context
from ..errors import BuiltinError
from ..frame import Frame
from ..types import Var
from ..vision import Sighting
from .camera import grab

WorldToWire = Annotated[Frame, "world -> wire"]
WireToTool = Annotated[Frame, "wire -> tool"]
STEP_PX = 1.0  # how far along an image direction to look when mapping it to the tray


def wire_frames(model, s: Sighting) -> tuple[Frame, Frame]:
    """(W, WG) for a sighting, through the camera model (anything with warp(u, v) -> (x, y, z))."""
    end = np.array(model.warp(*s.end))
    along = _tray_direction(model, s.end, s.end_angle)
    up = np.array([0.0, 0.0, 1.0])
    w = Frame.from_columns(up, np.cross(along, up), along, end)
    grasp = np.array(model.warp(*s.grasp))
    tangent = _tray_direction(model, s.grasp, s.grasp_angle)
    down = -up
    across = np.cross(down, tangent)  # the fingers close across the wire
    g = Frame.from_columns(np.cross(across, down), across, down, grasp)
    return w, w.inv() * g


def _tray_direction(model, uv, angle_deg: float) -> np.ndarray:
    t = math.radians(angle_deg)
    u, v = uv
    a = np.array(model.warp(u, v))
    b = np.array(model.warp(u + STEP_PX * math.cos(t), v + STEP_PX * math.sin(t)))
    d = b - a
    d[2] = 0.0
    n = float(np.linalg.norm(d))
    if not n > 0.0:
        raise BuiltinError("the camera model maps the wire direction to nothing")
    return d / n


def _find(ctx: Context, method: str, w: Var[Frame], wg: Var[Frame], name: str) -> bool:
    if ctx.wire_finder is None:
        raise BuiltinError(f"{name}: this session has no {method} wire finder")
    image = grab(ctx, name)
    try:
        sighting = ctx.wire_finder(image, method)
    except BuiltinError as e:
        raise BuiltinError(f"{name}: {e}") from None
    if sighting is None:
        return False
    try:
        frames = wire_frames(ctx.camera_model, sighting)
    except CameraModelError as e:
        raise BuiltinError(f"{name}: {e}") from None
    w.set(frames[0])
    wg.set(frames[1])
    return True


def binwire(ctx: Context, w: Var[WorldToWire], wg: Var[WireToTool]) -> bool:
    """BINWIRE(VAR W^, VAR WG^): look with the binary pipeline; TRUE sets W^ and WG^, FALSE if no graspable end."""
    return _find(ctx, "binary", w, wg, "BINWIRE")


def findwire(ctx: Context, w: Var[WorldToWire], wg: Var[WireToTool]) -> bool:
    """FINDWIRE(VAR W^, VAR WG^): look with the default wire finder (centre lines as ridges, every end checked free); TRUE sets W^ and WG^, FALSE if no graspable end."""  # noqa: E501 - one line: the REPL's :help shows it whole
    return _find(ctx, "ridge", w, wg, "FINDWIRE")


def findmiddle(ctx: Context, w: Var[WorldToWire], wg: Var[WireToTool]) -> bool:
    """FINDMIDDLE(VAR W^, VAR WG^): look for a place to take a wire by its middle, 20 mm or more along the lines seen from their ends and 8 mm from any crossing, with room for the fingers (for a wire none of whose ends is free: lift it and let it fall in a new shape); TRUE sets W^ there (Z along the wire) and WG^ the grasp at W^'s origin, FALSE if there is none."""  # noqa: E501 - one line: the REPL's :help shows it whole
    return _find(ctx, "middle", w, wg, "FINDMIDDLE")


def greywire(ctx: Context, w: Var[WorldToWire], wg: Var[WireToTool]) -> bool:
    """GREYWIRE(VAR W^, VAR WG^): look with the grey-scale pipeline; TRUE sets W^ and WG^, FALSE if no graspable end."""
    return _find(ctx, "grey", w, wg, "GREYWIRE")


BUILTINS = {"FINDWIRE": findwire, "BINWIRE": binwire, "GREYWIRE": greywire, "FINDMIDDLE": findmiddle}
