"""The checker's statements: each stmt_<Node> checks one kind of statement, declaring
implicitly typed variables at their first assignment (see base.CheckerBase._store).
"""
from __future__ import annotations

from .. import ast as A
from .. import types as T
from ..constants import NotConstant
from ..rules import article
from ..scope import Routine
from ..solve import SolveError, solve
from .base import CheckerBase


class Statements(CheckerBase):
    def block(self, block: A.Block, top: bool = False) -> None:
        for s in block.body:
            self.stmt(s, top)

    def stmt(self, s: A.Stmt, top: bool = False) -> None:
        getattr(self, "stmt_" + type(s).__name__)(s, top)

    def stmt_Assign(self, s: A.Assign, top: bool) -> None:
        value_type = self.value(s.value)
        target = s.target
        if isinstance(target, A.Name):
            target.symbol = self._store(target.ident, value_type, s.value.span, s)
            target.type = target.symbol.type if target.symbol and target.symbol.type else T.ANY
            return
        if isinstance(target, (A.Index, A.Field)):
            t = self.lvalue(target)
            if t is T.ANY or value_type is T.ANY:
                return
            if not T.assignable(t, value_type):
                self.error(s.value.span, f"cannot store {article(value_type)} where {article(t)} belongs")
                return
            problem = T.refs_conflict(t, value_type)
            if problem:
                self.error(s.value.span, problem)
            return
        self.error(target.span, "only a variable, an array element or a field can be assigned")

    def stmt_CallStmt(self, s: A.CallStmt, top: bool) -> None:
        c = s.call
        if isinstance(c, A.Call):
            self.call(c)
            return
        if isinstance(c, A.Name):
            v = self.lookup(c.ident.key)
            if v is not None:
                self.error(c.span, f"{v.name} is a variable; a statement cannot be just a value")
                return
            self.call(A.Call(c.ident, [], span=c.span), bare=c)
            return
        self.expr(c)
        self.error(c.span, "this is a value, not a statement; assign it with := or call a procedure")

    def stmt_If(self, s: A.If, top: bool) -> None:
        for cond, body in s.branches:
            self.condition(cond, "IF")
            self.block(body)
        if s.otherwise is not None:
            self.block(s.otherwise)

    def stmt_While(self, s: A.While, top: bool) -> None:
        self.condition(s.cond, "WHILE")
        self.block(s.body)

    def stmt_Repeat(self, s: A.Repeat, top: bool) -> None:
        self.block(s.body)
        self.condition(s.cond, "UNTIL")

    def condition(self, e: A.Expr, keyword: str) -> None:
        t = self.value(e)
        if t is not T.ANY and t != T.BOOLEAN:
            self.error(e.span, f"the condition of {keyword} must be BOOLEAN, not {t}")

    def stmt_For(self, s: A.For, top: bool) -> None:
        for part, what in ((s.start, "start"), (s.stop, "limit"), (s.step, "step")):
            if part is None:
                continue
            t = self.value(part)
            if t is not T.ANY and t != T.INTEGER:
                self.error(part.span, f"the {what} of a FOR loop must be an INTEGER, not {t}")
        if s.step is not None:
            try:
                step, _ = self.const_value(s.step)
                if isinstance(step, int) and step <= 0:
                    self.error(s.step.span, f"a FOR step must be positive (count down with DOWNTO), not {step}")
            except NotConstant:
                pass
        s.symbol = self._store(s.var, T.INTEGER, s.var.span, s)
        if s.symbol is not None and s.symbol.type not in (None, T.INTEGER):
            self.error(s.var.span, f"the FOR variable {s.symbol.name} must be an INTEGER, "
                                   f"but it is {s.symbol.type}")
        self.block(s.body)

    def stmt_Return(self, s: A.Return, top: bool) -> None:
        r = self.routine
        if r is None:
            if s.value is not None:
                self.value(s.value)
                self.error(s.value.span, "RETURN outside a function gives no value")
            return
        s.result_type = r.result
        if r.result is None:
            if s.value is not None:
                self.value(s.value)
                self.error(s.value.span, f"procedure {r.name} gives no value; use a FUNCTION to return one")
            return
        if s.value is None:
            self.error(s.span, f"function {r.name} must RETURN {article(r.result)}")
            return
        t = self.value(s.value)
        if not T.assignable(r.result, t):
            self.error(s.value.span, f"function {r.name} returns {r.result}, not {t}")
            return
        problem = T.refs_conflict(r.result, t)
        if problem:
            self.error(s.value.span, f"function {r.name}: {problem}")

    def stmt_Try(self, s: A.Try, top: bool) -> None:
        self.block(s.body)
        self.block(s.handler)

    def stmt_Raise(self, s: A.Raise, top: bool) -> None:
        t = self.value(s.message)
        if t is not T.ANY and t != T.STRING:
            self.error(s.message.span, f"RAISE takes a STRING message, not {t}")

    def stmt_Solve(self, s: A.Solve, top: bool) -> None:
        v = self.lookup(s.unknown.key)
        if v is None:
            v = self._declare(s.unknown, T.FRAME, s)  # the grammar makes the unknown a frame name
        try:
            solution = solve(s.lhs, s.rhs, s.unknown, s.span)
        except SolveError as e:
            self.expr(s.lhs)
            self.expr(s.rhs)
            self.error(e.span, str(e))
            return
        sides = []
        for side in (s.lhs, s.rhs):
            t = self.value(side)
            if t is not T.ANY and not T.is_frame(t):
                self.error(side.span, f"each side of SOLVE must be a product of frames, not a {t}")
                return
            sides.append(t)
        left, right = sides
        if T.is_frame(left) and T.is_frame(right):
            for end, a, b in (("start", left.src, right.src), ("end", left.dst, right.dst)):
                if a is not None and b is not None and a != b:
                    self.error(s.span, f"the two sides of SOLVE {end} at different frames: "
                                       f"{a!r} on the left, {b!r} on the right")
        self.reporting, saved = False, self.reporting
        try:
            t = self.value(solution)  # derived from the sides: their errors are already reported
        finally:
            self.reporting = saved
        s.solution, s.symbol = solution, v
        if v.kind == "const":
            self.error(s.unknown.span, f"{v.name} is a constant; it cannot be assigned")
        else:
            self._store_into(v, t, s.unknown.span)

    def stmt_Import(self, s: A.Import, top: bool) -> None:
        if not top:
            self.error(s.span, "IMPORT belongs at the top level of a file")
            return
        m = s.module
        if m is not None and id(m) not in self._visited:
            self._visited.add(id(m))
            self._in_module(m, lambda: self.block(m.body, top=True))

    def stmt_VarDecl(self, s: A.VarDecl, top: bool) -> None:
        symbols = []
        for ident in s.names:
            t = self.declared_type(ident, s.type, f"{ident.text} needs a type, as in VAR {ident.text} : REAL "
                                                  f"(only frame names may omit it)")
            existing = self.lookup(ident.key)
            local_scope = self.routine is None or (existing is not None and not existing.is_global)
            if existing is not None and local_scope and existing.origin is not s:
                if (self.routine is None and ident.key in self.prior and existing.declared
                        and existing.type == t):
                    symbols.append(existing)  # declared the same way in an earlier run of the session
                    continue
                where = f" at line {existing.span.line}" if existing.span and existing.filename == self.module.filename else ""
                self.error(ident.span, f"{ident.text} is already declared{where}")
                symbols.append(existing)
                continue
            if existing is not None and existing.origin is s:
                symbols.append(existing)
                continue
            symbols.append(self._declare(ident, None if t is T.ANY else t, s, declared=True))
        s.symbols = symbols

    def stmt_ConstDecl(self, s: A.ConstDecl, top: bool) -> None:
        existing = self.lookup(s.name.key)
        if existing is not None and existing.origin is s:
            s.symbol = existing
            self.value(s.value)
            return
        try:
            value, t = self.const_value(s.value)
        except NotConstant:
            self.value(s.value)
            self.error(s.value.span, "a CONST must be a constant expression of numbers, strings or BOOLEANs")
            value, t = None, T.ANY
        if existing is not None and not (self.routine is not None and existing.is_global):
            if not (existing.kind == "const" and s.name.key in self.prior and existing.value == value):
                self.error(s.name.span, f"{s.name.text} is already declared")
                return
        self.value(s.value)
        s.symbol = self._declare(s.name, t, s, kind="const", declared=True, value=value)

    def stmt_RoutineDecl(self, s: A.RoutineDecl, top: bool) -> None:
        if not top:
            self.error(s.span, "PROCEDURE and FUNCTION are declared at the top level of a file only")

    def _check_routine(self, r: Routine, modules) -> None:
        self.routine = r
        try:
            self._in_module(r.module, lambda: self.block(r.decl.body))
        finally:
            self.routine = None

