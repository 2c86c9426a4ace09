"""The checker's shared state, its reporting, and name resolution (Pascal scoping: a
routine's parameters and locals, then the globals), with the frame rule at each
place a name gets a type.

The other parts (signatures, statements, expressions, calls) each extend
CheckerBase; the methods at the end are the entry points they call in one another.
"""
from __future__ import annotations

import difflib
from collections.abc import Callable

from .. import ast as A
from .. import types as T
from ..errors import Diagnostic, source_line
from ..scope import GlobalScope, Routine, Variable

MAX_SUGGESTIONS = 20  # unknown names per pass of the checker that get a "did you mean"


class CheckerBase:
    """What every part of the checker shares: the scope being filled, the errors, where it is."""

    def __init__(self, scope: GlobalScope) -> None:
        self.scope = scope
        self.prior = set(scope.variables)  # globals from earlier runs of the session
        self.errors: list[Diagnostic] = []
        self._module: A.Module | None = None
        self.routine: Routine | None = None
        self.new_routines: list[Routine] = []
        self.changed = False
        self.reporting = True
        self._visited: set[int] = set()
        self._suggested = 0  # unknown names given a suggestion in this pass (MAX_SUGGESTIONS)

    @property
    def module(self) -> A.Module:
        """The module being checked (set by _in_module around every walk)."""
        assert self._module is not None
        return self._module

    def _in_module(self, module: A.Module, action: Callable[[], None]) -> None:
        saved = self._module
        self._module = module
        try:
            action()
        finally:
            self._module = saved

    # Reporting -----------------------------------------------------------

    def error(self, span: A.Span, message: str) -> None:
        if self.reporting:
            self.errors.append(Diagnostic(self.module.filename, span, message,
                                          source_line(self.module.source, span.line)))

    def _suggest(self, key: str, candidates: dict[str, str] | Callable[[], dict[str, str]]) -> str:
        """'; did you mean NAME?' for a near name, for the first MAX_SUGGESTIONS unknown names of a
        pass (each search compares with every name: thousands of unknown names in a big file
        must not cost quadratic time)."""
        self._suggested += 1
        if self._suggested > MAX_SUGGESTIONS:
            return ""
        if callable(candidates):
            candidates = candidates()
        close = difflib.get_close_matches(key, list(candidates), n=1, cutoff=0.75)
        return f"; did you mean {candidates[close[0]]}?" if close else ""

    def _visible_names(self) -> dict[str, str]:
        names = {k: v.name for k, v in self.scope.variables.items()}
        if self.routine is not None:
            names.update({k: v.name for k, v in self.routine.locals.items()})
        return names

    def _routine_names(self) -> dict[str, str]:
        names = {k: b.name for k, b in self.scope.builtins.items()}
        names.update({k: r.name for k, r in self.scope.routines.items()})
        return names

    # Names ---------------------------------------------------------------

    def lookup(self, key: str) -> Variable | None:
        if self.routine is not None:
            v = self.routine.locals.get(key)
            if v is not None:
                return v
        return self.scope.variables.get(key)

    def _declare(self, ident: A.Ident, t: T.Type | None, origin, **kw) -> Variable:
        """A new variable in the current scope (a routine's locals, else the globals)."""
        self.changed = True
        if self.routine is not None:
            v = Variable(ident.text, t, False, len(self.routine.locals), filename=self.module.filename,
                         span=ident.span, origin=origin, **kw)
            self.routine.locals[ident.key] = v
            return v
        return self.scope.new_global(ident.text, t, filename=self.module.filename, span=ident.span,
                                     origin=origin, **kw)

    def declared_type(self, ident: A.Ident, texpr: A.TypeExpr | None, missing: str = "", verb: str = "hold",
                      allow_open: bool = False) -> T.Type:
        """The type a declaration gives ident (a variable, parameter or function): the type written,
        else FRAME for a frame name (only frame names may omit it); T.ANY, with the error
        reported, when it is missing or breaks the frame rule."""
        if texpr is None:
            if ident.is_frame:
                return T.FRAME
            self.error(ident.span, missing)
            return T.ANY
        t = self.resolve_type(texpr, allow_open)
        if t is not T.ANY and T.contains_frame(t) != ident.is_frame:
            self.error(ident.span, self._frame_rule_message(ident.text, t, verb))
            return T.ANY
        return t

    def _frame_rule_message(self, name: str, t: T.Type, verb: str) -> str:
        if name.endswith("^"):
            return f"frame name {name} can only {verb} a FRAME, not {t}"
        return (f"{name} is not a frame name, so it cannot {verb} a {t}; "
                f"frames live in names ending in ^, such as {name}^")

    def _store(self, ident: A.Ident, value_type: T.Type, span: A.Span, origin) -> Variable | None:
        """Check (and, the first time, declare) an assignment of value_type to a plain name."""
        v = self.lookup(ident.key)
        if v is None:
            if value_type is T.ANY:
                return None
            if value_type is None:
                self.error(span, "this call gives no value to assign")
                return None
            if T.contains_frame(value_type) != ident.is_frame:
                self.error(span, self._frame_rule_message(ident.text, value_type, "hold"))
                t: T.Type | None = T.FRAME if ident.is_frame else None
            else:
                t = T.FRAME if T.is_frame(value_type) else value_type  # implicit frames are unconstrained
            return self._declare(ident, t, origin)
        if v.kind == "const":
            self.error(span, f"{v.name} is a constant; it cannot be assigned")
            return v
        self._store_into(v, value_type, span)
        return v

    def _store_into(self, v: Variable, value_type: T.Type, span: A.Span) -> None:
        if value_type is T.ANY:
            return
        if value_type is None:
            self.error(span, "this call gives no value to assign")
            return
        if v.type is None:
            if T.contains_frame(value_type) != v.name.endswith("^"):
                self.error(span, self._frame_rule_message(v.name, value_type, "hold"))
                return
            v.type = T.FRAME if T.is_frame(value_type) else value_type
            self.changed = True
            return
        if not v.declared and v.type == T.INTEGER and value_type == T.REAL:
            v.type = T.REAL  # INTEGER then REAL: the variable is REAL
            self.changed = True
            return
        if T.assignable(v.type, value_type):
            problem = T.refs_conflict(v.type, value_type)
            if problem:
                self.error(span, f"{v.name}: {problem}")
            return
        if T.contains_frame(v.type) != T.contains_frame(value_type):
            self.error(span, self._frame_rule_message(v.name, value_type, "hold"))
        else:
            where = f" (declared at line {v.span.line})" if v.span and v.declared else ""
            self.error(span, f"{v.name} is {v.type}{where}; it cannot hold a {value_type}")

    # The parts' entry points, defined in signatures.py, statements.py, expressions.py, calls.py

    def resolve_type(self, texpr: A.TypeExpr, allow_open: bool = False) -> T.Type:
        raise NotImplementedError

    def const_value(self, e: A.Expr) -> tuple[object, T.Type]:
        raise NotImplementedError

    def block(self, block: A.Block, top: bool = False) -> None:
        raise NotImplementedError

    def stmt(self, s: A.Stmt, top: bool = False) -> None:
        raise NotImplementedError

    def lvalue(self, e: A.Expr) -> T.Type:
        raise NotImplementedError

    def value(self, e: A.Expr) -> T.Type:
        raise NotImplementedError

    def expr(self, e: A.Expr) -> T.Type | None:
        raise NotImplementedError

    def call(self, e: A.Call, bare: A.Name | None = None) -> T.Type | None:
        raise NotImplementedError
