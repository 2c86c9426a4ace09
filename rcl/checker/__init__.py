"""The static checker: every error in a program, with its position, before anything runs.

It resolves names (Pascal scoping: globals, then a routine's parameters and
locals), infers the type of each implicitly declared variable from its first
assignment, and checks the type of every expression and call, the frame rule
(names ending in ^ hold FRAMEs, others never), BOOLEAN conditions, VAR
arguments, RETURN, frame references and SOLVE. It annotates the AST with
types and symbols for the interpreter.

Types are inferred by passes over the whole program, repeated until no
variable's type changes (INTEGER may widen to REAL); the errors of that last,
stable pass are the program's errors.

One module a job, one class built from them:
    base.py         shared state, reporting, names and the frame rule where a name gets a type
    signatures.py   routine headings, written types, constant array bounds
    statements.py   stmt_<Node>
    expressions.py  expr_<Node>
    calls.py        calls and their arguments
"""
from __future__ import annotations

import functools

from .. import ast as A
from .. import types as T
from ..errors import Diagnostic
from .base import MAX_SUGGESTIONS
from .calls import Calls
from .expressions import Expressions
from .signatures import Signatures
from .statements import Statements

__all__ = ["Checker", "MAX_SUGGESTIONS"]

MAX_PASSES = 64


class Checker(Signatures, Statements, Expressions, Calls):
    """Checks new modules against a (forked) session scope."""

    def check(self, modules: list[A.Module]) -> list[Diagnostic]:
        """Check modules (imports first, the main program last); return the diagnostics."""
        order = {id(m): i for i, m in enumerate(modules)}
        self.errors = []
        for m in modules:
            self._in_module(m, self._declare_routines)
        declaration_errors = self.errors
        for _ in range(MAX_PASSES):
            self.errors = []
            self._suggested = 0  # each pass reports afresh; the last one's errors are kept
            self.changed = False
            self._visited = set()
            for m in modules:
                if id(m) not in self._visited:
                    self._visited.add(id(m))
                    self._in_module(m, functools.partial(self.block, m.body, top=True))
            for r in self.new_routines:
                self._check_routine(r, modules)
            if not self.changed:
                break
        found = {(d.filename, d.span, d.message): d for d in declaration_errors + self.errors}
        file_rank = {m.filename: order[id(m)] for m in modules}
        return sorted(found.values(), key=lambda d: (file_rank.get(d.filename, 0), d.span.line, d.span.col))

    def check_expression(self, e: A.Expr, module: A.Module) -> tuple[T.Type | None, list[Diagnostic]]:
        """The type of one expression in the session's scope (None for a procedure call), and its errors."""
        self._module = module
        self.errors = []
        t = self.expr(e)
        return t, self.errors

