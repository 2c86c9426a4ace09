"""The typing rules of RCL's operators (section 4), as plain functions of types.

Each rule gives the result type, or a message saying why the operation is not
allowed; the checker reports the message at the operator.
"""
from __future__ import annotations

from functools import lru_cache

from . import types as T

ORDERING = {"<", "<=", ">", ">="}


def article(t) -> str:
    text = str(t)
    return ("an " if text[:1] in "AEIOU" else "a ") + text


@lru_cache(maxsize=1024)  # a program uses few (op, type, type) triples, each many times
def binop_type(op: str, a: T.Type, b: T.Type) -> T.Type | str:
    """The result type of a op b, or a message saying why it is not allowed."""
    num_a, num_b = T.is_numeric(a), T.is_numeric(b)
    fa, fb = T.is_frame(a), T.is_frame(b)
    if op in ("AND", "OR"):
        if a == b == T.BOOLEAN:
            return T.BOOLEAN
        return f"{op} needs BOOLEANs, not {a} and {b}"
    if op in ("=", "<>"):
        if (num_a and num_b) or (a == b and a in (T.BOOLEAN, T.STRING)):
            return T.BOOLEAN
        if fa or fb or T.VECTOR in (a, b):
            return "frames and vectors are not compared with = or <>; compare DIST(A^, B^) or NORM(u - v) with a tolerance"
        return f"cannot compare {article(a)} with {article(b)}"
    if op in ORDERING:
        if (num_a and num_b) or a == b == T.STRING:
            return T.BOOLEAN
        return f"{op} compares numbers or strings, not {a} and {b}"
    if fa or fb:
        if op == "*":
            if fa and fb:
                return T.FRAME
            if fa and b == T.VECTOR:
                return T.VECTOR
            if fb and num_a:
                return "a FRAME cannot be scaled; frames are multiplied only by frames (and vectors)"
            return f"a FRAME can multiply a FRAME or a VECTOR, not {article(b if fa else a)}"
        if op in ("+", "-"):
            return f"frames are combined with *, not {op} (to move a frame, multiply by TRANS(x, y, z))"
        return f"{op} is not defined for frames"
    if op == "+" and a == b == T.STRING:
        return T.STRING
    if a == T.VECTOR or b == T.VECTOR:
        if op in ("+", "-") and a == b:
            return T.VECTOR
        if op == "*" and (num_a or num_b):
            return T.VECTOR
        if op == "/" and a == T.VECTOR and num_b:
            return T.VECTOR
        if op == "*" and a == b:
            return "VECTOR * VECTOR is not defined; use DOT(u, v) or CROSS(u, v)"
        return f"{op} is not defined for {a} and {b}"
    if num_a and num_b:
        if op == "/":
            return T.REAL
        if op in ("DIV", "MOD"):
            if a == b == T.INTEGER:
                return T.INTEGER
            return f"{op} takes INTEGERs (for REALs use /), not {a} and {b}"
        return T.INTEGER if a == b == T.INTEGER else T.REAL
    return f"{op} is not defined for {article(a)} and {article(b)}"
