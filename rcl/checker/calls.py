"""The checker's calls: a call's routine, its arguments against the parameters (VAR
arguments must be variables of exactly the type), and its result type.
"""
from __future__ import annotations

from .. import ast as A
from .. import foreign
from .. import types as T
from ..rules import article
from ..scope import ParamInfo, Routine
from .base import CheckerBase


class Calls(CheckerBase):
    def call(self, e: A.Call, bare: A.Name | None = None) -> T.Type | None:
        key = e.callee.key
        target = self.scope.routines.get(key) or self.scope.builtins.get(key)
        if target is None:
            for a in e.args:
                self.expr(a)
            hint = foreign.hint(key) or self._suggest(key, self._routine_names)
            self.error(e.callee.span, f"unknown routine {e.callee.text}{hint}")
            return T.ANY
        e.symbol = target
        if bare is not None:
            bare.symbol = target
        params = list(target.params)
        variadic = getattr(target, "variadic", None)
        n = len(e.args)
        if n < len(params) or (n > len(params) and variadic is None):
            want = f"{len(params)}" + (" or more" if variadic is not None else "")
            plural = "" if want == "1" else "s"
            self.error(e.span, f"{target.name} takes {want} argument{plural}, not {n}")
            for a in e.args:
                self.expr(a)
            return self._result(target, [T.ANY] * n)
        arg_types = []
        for i, a in enumerate(e.args):
            if i < len(params):
                p = params[i]
                if p.by_ref:
                    arg_types.append(self._var_argument(a, p, target.name, i + 1))
                    continue
                want = p.type
            else:
                assert variadic is not None  # more arguments than parameters: refused above without one
                want = variadic
            t = self.value(a)
            arg_types.append(t)
            if t is T.ANY:
                continue
            if not T.assignable(want, t):
                self.error(a.span, f"argument {i + 1} of {target.name} must be {article(want)}, not {article(t)}")
                continue
            problem = T.refs_conflict(want, t)
            if problem:
                self.error(a.span, f"argument {i + 1} of {target.name}: {problem}")
        return self._result(target, arg_types)

    @staticmethod
    def _result(target, arg_types) -> T.Type | None:
        if isinstance(target, Routine):
            return target.result
        return target.result_for(arg_types)

    def _var_argument(self, a: A.Expr, p: ParamInfo, routine: str, position: int) -> T.Type:
        """A VAR argument: a variable (declared here if new) or an element of one, of exactly the type."""
        if isinstance(a, A.Name) and self.lookup(a.ident.key) is None:
            if isinstance(p.type, T.ArrayType):
                self.error(a.span, f"unknown name {a.ident.text}: declare the array first, as in "
                                   f"VAR {a.ident.text} : ARRAY [1..5] OF {p.type.element}")
                return T.ANY
            a.symbol = self._store(a.ident, p.type if not T.is_frame(p.type) else T.FRAME, a.span, a)
            a.type = a.symbol.type if a.symbol and a.symbol.type else T.ANY
            return a.type
        if not isinstance(a, (A.Name, A.Index)):
            self.expr(a)
            self.error(a.span, f"argument {position} of {routine} is a VAR parameter: pass a variable")
            return T.ANY
        t = self.lvalue(a)
        if isinstance(a, A.Name) and a.symbol is not None and a.symbol.kind == "const":
            return T.ANY
        if t is T.ANY or p.type is T.ANY:
            return t
        if T.is_frame(p.type) and T.is_frame(t):
            problem = T.refs_conflict(p.type, t)
            if problem:
                self.error(a.span, f"argument {position} of {routine}: {problem}")
            return t
        exact = T.same_shape(p.type, t) or (
            isinstance(p.type, T.ArrayType) and p.type.is_open and isinstance(t, T.ArrayType)
            and T.same_shape(p.type.element, t.element))
        if not exact:
            self.error(a.span, f"argument {position} of {routine} is a VAR {p.type}; "
                               f"{article(t)} variable cannot be passed")
        return t
