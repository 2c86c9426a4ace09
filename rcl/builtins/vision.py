"""Vision built-ins: a fresh camera image in, the chosen wire end out as frames.

They call the session's sensor: an object with
``find_wire(method) -> (W, WG) | None`` where W and WG are 4x4 matrices
(W^: the wire end in world coordinates; WG^: the gripper relative to W^).
"""
from __future__ import annotations

from typing import Annotated

from ..errors import BuiltinError
from ..frame import Frame, FrameError
from ..types import Var


def _find(ctx, method: str, w: Var[Frame], wg: Var[Frame], name: str) -> bool:
    if ctx.sensor is None:
        raise BuiltinError(f"{name}: this session has no camera to look with")
    found = ctx.sensor.find_wire(method)
    if found is None:
        return False
    try:
        w.set(Frame(found[0]))
        wg.set(Frame(found[1]))
    except FrameError as e:
        raise BuiltinError(f"{name}: the vision result is not a frame: {e}") from None
    return True


WorldToWire = Annotated[Frame, "world -> wire"]
WireToTool = Annotated[Frame, "wire -> tool"]


def binwire(ctx, w: Var[WorldToWire], wg: Var[WireToTool]) -> bool:
    """BINWIRE(VAR W^, VAR WG^): look with the binary pipeline; TRUE sets W^ and WG^, FALSE if no graspable end."""
    return _find(ctx, "binary", w, wg, "BINWIRE")


def greywire(ctx, w: Var[WorldToWire], wg: Var[WireToTool]) -> bool:
    """GREYWIRE(VAR W^, VAR WG^): look with the grey-scale pipeline; TRUE sets W^ and WG^, FALSE if no graspable end."""
    return _find(ctx, "grey", w, wg, "GREYWIRE")


BUILTINS = {"BINWIRE": binwire, "GREYWIRE": greywire}
