"""Built-ins for frames, vectors, numbers, strings, arrays, errors and output.

Angles are in degrees, lengths in millimetres.
"""
from __future__ import annotations

import math
from typing import Annotated

from ..context import Context
from ..errors import BuiltinError
from ..frame import Frame, Vector, vec
from ..types import SWAPPED, AnyArray, Number, Printable
from ..values import format_value

# Frames ------------------------------------------------------------------


def trans(x: float, y: float, z: float) -> Frame:
    """TRANS(x, y, z): a translation by (x, y, z) mm."""
    return Frame.trans(x, y, z)


def rotx(a: float) -> Frame:
    """ROTX(a): a rotation by a degrees about X."""
    return Frame.rotx(a)


def roty(a: float) -> Frame:
    """ROTY(a): a rotation by a degrees about Y."""
    return Frame.roty(a)


def rotz(a: float) -> Frame:
    """ROTZ(a): a rotation by a degrees about Z."""
    return Frame.rotz(a)


def rot(axis: Vector, a: float) -> Frame:
    """ROT(axis, a): a rotation by a degrees about the axis (any non-zero VECTOR) through the origin."""
    return Frame.rot(axis, a)


def rpy(roll: float, pitch: float, yaw: float) -> Frame:
    """RPY(roll, pitch, yaw) = ROTZ(yaw) * ROTY(pitch) * ROTX(roll)."""
    return Frame.rpy(roll, pitch, yaw)


def euler(phi: float, theta: float, psi: float) -> Frame:
    """EULER(phi, theta, psi) = ROTZ(phi) * ROTY(theta) * ROTZ(psi)."""
    return Frame.euler(phi, theta, psi)


def frame(n: Vector, o: Vector, a: Vector, p: Vector) -> Frame:
    """FRAME(n, o, a, p): the frame with axes n, o, a (orthonormal, right-handed within 1e-6) and origin p."""
    return Frame.from_columns(n, o, a, p)


def inv(f: Frame) -> Annotated[Frame, SWAPPED]:
    """INV(F^): the inverse frame (closed form for a rigid transform)."""
    return f.inv()


def ident() -> Frame:
    """IDENT(): the identity frame."""
    return Frame.identity()


def dist(f1: Frame, f2: Frame) -> float:
    """DIST(F1^, F2^): the distance between the two origins, mm."""
    return f1.dist(f2)


def pos(f: Frame) -> Vector:
    """POS(F^) = F^.P, the origin of a frame."""
    return f.p


# Vectors -----------------------------------------------------------------


def vec_(x: float, y: float, z: float) -> Vector:
    """VEC(x, y, z): a vector (mm)."""
    return vec(x, y, z)


def dot(u: Vector, v: Vector) -> float:
    """DOT(u, v): the scalar product."""
    return float(u @ v)


def cross(u: Vector, v: Vector) -> Vector:
    """CROSS(u, v): the vector product."""
    (a, b, c), (d, e, f) = u, v
    return vec(b * f - c * e, c * d - a * f, a * e - b * d)


def norm(v: Vector) -> float:
    """NORM(v): the length of v."""
    return math.sqrt(float(v @ v))


def unit(v: Vector) -> Vector:
    """UNIT(v): v scaled to length 1 (an error for the zero vector)."""
    n = math.sqrt(float(v @ v))
    if not n > 0.0:
        raise BuiltinError("UNIT of a zero-length vector")
    out = v / n
    out.flags.writeable = False
    return out


# Numbers -----------------------------------------------------------------


def abs_(x: Number) -> Number:
    """ABS(x): the absolute value (INTEGER for an INTEGER)."""
    return abs(x)


def sqrt(x: float) -> float:
    """SQRT(x): the square root of x >= 0."""
    if x < 0:
        raise BuiltinError(f"SQRT of a negative number ({format_value(float(x))})")
    return math.sqrt(x)


def _angle(name: str, a: float) -> float:
    """a degrees in radians; BuiltinError for an angle that is no number or infinite."""
    if not math.isfinite(a):
        raise BuiltinError(f"{name} of {format_value(float(a))} degrees: the angle must be a finite number")
    return math.radians(a)


