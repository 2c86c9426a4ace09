"""Run-time values: arrays, default values and how WRITE shows each type.

INTEGER is a Python int, REAL a float (always: the interpreter converts
where an INTEGER flows into a REAL), BOOLEAN a bool, STRING a str, VECTOR a
read-only numpy array of shape (3,), FRAME a rcl.frame.Frame, and an array
an Array. An unassigned variable holds None.
"""
from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from .frame import Frame
from .types import BOOLEAN, INTEGER, REAL, STRING, VECTOR, ArrayType, Type


class Ref:
    """A reference to a variable or array element, as a VAR parameter receives it."""

    __slots__ = ("c", "i")

    def __init__(self, container: list, index: int) -> None:
        self.c = container
        self.i = index

    def get(self) -> Any:
        return self.c[self.i]

    def set(self, value: Any) -> None:
        self.c[self.i] = value


class Array:
    """A fixed-size RCL array: its low bound and its elements."""

    __slots__ = ("low", "items")

    def __init__(self, low: int, items: list) -> None:
        self.low = low
        self.items = items

    @property
    def high(self) -> int:
        return self.low + len(self.items) - 1

    def copy(self) -> Array:
        return Array(self.low, [x.copy() if isinstance(x, Array) else x for x in self.items])

    def __eq__(self, other) -> bool:
        return (isinstance(other, Array) and self.low == other.low
                and len(self.items) == len(other.items)
                and all(_same(a, b) for a, b in zip(self.items, other.items)))

    def __repr__(self) -> str:
        return f"Array(low={self.low}, items={self.items!r})"


def _same(a, b) -> bool:
    if isinstance(a, np.ndarray):
        return isinstance(b, np.ndarray) and bool(np.array_equal(a, b))
    return a == b


_ZERO_VECTOR = np.zeros(3)
_ZERO_VECTOR.flags.writeable = False


def default_factory(t: Type) -> Callable[[], Any]:
    """What a declared variable of type t holds before any assignment.

    Numbers are 0, BOOLEAN FALSE, STRING '', VECTOR (0, 0, 0); a FRAME has no
    value until assigned (reading it is a run-time error): a robot must never
    move to a frame nobody set.
    """
    if isinstance(t, ArrayType):
        assert t.low is not None and t.high is not None, "an open array is a parameter's type, never a variable's"
        size = t.high - t.low + 1
        element = default_factory(t.element)
        low = t.low
        return lambda: Array(low, [element() for _ in range(size)])
    defaults: dict[Type, Any] = {INTEGER: 0, REAL: 0.0, BOOLEAN: False, STRING: "", VECTOR: _ZERO_VECTOR}
    value = defaults.get(t)
    return lambda: value


def format_real(x: float) -> str:
    return format(x + 0.0, ".6g")  # + 0.0 turns -0.0 into 0.0


def format_value(v: Any) -> str:
    """A value as WRITE shows it."""
    if isinstance(v, bool):
        return "TRUE" if v else "FALSE"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return format_real(v)
    if isinstance(v, str):
        return v
    if isinstance(v, np.ndarray):
        return "(" + ", ".join(format_real(float(c)) for c in v) + ")"
    if isinstance(v, Frame):
        roll, pitch, yaw = v.rpy_angles()
        x, y, z = (format_real(float(c)) for c in v.p)
        return f"TRANS({x}, {y}, {z}) * RPY({format_real(roll)}, {format_real(pitch)}, {format_real(yaw)})"
    if isinstance(v, Array):
        return "[" + ", ".join(format_value(x) for x in v.items) + "]"
    if v is None:
        return "(no value)"
    return str(v)
