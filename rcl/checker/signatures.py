"""The checker's first job: routine signatures and types as written.

Before any statement is checked, every PROCEDURE and FUNCTION of a module is
declared from its heading (the CONSTs first, since they may size arrays in a
signature), so calls may come before the routine in the file. resolve_type turns
a written type into a T.Type, evaluating array bounds as constant expressions.
"""
from __future__ import annotations

from .. import ast as A
from .. import types as T
from ..constants import NotConstant, fold
from ..scope import ParamInfo, Routine, Variable
from .base import CheckerBase

MAX_ARRAY_ELEMENTS = 10_000_000


class Signatures(CheckerBase):
    def _declare_routines(self) -> None:
        for stmt in self.module.body.body:
            if isinstance(stmt, A.ConstDecl):
                self.stmt(stmt)  # constants may size the arrays in signatures
            elif isinstance(stmt, A.RoutineDecl):
                self._declare_routine(stmt)

    def _declare_routine(self, decl: A.RoutineDecl) -> None:
        name = decl.name
        key = name.key
        if key in self.scope.builtins:
            self.error(name.span, f"{name.text} is a built-in routine; choose another name")
            return
        if decl.is_function:
            result = self.declared_type(name, decl.result, f"function {name.text} needs a result type, as in "
                                                           f"FUNCTION {name.text}(...) : REAL", "return")
        else:
            result = None
            if name.is_frame:
                self.error(name.span, f"procedure {name.text} gives no value, so its name cannot end in ^")
        params = self._resolve_params(decl)
        existing = self.scope.routines.get(key)
        if existing is not None and existing.decl is not decl:
            if existing in self.new_routines:
                where = (f"line {existing.decl.span.line}" if existing.module is self.module
                         else f"{existing.module.filename}:{existing.decl.span.line}")
                self.error(name.span, f"{existing.name} is already defined at {where}")
                return
            if ([(p.type, p.by_ref) for p in existing.params] != [(p.type, p.by_ref) for p in params]
                    or existing.result != result):
                self.error(name.span, f"{name.text} was defined earlier in this session with another "
                                      f"signature; it cannot change")
                return
        routine = Routine(name.text, params, result, decl, self.module)
        for i, p in enumerate(params):
            routine.locals[p.name.lower()] = Variable(
                p.name, p.type, False, i, kind="ref" if p.by_ref else "param", declared=True,
                filename=self.module.filename, span=p_span(decl, p.name))
        decl.symbol = routine
        self.scope.routines[key] = routine
        self.new_routines.append(routine)

    def _resolve_params(self, decl: A.RoutineDecl) -> list[ParamInfo]:
        out: list[ParamInfo] = []
        seen: set[str] = set()
        for group in decl.params:
            pending: list[A.Param] = []
            for p in group:
                if p.type is None and p.name.is_frame and not pending:
                    out.append(ParamInfo(p.name.text, T.FRAME, p.by_ref))
                    continue
                pending.append(p)
                if p.type is None:
                    continue
                by_ref = False
                for q in pending:
                    by_ref = by_ref or q.by_ref  # VAR a, b : T makes both VAR
                    out.append(ParamInfo(q.name.text, self.declared_type(q.name, p.type, allow_open=True), by_ref))
                pending = []
            for q in pending:
                t = self.declared_type(q.name, None, f"parameter {q.name.text} needs a type, as in "
                                                     f"{q.name.text} : REAL (only frame names may omit it)")
                out.append(ParamInfo(q.name.text, t, q.by_ref))
        for p in (p for g in decl.params for p in g):
            if p.name.key in seen:
                self.error(p.name.span, f"parameter {p.name.text} appears twice")
            seen.add(p.name.key)
        return out

    def resolve_type(self, texpr: A.TypeExpr, allow_open: bool = False) -> T.Type:
        if isinstance(texpr, A.FrameTypeExpr):
            if texpr.refs is None:
                return T.FRAME
            return T.FrameType(*texpr.refs)
        if isinstance(texpr, A.NamedType):
            t = T.NAMED.get(texpr.name.key)
            if t is None:
                names = {k: k.upper() for k in list(T.NAMED) + ["frame"]}
                self.error(texpr.span, f"unknown type {texpr.name.text}{self._suggest(texpr.name.key, names)}")
                return T.ANY
            return t
        assert isinstance(texpr, A.ArrayTypeExpr)
        element = self.resolve_type(texpr.element)
        if texpr.low is None or texpr.high is None:  # both or neither, as the grammar has it
            if not allow_open:
                self.error(texpr.span, "an array without bounds (ARRAY OF ...) is only for parameters")
                return T.ANY
            return T.ArrayType(element)
        low = self._constant_int(texpr.low)
        high = self._constant_int(texpr.high)
        if low is None or high is None:
            return T.ANY
        if high < low:
            self.error(texpr.span, f"array bounds [{low}..{high}] are empty (the high bound is below the low)")
            return T.ANY
        size = (high - low + 1) * T.element_count(element)
        if size > MAX_ARRAY_ELEMENTS:
            self.error(texpr.span, f"array of {size} elements is too large (at most {MAX_ARRAY_ELEMENTS})")
            return T.ANY
        if element is T.ANY:
            return T.ANY
        return T.ArrayType(element, low, high)

    def _constant_int(self, e: A.Expr) -> int | None:
        try:
            value, t = self.const_value(e)
        except NotConstant:
            self.error(e.span, "an array bound must be a constant INTEGER (a number or a CONST)")
            return None
        if t != T.INTEGER:
            self.error(e.span, f"an array bound must be an INTEGER, not {t}")
            return None
        return value

    def const_value(self, e: A.Expr):
        """(value, type) of a constant expression; raises NotConstant."""
        return fold(e, self._constant_symbol, self.expr, self.error)

    def _constant_symbol(self, e: A.Name):
        v = self.lookup(e.ident.key)
        if v is None or v.kind != "const":
            raise NotConstant
        e.symbol, e.type = v, v.type
        return v.value, v.type



def p_span(decl: A.RoutineDecl, name: str) -> A.Span:
    """Where parameter name is written in decl."""
    for group in decl.params:
        for p in group:
            if p.name.text == name:
                return p.name.span
    return decl.span
