"""RCL's static types, and how Python annotations name them.

A built-in's Python signature is its RCL signature: ``int`` is INTEGER,
``float`` REAL, ``bool`` BOOLEAN, ``str`` STRING, ``Vector`` VECTOR,
``Frame`` FRAME (``Annotated[Frame, "base -> t5"]`` with frame references),
``list[float]`` an open ARRAY OF REAL, ``Var[T]`` a VAR parameter of type T,
``Number`` INTEGER or REAL (a ``Number`` result is INTEGER only when every
``Number`` argument is), ``Printable`` any value, ``AnyArray`` any array.
"""
from __future__ import annotations

import typing
from dataclasses import dataclass
from typing import Annotated, Generic, TypeGuard, TypeVar

import numpy as np

from .frame import Frame


class Type:
    """Base of the static types."""


@dataclass(frozen=True)
class Prim(Type):
    name: str

    def __str__(self) -> str:
        return self.name


@dataclass(frozen=True)
class FrameType(Type):
    """FRAME, with the references it maps between where known (Paul's ^src dst)."""

    src: str | None = None
    dst: str | None = None

    def __str__(self) -> str:
        if self.src is None and self.dst is None:
            return "FRAME"
        return f"FRAME {self.src or '?'} -> {self.dst or '?'}"

    @property
    def plain(self) -> bool:
        return self.src is None and self.dst is None


@dataclass(frozen=True)
class ArrayType(Type):
    element: Type
    low: int | None = None  # None: an open array (parameters only)
    high: int | None = None

    @property
    def is_open(self) -> bool:
        return self.low is None

    def __str__(self) -> str:
        if self.is_open:
            return f"ARRAY OF {self.element}"
        return f"ARRAY [{self.low}..{self.high}] OF {self.element}"


@dataclass(frozen=True)
class _Special(Type):
    """Types that exist only in signatures or in error recovery."""

    name: str

    def __str__(self) -> str:
        return self.name


INTEGER = Prim("INTEGER")
INT_MIN, INT_MAX = -(2**63), 2**63 - 1  # an INTEGER's range: a literal past it is a static error, a result past it a runtime one
REAL = Prim("REAL")
BOOLEAN = Prim("BOOLEAN")
STRING = Prim("STRING")
VECTOR = Prim("VECTOR")
FRAME = FrameType()
ANY = _Special("ANY")  # the type of an expression already reported as wrong
NUMBER = _Special("INTEGER or REAL")
PRINTABLE = _Special("any value")
ANY_ARRAY = _Special("an array")

NAMED = {"integer": INTEGER, "real": REAL, "boolean": BOOLEAN, "string": STRING, "vector": VECTOR}


def int_div(x: int, y: int) -> int:
    """x DIV y: the quotient truncated toward zero (y not 0)."""
    q = abs(x) // abs(y)
    return q if (x < 0) == (y < 0) else -q


def int_mod(x: int, y: int) -> int:
    """x MOD y: the remainder with the dividend's sign, so that x = (x DIV y) * y + x MOD y."""
    return x - int_div(x, y) * y


def is_frame(t: Type | None) -> TypeGuard[FrameType]:
    return isinstance(t, FrameType)


def is_numeric(t: Type) -> bool:
    return t is INTEGER or t is REAL or t == INTEGER or t == REAL


def element_count(t: Type) -> int:
    """How many elements a value of t holds: 1 for a scalar, nested arrays counted whole."""
    n = 1
    while isinstance(t, ArrayType) and t.low is not None and t.high is not None:
        n *= t.high - t.low + 1
        t = t.element
    return n


def contains_frame(t: Type) -> bool:
    """Whether values of t must live in a frame name (frames and arrays of them)."""
    while isinstance(t, ArrayType):
        t = t.element
    return isinstance(t, FrameType)


def same_shape(a: Type, b: Type) -> bool:
    """Equal types, ignoring frame references."""
    if isinstance(a, FrameType) and isinstance(b, FrameType):
        return True
    if isinstance(a, ArrayType) and isinstance(b, ArrayType):
        return a.low == b.low and a.high == b.high and same_shape(a.element, b.element)
    return a == b


