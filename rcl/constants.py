"""Constant expressions: folded at check time for CONST values and array bounds."""
from __future__ import annotations

from collections.abc import Callable
from typing import Any

from . import ast as A
from . import types as T

ARITHMETIC = {"+", "-", "*", "/", "DIV", "MOD"}


class NotConstant(Exception):
    """The expression needs run time to evaluate."""


def fold(e: A.Expr, name: Callable[[A.Name], tuple], typed: Callable, error: Callable) -> tuple[Any, T.Type]:
    """(value, type) of e, built from literals, CONSTs (name(e) gives theirs) and operators.

    typed(e) types a literal in the checker (reporting bad literals); error(span, text)
    reports a division by zero. Raises NotConstant for anything else.
    """
    if isinstance(e, A.Integer):
        typed(e)
        return (int(e.text) if len(e.text) <= 19 else 0), T.INTEGER
    if isinstance(e, A.Real):
        return float(e.text), T.REAL
    if isinstance(e, A.String):
        return e.value, T.STRING
    if isinstance(e, A.Boolean):
        return e.value, T.BOOLEAN
    if isinstance(e, A.Name):
        return name(e)
    if isinstance(e, A.UnOp):
        value, t = fold(e.operand, name, typed, error)
        if e.op == "NOT" and t == T.BOOLEAN:
            return not value, t
        if e.op in "+-" and T.is_numeric(t):
            return (-value if e.op == "-" else value), t
        raise NotConstant
    if isinstance(e, A.BinOp) and e.op in ARITHMETIC:
        a, ta = fold(e.left, name, typed, error)
        b, tb = fold(e.right, name, typed, error)
        if not (T.is_numeric(ta) and T.is_numeric(tb)):
            if e.op == "+" and ta == tb == T.STRING:
                return a + b, T.STRING
            raise NotConstant
        both_int = ta == tb == T.INTEGER
        if e.op in ("/", "DIV", "MOD") and b == 0:
            error(e.span, "division by zero in a constant")
            return 0, T.INTEGER if e.op != "/" else T.REAL
        if e.op == "/":
            return a / b, T.REAL
        if e.op in ("DIV", "MOD"):
            if not both_int:
                raise NotConstant
            return (T.int_div(a, b) if e.op == "DIV" else T.int_mod(a, b)), T.INTEGER
        value = {"+": a + b, "-": a - b, "*": a * b}[e.op]
        return value, T.INTEGER if both_int else T.REAL
    raise NotConstant
