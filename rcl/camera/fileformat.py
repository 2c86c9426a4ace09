"""The camera-model file: versioned JSON holding either model, its fit and its z plane.

    {"format": "rcl-camera-model", "version": 1, "model": "warp" | "linear", "z_mm": 0.0,
     "warp": {"u0": .., "su": .., "v0": .., "sv": .., "x": [16], "y": [16],
              "inverse": {"x0": .., "sx": .., "y0": .., "sy": .., "u": [16], "v": [16]}},
     "linear": {"C": [[4], [4], [4]]},
     "fit": {"points": N, "rms_mm": .., "max_mm": .., "loo_rms_mm": .. | null, "residuals_mm": [[dx, dy], ...]}}

The warp's terms are u^i v^j with i major (i, j = 0..3) of the normalised
u' = (u - u0) / su, v' = (v - v0) / sv.
"""
from __future__ import annotations

import json
import math
import os
import re
import stat
from pathlib import Path
from typing import Any

import numpy as np

from .models import Bicubic, BicubicWarp, CameraModelError, FitReport, LinearCamera, Normalisation

FORMAT = "rcl-camera-model"
VERSION = 1
MAX_BYTES = 1024 * 1024  # a camera-model file is a few kB; a larger one is not one (or a device)
MAX_NESTING = 8  # a camera-model file nests 3 deep

Model = BicubicWarp | LinearCamera


def to_json(model: Model, z: float, report: FitReport | None) -> dict:
    doc: dict = {"format": FORMAT, "version": VERSION, "z_mm": float(z)}
    if isinstance(model, BicubicWarp):
        f, b = model.forward, model.backward
        doc["model"] = "warp"
        doc["warp"] = {"u0": f.norm.centre[0], "su": f.norm.scale[0], "v0": f.norm.centre[1],
                       "sv": f.norm.scale[1], "x": f.p.tolist(), "y": f.q.tolist(),
                       "inverse": {"x0": b.norm.centre[0], "sx": b.norm.scale[0], "y0": b.norm.centre[1],
                                   "sy": b.norm.scale[1], "u": b.p.tolist(), "v": b.q.tolist()}}
    else:
        doc["model"] = "linear"
        doc["linear"] = {"C": model.C.tolist()}
    if report is not None:
        doc["fit"] = {"points": report.points, "rms_mm": report.rms, "max_mm": report.max,
                      "loo_rms_mm": report.loo_rms, "residuals_mm": report.residuals.tolist()}
    return doc


def save(path: str | Path, model: Model, z: float, report: FitReport | None) -> None:
    text = json.dumps(to_json(model, z, report), indent=2)
    try:
        Path(path).write_text(text + "\n", encoding="utf-8")
    except OSError as e:
        raise CameraModelError(f"cannot write {path}: {e.strerror or e}") from None