def assignable(target: Type, value: Type) -> bool:
    """Whether a value of type value may be stored where target is expected.

    Frame references are judged separately (refs_conflict), so that their
    error can say what differs.
    """
    if target is ANY or value is ANY:
        return True
    if target == REAL and value == INTEGER:
        return True
    if target is NUMBER:
        return is_numeric(value)
    if target is PRINTABLE:
        return True
    if target is ANY_ARRAY:
        return isinstance(value, ArrayType)
    if isinstance(target, ArrayType) and isinstance(value, ArrayType):
        if target.is_open:
            return same_shape(target.element, value.element)
        return same_shape(target, value)
    return same_shape(target, value)


def refs_conflict(target: Type, value: Type) -> str | None:
    """Why a frame of references value cannot go where target is expected, or None."""
    if not (isinstance(target, FrameType) and isinstance(value, FrameType)):
        return None
    for side, want, got in (("starts", target.src, value.src), ("ends", target.dst, value.dst)):
        if want is not None and got is not None and want != got:
            return f"expected a frame {target.src} -> {target.dst}, but this one {side} at {got!r} (it is {value})"
    return None


def compose(left: FrameType, right: FrameType) -> tuple[FrameType, str | None]:
    """The references of left * right, and the mismatch if their inner names differ."""
    problem = None
    if left.dst is not None and right.src is not None and left.dst != right.src:
        problem = (f"frames do not chain: the left factor ends at {left.dst!r} "
                   f"but the right one starts at {right.src!r} ({left} * {right})")
    return FrameType(left.src, right.dst), problem


def inverse(t: FrameType) -> FrameType:
    return FrameType(t.dst, t.src)


@dataclass(frozen=True)
class ParamInfo:
    """A routine's parameter as callers see it: a built-in's (from its annotations) or one
    written in RCL (from its declaration)."""

    name: str
    type: Type
    by_ref: bool


def parse_refs(text: str) -> FrameType:
    left, _, right = text.partition("->")
    return FrameType(left.strip().lower() or None, right.strip().lower() or None)


# Annotations -------------------------------------------------------------

T = TypeVar("T")


class Var(Generic[T]):
    """Annotation: a VAR (by-reference) parameter; the built-in receives a Ref, which has these."""

    def get(self) -> T:
        raise NotImplementedError

    def set(self, value: T) -> None:
        raise NotImplementedError


class Printable:
    """Annotation: any RCL value."""


if typing.TYPE_CHECKING:  # what a built-in receives, as mypy should see it
    from .values import Array

    Number = float  # an INTEGER (int) is a float to mypy
    AnyArray = Array
    RealArray = Array
else:  # the same names as RCL signatures (see from_annotation)
    class Number:
        """Annotation: INTEGER or REAL."""

    class AnyArray:
        """Annotation: an array of any element type and bounds."""

    RealArray = list[float]  # an ARRAY OF REAL; the built-in receives a values.Array


_SIMPLE = {int: INTEGER, float: REAL, bool: BOOLEAN, str: STRING, np.ndarray: VECTOR,
           Frame: FRAME, Number: NUMBER, Printable: PRINTABLE, AnyArray: ANY_ARRAY}


SWAPPED = "the first argument's frame references, swapped"
"""Annotated[Frame, SWAPPED] as a built-in's result: INV of a [a -> b] frame is a [b -> a] frame."""


def swaps_refs(annotation) -> bool:
    """Whether a built-in's result annotation is Annotated[Frame, SWAPPED]."""
    return typing.get_origin(annotation) is Annotated and typing.get_args(annotation)[1:2] == (SWAPPED,)


def from_annotation(annotation) -> tuple[Type, bool]:
    """(type, by_ref) for a Python annotation of a built-in's parameter or result."""
    origin = typing.get_origin(annotation)
    if origin is Var:
        (inner,) = typing.get_args(annotation)
        return from_annotation(inner)[0], True
    if origin is Annotated:
        base, *meta = typing.get_args(annotation)
        if base is Frame and meta:
            return (FRAME if swaps_refs(annotation) else parse_refs(meta[0])), False
        return from_annotation(base)
    if origin is list:
        (inner,) = typing.get_args(annotation)
        return ArrayType(from_annotation(inner)[0]), False
    if annotation in _SIMPLE:
        return _SIMPLE[annotation], False
    raise TypeError(f"no RCL type for the annotation {annotation!r}")
