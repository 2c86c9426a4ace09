"""Transform equations: isolate the unknown of ``lhs = rhs`` algebraically.

Each side is a product of frame terms. If the unknown X is the k-th factor
of ``F1 * ... * Fn = R`` then ``X = INV(F1 ... Fk-1) * R * INV(Fk+1 ... Fn)``;
if the factor is ``INV(G)`` the same is done for ``G = INV(that)``. The
result is an ordinary expression, so SOLVE costs what the written-out
product costs and is exact (no numerical search).
"""
from __future__ import annotations

from . import ast as A


class SolveError(Exception):
    """Why an equation cannot be solved for its unknown (message, span)."""

    def __init__(self, message: str, span: A.Span) -> None:
        super().__init__(message)
        self.span = span


def factors(e: A.Expr) -> list[A.Expr]:
    """The factors of a product, left to right."""
    if isinstance(e, A.BinOp) and e.op == "*":
        return factors(e.left) + factors(e.right)
    return [e]


def occurrences(e: A.Expr, key: str) -> int:
    """How often the name key occurs anywhere inside e."""
    if isinstance(e, A.Name):
        return int(e.ident.key == key)
    if isinstance(e, A.BinOp):
        return occurrences(e.left, key) + occurrences(e.right, key)
    if isinstance(e, A.UnOp):
        return occurrences(e.operand, key)
    if isinstance(e, A.Call):
        return sum(occurrences(a, key) for a in e.args)
    if isinstance(e, A.Field):
        return occurrences(e.obj, key)
    if isinstance(e, A.Index):
        return occurrences(e.obj, key) + occurrences(e.index, key)
    return 0


def _inv(e: A.Expr, span: A.Span) -> A.Call:
    return A.Call(A.Ident("INV", span), [e], span=span)


def _product(terms: list[A.Expr], span: A.Span) -> A.Expr:
    out = terms[0]
    for t in terms[1:]:
        out = A.BinOp("*", out, t, span=span, op_span=span)
    return out


def _is_inv(e: A.Expr) -> bool:
    return isinstance(e, A.Call) and e.callee.key == "inv" and len(e.args) == 1


def solve(lhs: A.Expr, rhs: A.Expr, unknown: A.Ident, span: A.Span) -> A.Expr:
    """An expression for the unknown; raises SolveError unless it occurs exactly once as a factor."""
    key = unknown.key
    count = occurrences(lhs, key) + occurrences(rhs, key)
    if count != 1:
        where = "does not appear" if count == 0 else f"appears {count} times"
        raise SolveError(f"the unknown {unknown.text} {where} in the equation; SOLVE needs it exactly once",
                         unknown.span)
    if occurrences(lhs, key) == 0:
        lhs, rhs = rhs, lhs
    return _isolate(factors(lhs), rhs, key, span)


def _isolate(terms: list[A.Expr], value: A.Expr, key: str, span: A.Span) -> A.Expr:
    k = next(i for i, t in enumerate(terms) if occurrences(t, key))
    if k > 0:
        value = A.BinOp("*", _inv(_product(terms[:k], span), span), value, span=span, op_span=span)
    if k < len(terms) - 1:
        value = A.BinOp("*", value, _inv(_product(terms[k + 1:], span), span), span=span, op_span=span)
    term = terms[k]
    if isinstance(term, A.Name):
        return value
    if isinstance(term, A.Call) and _is_inv(term):
        return _isolate(factors(term.args[0]), _inv(value, span), key, span)
    what = f"a call to {term.callee.text}" if isinstance(term, A.Call) else "an expression"
    raise SolveError(f"SOLVE can only undo products and INV, but the unknown is inside {what}", term.span)
