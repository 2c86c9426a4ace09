"""Camera-model built-ins: calibration points, the bicubic warp, the marker.

Thin adapters over rcl.camera: the session's Calibration (ctx.camera_model)
and its camera (ctx.camera, anything with grab() -> image array).
"""
from __future__ import annotations

import numpy as np

from ..camera import CameraModelError, ImageError, find_mark
from ..context import Context
from ..errors import BuiltinError
from ..files import FileRefused
from ..frame import Vector, vec
from ..types import Var


def _model(ctx: Context, name: str):
    if ctx.camera_model is None:
        raise BuiltinError(f"{name}: this session has no camera model")
    return ctx.camera_model


def _call(name: str, action, *args):
    try:
        return action(*args)
    except (CameraModelError, ImageError) as e:
        raise BuiltinError(f"{name}: {e}") from None


def grab(ctx: Context, name: str):
    """A fresh image from the session's camera."""
    if ctx.camera is None:
        raise BuiltinError(f"{name}: this session has no camera to look with")
    image = _call(name, ctx.camera.grab)
    if image is None:
        raise BuiltinError(f"{name}: the camera returned no image")
    if not isinstance(image, np.ndarray) or image.dtype.kind not in "biuf":
        raise BuiltinError(f"{name}: the camera returned {type(image).__name__} "
                           f"{'of ' + str(image.dtype) + ' ' if isinstance(image, np.ndarray) else ''}"
                           f"instead of an image of numbers")
    return image


def calpoint(ctx: Context, u: float, v: float, x: float, y: float) -> None:
    """CALPOINT(u, v, x, y): add a correspondence: image point (u, v) px is tray point (x, y) mm."""
    _call("CALPOINT", _model(ctx, "CALPOINT").add_point, u, v, x, y)


def fitwarp(ctx: Context) -> float:
    """FITWARP(): fit the bicubic warp to the points added; gives the RMS residual in mm of the
    points kept. A point that the fit of the others misses grossly is left out, with a line saying so."""
    model = _model(ctx, "FITWARP")
    rms = float(_call("FITWARP", model.fit))
    for i, miss in model.left_out:
        u, v, x, y = model.points[i]
        ctx.out.write(f"FITWARP: point {i + 1}, ({u:.1f}, {v:.1f}) px at ({x:g}, {y:g}) mm, left out: "
                      f"the other points put it {miss:.1f} mm away\n")
    return rms


def _file(ctx: Context, name: str, path: str, writing: bool = False):
    """The real path of a file the program names, if it may touch it (rcl.files)."""
    try:
        return ctx.files.resolve(path, writing)
    except FileRefused as e:
        raise BuiltinError(f"{name}: {e}") from None


def loadwarp(ctx: Context, path: str) -> None:
    """LOADWARP(path): load a camera-model file (a warp or a linear camera)."""
    model = _model(ctx, "LOADWARP")
    _call("LOADWARP", model.load, _file(ctx, "LOADWARP", path))


def savewarp(ctx: Context, path: str) -> None:
    """SAVEWARP(path): save the fitted camera model to a file."""
    model = _model(ctx, "SAVEWARP")
    _call("SAVEWARP", model.save, _file(ctx, "SAVEWARP", path, writing=True))


def filepath(ctx: Context, path: str) -> str:
    """FILEPATH(name): the full path a file name stands for, where LOADWARP reads it and SAVEWARP writes it."""
    return str(_file(ctx, "FILEPATH", path))


def warp(ctx: Context, u: float, v: float) -> Vector:
    """WARP(u, v): the tray-plane point (mm) seen at image point (u, v) px."""
    x, y, z = _call("WARP", _model(ctx, "WARP").warp, u, v)
    return vec(x, y, z)


def findmark(ctx: Context, u: Var[float], v: Var[float]) -> bool:
    """FINDMARK(VAR u, VAR v): find the calibration marker in a fresh image; TRUE sets its centre (px)."""
    found = _call("FINDMARK", find_mark, grab(ctx, "FINDMARK"))
    if found is None:
        return False
    u.set(float(found[0]))
    v.set(float(found[1]))
    return True


BUILTINS = {
    "CALPOINT": calpoint, "FITWARP": fitwarp, "LOADWARP": loadwarp, "SAVEWARP": savewarp,
    "WARP": warp, "FINDMARK": findmark, "FILEPATH": filepath,
}
