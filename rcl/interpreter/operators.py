"""The compiler's operators: each of RCL's unary and binary operators as a closure, doing only what
the operands' static types say (INTEGER + INTEGER is a checked 64-bit add, FRAME * FRAME a matrix
product) and the checks only run time can make (overflow, division by zero, a STRING's length)."""
from __future__ import annotations

from collections.abc import Callable
from typing import NoReturn

from .. import ast as A
from .. import types as T
from ..frame import Frame
from ..scope import Variable
from ..types import INT_MAX, INT_MIN  # bound here: read on every INTEGER operation
from .base import _COMPARE, MAX_STRING, CompilerBase


class Operators(CompilerBase):
    def expr_UnOp(self, e: A.UnOp):
        f = self.expr(e.operand)
        if e.op == "NOT":
            return lambda fr: not f(fr)
        if e.op == "+":
            return f
        if e.type == T.INTEGER:
            return self._checked(lambda fr: -f(fr), e.span)
        return lambda fr: -f(fr)

    def _checked(self, f: Callable, span: A.Span) -> Callable:
        """An INTEGER operation with 64-bit overflow detection."""
        make = self._raiser()

        def run(fr):
            x = f(fr)
            if INT_MIN <= x <= INT_MAX:
                return x
            raise make("INTEGER overflow (beyond 64 bits)", span)
        return run

    def expr_BinOp(self, e: A.BinOp):
        ta, tb = e.left.type, e.right.type
        if T.is_frame(ta) and T.is_frame(tb):
            return self._frame_product(e)
        op, a, b = e.op, self.expr(e.left), self.expr(e.right)
        if op == "AND":
            return lambda fr: a(fr) and b(fr)
        if op == "OR":
            return lambda fr: a(fr) or b(fr)
        if op in _COMPARE:
            cmp = _COMPARE[op]
            return lambda fr: cmp(a(fr), b(fr))
        if T.is_frame(ta):
            return lambda fr: a(fr).apply(b(fr))
        if op in ("/", "DIV", "MOD"):
            return self._division(op, a, b, e)
        if e.type == T.INTEGER:
            return self._integer_arithmetic(e, a, b)
        if e.type == T.STRING:
            return self._concatenation(a, b, e.op_span)
        if op == "+":
            return lambda fr: a(fr) + b(fr)
        if op == "-":
            return lambda fr: a(fr) - b(fr)
        return lambda fr: a(fr) * b(fr)

    def _frame_product(self, e: A.BinOp) -> Callable:
        """A chain of frame products, A * B * C ..., as one closure over the matrices: no Frame
        is made for the partial products (the checker proved every factor a FRAME)."""
        factors: list[A.Expr] = []

        def flatten(x: A.Expr) -> None:
            if isinstance(x, A.BinOp) and x.op == "*" and T.is_frame(x.left.type) and T.is_frame(x.right.type):
                flatten(x.left)
                flatten(x.right)
            else:
                factors.append(x)
        flatten(e)
        fs = [self.expr(x) for x in factors]
        trusted = Frame.trusted
        if len(fs) == 2:
            a, b = fs
            return lambda fr: trusted(a(fr).matrix @ b(fr).matrix)
        if len(fs) == 3:
            a, b, c = fs
            return lambda fr: trusted(a(fr).matrix @ b(fr).matrix @ c(fr).matrix)
        if len(fs) == 4:
            a, b, c, d = fs
            return lambda fr: trusted(a(fr).matrix @ b(fr).matrix @ c(fr).matrix @ d(fr).matrix)
        first, *rest = fs

        def run(fr):
            m = first(fr).matrix
            for f in rest:
                m = m @ f(fr).matrix
            return trusted(m)
        return run

    def _integer_arithmetic(self, e: A.BinOp, a: Callable, b: Callable) -> Callable:
        """+ - * on INTEGERs, each written out: this is the inner loop of most programs."""
        make, op = self._raiser(), e.op

        def overflow():
            return make("INTEGER overflow (beyond 64 bits)", e.op_span)
        i, j = self._frame_slot(e.left), self._frame_slot(e.right)
        if i is not None and j is not None:
            return self._slots_arithmetic(op, i, j, a, b, overflow)
        if i is not None and isinstance(e.right, A.Integer):
            return self._slot_literal_arithmetic(op, i, int(e.right.text), a, overflow)
        if op == "+":
            def run(fr):
                x = a(fr) + b(fr)
                if INT_MIN <= x <= INT_MAX:
                    return x
                raise overflow()
        elif op == "-":
            def run(fr):
                x = a(fr) - b(fr)
                if INT_MIN <= x <= INT_MAX:
                    return x
                raise overflow()
        else:
            def run(fr):
                x = a(fr) * b(fr)
                if INT_MIN <= x <= INT_MAX:
                    return x
                raise overflow()
        return run

    # Two variables of the activation, or one and a literal, read in place (no call for each
    # operand). A variable with no value yet holds None, which makes the operation a TypeError:
    # the operands' own readers then say which one it is. Written out for speed, as above.

    @staticmethod
    def _slots_arithmetic(op: str, i: int, j: int, a: Callable, b: Callable, overflow: Callable) -> Callable:
        if op == "+":
            def run(fr):
                try:
                    x = fr[i] + fr[j]
                except TypeError:
                    _raise_unset(fr, a, b)
                if INT_MIN <= x <= INT_MAX:
                    return x
                raise overflow()
        elif op == "-":
            def run(fr):
                try:
                    x = fr[i] - fr[j]
                except TypeError:
                    _raise_unset(fr, a, b)
                if INT_MIN <= x <= INT_MAX:
                    return x
                raise overflow()
        else:
            def run(fr):
                try:
                    x = fr[i] * fr[j]
                except TypeError:
                    _raise_unset(fr, a, b)
                if INT_MIN <= x <= INT_MAX:
                    return x
                raise overflow()
        return run

    @staticmethod
    def _slot_literal_arithmetic(op: str, i: int, k: int, a: Callable, overflow: Callable) -> Callable:
        if op == "+":
            def run(fr):
                try:
                    x = fr[i] + k
                except TypeError:
                    _raise_unset(fr, a)
                if INT_MIN <= x <= INT_MAX:
                    return x
                raise overflow()
        elif op == "-":
            def run(fr):
                try:
                    x = fr[i] - k
                except TypeError:
                    _raise_unset(fr, a)
                if INT_MIN <= x <= INT_MAX:
                    return x
                raise overflow()
        else:
            def run(fr):
                try:
                    x = fr[i] * k
                except TypeError:
                    _raise_unset(fr, a)
                if INT_MIN <= x <= INT_MAX:
                    return x
                raise overflow()
        return run

    def _frame_slot(self, e: A.Expr) -> int | None:
        """The slot of a variable read straight from the activation, else None."""
        if isinstance(e, A.Name) and isinstance(e.symbol, Variable) and e.symbol.kind != "const" \
                and self._in_frame(e.symbol):
            return e.symbol.slot
        return None

    def _concatenation(self, a: Callable, b: Callable, span: A.Span) -> Callable:
        """STRING + STRING, at most MAX_STRING characters (a doubling loop ends in an error, not in
        all the memory there is)."""
        make = self._raiser()

        def run(fr):
            x, y = a(fr), b(fr)
            if len(x) + len(y) > MAX_STRING:
                raise make(f"string too long: {len(x) + len(y):,} characters (at most {MAX_STRING:,})", span)
            return x + y
        return run

    def _division(self, op: str, a: Callable, b: Callable, e: A.BinOp) -> Callable:
        make, span = self._raiser(), e.op_span
        if op == "/":
            def run(fr):
                x, y = a(fr), b(fr)
                if y == 0:
                    raise make("division by zero", span)
                return x / y
            return run

        whole = T.int_div if op == "DIV" else T.int_mod

        def run_whole(fr):
            x, y = a(fr), b(fr)
            if y == 0:
                raise make("division by zero", span)
            return whole(x, y)
        return self._checked(run_whole, span) if op == "DIV" else run_whole


def _raise_unset(fr: list, *readers: Callable) -> NoReturn:
    """Raise the error of the first operand with no value yet: its reader's."""
    for read in readers:
        read(fr)
    raise AssertionError("an INTEGER operation failed with every operand set")  # the checker proved the types
