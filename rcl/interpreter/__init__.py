"""The interpreter: walks the checked AST once, turning each node into a Python closure, then runs them.

Each ``expr_<Node>`` method gives a closure ``f(fr) -> value`` and each
``stmt_<Node>`` a closure ``f(fr) -> None | RETURN``, where ``fr`` is the
activation (a list of the running routine's slots). The checker has already
proved every type, so the closures do no type tests: they only do what the
static types say (INTEGER + INTEGER is a checked 64-bit add, FRAME * FRAME a
matrix product, ...) and the checks only run time can make (division by
zero, array bounds, unassigned variables, recursion depth, cancellation).
"""
from __future__ import annotations

from collections.abc import Callable
from typing import Any

from .. import ast as A
from .. import types as T
from ..scope import Routine
from ..values import default_factory
from .base import MAX_LIVE_ELEMENTS, RETURN
from .calls import Calls
from .expressions import Expressions
from .operators import Operators
from .statements import Statements

__all__ = ["MAX_LIVE_ELEMENTS", "RETURN", "Compiler"]


class Compiler(Statements, Expressions, Operators, Calls):
    """Turns checked modules and routines into closures over one session's storage."""

    def module_code(self, m: A.Module) -> Callable[[], None]:
        self._module, self.routine = m, None
        body, top = self.block(m.body), self.values  # top-level code's activation is the globals
        return lambda: body(top)

    def expression_code(self, e: A.Expr, m: A.Module) -> Callable[[], Any]:
        """A checked top-level expression (the REPL's), ready to evaluate."""
        self._module, self.routine = m, None
        f, top = self.expr(e), self.values
        return lambda: f(top)

    def routine_code(self, r: Routine, m: A.Module) -> None:
        self._module, self.routine = m, r
        body = self.block(r.decl.body)
        template: list = [None] * r.frame_size
        fresh = []
        elements = 0  # in the local arrays each call makes
        for v in r.locals.values():
            if v.kind == "var" and v.declared and v.type is not None:
                make = default_factory(v.type)
                if isinstance(v.type, T.ArrayType):
                    fresh.append((v.slot, make))
                    elements += T.element_count(v.type)
                else:
                    template[v.slot] = make()
        r.code = (body, template, tuple(fresh), elements)