def sin(a: float) -> float:
    """SIN(a): the sine of a degrees."""
    return math.sin(_angle("SIN", a))


def cos(a: float) -> float:
    """COS(a): the cosine of a degrees."""
    return math.cos(_angle("COS", a))


def tan(a: float) -> float:
    """TAN(a): the tangent of a degrees."""
    r = _angle("TAN", a)
    if (a - 90.0) % 180.0 == 0.0:
        raise BuiltinError(f"TAN is infinite at {format_value(float(a))} degrees")
    return math.tan(r)


def _unit_interval(name: str, x: float) -> float:
    # Values a rounding error past +-1 (a DOT of unit vectors, say) are clamped.
    if abs(x) > 1.0 + 1e-9 or math.isnan(x):
        raise BuiltinError(f"{name} needs a value between -1 and 1, not {format_value(float(x))}")
    return max(-1.0, min(1.0, x))


def asin(x: float) -> float:
    """ASIN(x): the angle in degrees, -90..90, whose sine is x."""
    return math.degrees(math.asin(_unit_interval("ASIN", x)))


def acos(x: float) -> float:
    """ACOS(x): the angle in degrees, 0..180, whose cosine is x."""
    return math.degrees(math.acos(_unit_interval("ACOS", x)))


def atan2(y: float, x: float) -> float:
    """ATAN2(y, x): the angle in degrees, -180..180, of the point (x, y)."""
    return math.degrees(math.atan2(y, x))


def _to_integer(name: str, x: float) -> int:
    if not math.isfinite(x) or abs(x) >= 2.0**63:
        raise BuiltinError(f"{name} of {format_value(float(x))} is not a 64-bit INTEGER")
    return int(x)


def round_(x: float) -> int:
    """ROUND(x): the nearest INTEGER, halves away from zero."""
    if not math.isfinite(x):
        return _to_integer("ROUND", x)
    return _to_integer("ROUND", math.copysign(math.floor(abs(x) + 0.5), x))


def trunc(x: float) -> int:
    """TRUNC(x): x with its fraction dropped (towards zero)."""
    return _to_integer("TRUNC", x)


def min_(a: Number, b: Number, *more: Number) -> Number:
    """MIN(a, b, ...): the smallest argument."""
    return min(a, b, *more)


def max_(a: Number, b: Number, *more: Number) -> Number:
    """MAX(a, b, ...): the largest argument."""
    return max(a, b, *more)


def str_(x: Printable) -> str:
    """STR(x): x as WRITE would write it."""
    return format_value(x)


# Arrays and errors -------------------------------------------------------


def low(a: AnyArray) -> int:
    """LOW(a): the lowest index of an array."""
    return a.low


def high(a: AnyArray) -> int:
    """HIGH(a): the highest index of an array."""
    return a.low + len(a.items) - 1


def errmsg(ctx: Context) -> str:
    """ERRMSG(): inside EXCEPT, the message of the error being handled ('' elsewhere)."""
    return ctx.errmsgs[-1] if ctx.errmsgs else ""


# Output ------------------------------------------------------------------


def write(ctx: Context, *args: Printable) -> None:
    """WRITE(args...): write the arguments with no separator."""
    ctx.out.write("".join(format_value(a) for a in args))


def writeln(ctx: Context, *args: Printable) -> None:
    """WRITELN(args...): write the arguments, then a newline."""
    ctx.out.write("".join(format_value(a) for a in args) + "\n")


BUILTINS = {
    "TRANS": trans, "ROTX": rotx, "ROTY": roty, "ROTZ": rotz, "ROT": rot, "RPY": rpy,
    "EULER": euler, "FRAME": frame, "INV": inv, "IDENT": ident, "DIST": dist, "POS": pos,
    "VEC": vec_, "DOT": dot, "CROSS": cross, "NORM": norm, "UNIT": unit,
    "ABS": abs_, "SQRT": sqrt, "SIN": sin, "COS": cos, "TAN": tan, "ASIN": asin,
    "ACOS": acos, "ATAN2": atan2, "ROUND": round_, "TRUNC": trunc, "MIN": min_, "MAX": max_,
    "STR": str_, "LOW": low, "HIGH": high, "ERRMSG": errmsg, "WRITE": write, "WRITELN": writeln,
}