def load(path: str | Path) -> tuple[Model, float, FitReport | None]:
    """(model, z plane, fit report) from a file; CameraModelError says what is wrong."""
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))  # a pipe must not block the open
        with open(fd, "rb") as f:
            if not stat.S_ISREG(os.fstat(fd).st_mode):
                raise CameraModelError(f"{path} is not a regular file")
            data = f.read(MAX_BYTES + 1)
        if len(data) > MAX_BYTES:
            raise CameraModelError(f"{path} is larger than {MAX_BYTES // 1024} kB: not a camera-model file")
        text = data.decode("utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise CameraModelError(f"cannot read {path}: {getattr(e, 'strerror', None) or e}") from None
    depth = _nesting(text)
    if depth > MAX_NESTING:
        raise CameraModelError(f"{path}: arrays and objects nested {depth} deep: not a camera-model file")
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as e:
        raise CameraModelError(f"{path}:{e.lineno}:{e.colno}: not JSON: {e.msg}") from None
    except ValueError as e:  # a number of thousands of digits
        raise CameraModelError(f"{path}: not a camera-model file: {e}") from None
    try:
        return from_json(doc)
    except CameraModelError as e:
        raise CameraModelError(f"{path}: {e}") from None


def _nesting(text: str) -> int:
    """How deep JSON text nests arrays and objects (brackets inside strings do not count): the
    parser recurses as deep, and a hostile file must not take the stack with it."""
    bare = re.sub(r'"(?:[^"\\]|\\.)*"', '""', text).encode("utf-8")
    b = np.frombuffer(bare, np.uint8)
    step = np.isin(b, (ord("["), ord("{"))).astype(np.int32) - np.isin(b, (ord("]"), ord("}")))
    return int(np.cumsum(step).max(initial=0))


def from_json(doc) -> tuple[Model, float, FitReport | None]:
    if not isinstance(doc, dict) or doc.get("format") != FORMAT:
        raise CameraModelError(f"not an RCL camera-model file (no \"format\": \"{FORMAT}\")")
    version = doc.get("version")
    if version != VERSION:
        raise CameraModelError(f"camera-model file version {version!r} is not supported "
                               f"(this rcl reads version {VERSION})")
    z = _number(doc, "z_mm")
    kind = doc.get("model")
    if kind == "warp":
        w = _section(doc, "warp")
        inv = _section(w, "inverse")
        forward = Bicubic(Normalisation((_number(w, "u0"), _number(w, "v0")), (_scale(w, "su"), _scale(w, "sv"))),
                          _vector(w, "x", 16), _vector(w, "y", 16))
        backward = Bicubic(Normalisation((_number(inv, "x0"), _number(inv, "y0")),
                                         (_scale(inv, "sx"), _scale(inv, "sy"))),
                           _vector(inv, "u", 16), _vector(inv, "v", 16))
        model: Model = BicubicWarp(forward, backward, z)
    elif kind == "linear":
        c = np.array(_section(doc, "linear").get("C"), dtype=object)
        try:
            c = np.array(c.tolist(), dtype=float)
        except (TypeError, ValueError):
            raise CameraModelError("\"linear\".\"C\" must be 3 rows of 4 numbers") from None
        if c.shape != (3, 4) or not np.all(np.isfinite(c)):
            raise CameraModelError("\"linear\".\"C\" must be 3 rows of 4 finite numbers")
        model = LinearCamera(c)
    else:
        raise CameraModelError(f"\"model\" must be \"warp\" or \"linear\", not {kind!r}")
    report = None
    fit = doc.get("fit")
    if fit is not None:
        if not isinstance(fit, dict):
            raise CameraModelError(f"\"fit\" must be an object, not {type(fit).__name__}")
        rows = fit.get("residuals_mm", [])
        if not isinstance(rows, list) or not all(
                isinstance(r, list) and len(r) == 2 and all(_finite(x) for x in r) for r in rows):
            raise CameraModelError("\"residuals_mm\" must be a list of [dx, dy] pairs of finite numbers")
        residuals = np.array(rows, dtype=float).reshape(-1, 2)
        points = fit.get("points", len(residuals))
        if isinstance(points, bool) or not isinstance(points, int) or not 0 <= points <= 1_000_000:
            raise CameraModelError(f"\"points\" must be a whole number of points, not {str(points)[:40]}")
        loo = fit.get("loo_rms_mm")
        report = FitReport(points, _number(fit, "rms_mm"), _number(fit, "max_mm"),
                           None if loo is None else _number(fit, "loo_rms_mm"), residuals)
    return model, z, report


def _finite(value) -> bool:
    """Whether a JSON value is a finite number (not a bool, not an integer too large for a float)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return False
    try:
        return math.isfinite(value)
    except OverflowError:
        return False


def _section(doc: dict, key: str) -> dict:
    part = doc.get(key)
    if not isinstance(part, dict):
        raise CameraModelError(f"missing the \"{key}\" section")
    return part


def _number(doc: dict, key: str) -> float:
    value: Any = doc.get(key)
    if not _finite(value):
        raise CameraModelError(f"\"{key}\" must be a finite number, not {str(value)[:40]}")
    return float(value)


def _scale(doc: dict, key: str) -> float:
    value = _number(doc, key)
    if value == 0.0:
        raise CameraModelError(f"\"{key}\" must not be zero")
    return value


def _vector(doc: dict, key: str, n: int) -> np.ndarray:
    value = doc.get(key)
    if (not isinstance(value, list) or len(value) != n
            or not all(isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) for x in value)):
        raise CameraModelError(f"\"{key}\" must be a list of {n} finite numbers")
    return np.array(value, dtype=float)
