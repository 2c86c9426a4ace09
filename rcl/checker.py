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
"""
from __future__ import annotations

import difflib
from collections.abc import Callable

from . import ast as A
from . import foreign
from . import types as T
from .constants import NotConstant, fold
from .errors import Diagnostic, source_line
from .rules import ORDERING, article, binop_type
from .scope import GlobalScope, ParamInfo, Routine, Variable
from .solve import SolveError, solve

MAX_PASSES = 64
MAX_ARRAY_ELEMENTS = 10_000_000
MAX_SUGGESTIONS = 20  # unknown names per pass of the checker that get a "did you mean"


class Checker:
    """Checks new modules against a (forked) session scope."""

    def __init__(self, scope: GlobalScope) -> None:
        self.scope = scope
        self.prior = set(scope.variables)  # globals from earlier runs of the session
        self.errors: list[Diagnostic] = []
        self.module: A.Module | None = None
        self.routine: Routine | None = None
        self.new_routines: list[Routine] = []
        self.changed = False
        self.reporting = True
        self._visited: set[int] = set()
        self._suggested = 0  # unknown names given a suggestion in this pass (MAX_SUGGESTIONS)

    # Entry point ---------------------------------------------------------

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
                    self._in_module(m, lambda m=m: self.block(m.body, top=True))
            for r in self.new_routines:
                self._check_routine(r, modules)
            if not self.changed:
                break
        found = {(d.filename, d.span, d.message): d for d in declaration_errors + self.errors}
        file_rank = {m.filename: order[id(m)] for m in modules}
        return sorted(found.values(), key=lambda d: (file_rank.get(d.filename, 0), d.span.line, d.span.col))

    def check_expression(self, e: A.Expr, module: A.Module) -> tuple[T.Type | None, list[Diagnostic]]:
        """The type of one expression in the session's scope (None for a procedure call), and its errors."""
        self.module = module
        self.errors = []
        t = self.expr(e)
        return t, self.errors

    def _in_module(self, module: A.Module, action) -> None:
        saved = self.module
        self.module = module
        try:
            action()
        finally:
            self.module = saved

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

    # Declarations --------------------------------------------------------

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
            if decl.result is not None:
                result = self.resolve_type(decl.result)
            elif name.is_frame:
                result = T.FRAME
            else:
                self.error(name.span, f"function {name.text} needs a result type, as in "
                                      f"FUNCTION {name.text}(...) : REAL")
                result = T.ANY
            if result is not T.ANY and T.contains_frame(result) != name.is_frame:
                self.error(name.span, self._frame_rule_message(name.text, result, "return"))
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
                t = self.resolve_type(p.type, allow_open=True)
                by_ref = False
                for q in pending:
                    by_ref = by_ref or q.by_ref  # VAR a, b : T makes both VAR
                    if t is not T.ANY and T.contains_frame(t) != q.name.is_frame:
                        self.error(q.name.span, self._frame_rule_message(q.name.text, t, "hold"))
                    out.append(ParamInfo(q.name.text, t, by_ref))
                pending = []
            for q in pending:
                self.error(q.name.span, f"parameter {q.name.text} needs a type, as in "
                                        f"{q.name.text} : REAL (only frame names may omit it)")
                out.append(ParamInfo(q.name.text, T.ANY, q.by_ref))
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
        element = self.resolve_type(texpr.element)
        if texpr.low is None:
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
                t = T.FRAME if ident.is_frame else None
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

    # Statements ----------------------------------------------------------

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

    def lvalue(self, e: A.Expr) -> T.Type:
        """The type of an assignable place (a variable, element or field of one)."""
        if isinstance(e, A.Name):
            v = self.lookup(e.ident.key)
            if v is None:
                self.error(e.span, f"unknown name {e.ident.text}{self._suggest(e.ident.key, self._visible_names)}")
                return T.ANY
            if v.kind == "const":
                self.error(e.span, f"{v.name} is a constant; it cannot be assigned")
            e.symbol = v
            e.type = v.type or T.ANY
            return e.type
        if isinstance(e, A.Index):
            t = self.lvalue(e.obj)
            return self._index_type(e, t)
        if isinstance(e, A.Field):
            t = self.lvalue(e.obj)
            field = e.name.key
            if t is T.ANY:
                e.type = T.ANY
            elif t == T.VECTOR and field in ("x", "y", "z"):
                e.type = T.REAL
            elif T.is_frame(t) and field == "p":
                e.type = T.VECTOR
            elif T.is_frame(t) and field in ("n", "o", "a"):
                self.error(e.name.span, "only .P of a frame can be assigned; build rotations "
                                        "with ROT, RPY or FRAME")
                e.type = T.ANY
            else:
                e.type = self._field_type(e, t)
            return e.type
        self.error(e.span, "only a variable, an array element or a field can be assigned")
        return T.ANY

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
            if s.type is not None:
                t = self.resolve_type(s.type)
            elif ident.is_frame:
                t = T.FRAME
            else:
                self.error(ident.span, f"{ident.text} needs a type, as in VAR {ident.text} : REAL "
                                       f"(only frame names may omit it)")
                t = T.ANY
            if t is not T.ANY and T.contains_frame(t) != ident.is_frame:
                self.error(ident.span, self._frame_rule_message(ident.text, t, "hold"))
                t = T.ANY
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

    # Expressions ---------------------------------------------------------

    def value(self, e: A.Expr) -> T.Type:
        """The type of an expression used as a value (a procedure call gives none)."""
        t = self.expr(e)
        if t is None:
            self.error(e.span, "this procedure call gives no value")
            e.type = T.ANY
            return T.ANY
        return t

    def expr(self, e: A.Expr) -> T.Type | None:
        t = getattr(self, "expr_" + type(e).__name__)(e)
        e.type = t
        return t

    def expr_Integer(self, e: A.Integer) -> T.Type:
        if len(e.text) > 19 or int(e.text) > T.INT_MAX:
            self.error(e.span, f"integer {e.text[:30]}{'...' if len(e.text) > 30 else ''} is too large "
                               f"(an INTEGER is at most {T.INT_MAX}); write it as a REAL")
        return T.INTEGER

    def expr_Real(self, e: A.Real) -> T.Type:
        if float(e.text) == float("inf"):
            self.error(e.span, f"number {e.text} is too large for a REAL")
        return T.REAL

    def expr_String(self, e: A.String) -> T.Type:
        return T.STRING

    def expr_Boolean(self, e: A.Boolean) -> T.Type:
        return T.BOOLEAN

    def expr_Name(self, e: A.Name) -> T.Type | None:
        v = self.lookup(e.ident.key)
        if v is not None:
            e.symbol = v
            return v.type or T.ANY
        key = e.ident.key
        if key in self.scope.routines or key in self.scope.builtins:
            call = A.Call(e.ident, [], span=e.span)
            t = self.call(call)
            e.symbol = call.symbol
            return t
        self.error(e.span, f"unknown name {e.ident.text}{self._suggest(key, self._visible_names)}")
        return T.ANY

    def expr_Field(self, e: A.Field) -> T.Type:
        return self._field_type(e, self.value(e.obj))

    def _field_type(self, e: A.Field, t: T.Type) -> T.Type:
        field = e.name.key
        if t is T.ANY:
            return T.ANY
        if T.is_frame(t):
            if field in ("n", "o", "a", "p"):
                return T.VECTOR
            self.error(e.name.span, f"a FRAME has fields .N .O .A .P, not .{e.name.text}")
            return T.ANY
        if t == T.VECTOR:
            if field in ("x", "y", "z"):
                return T.REAL
            self.error(e.name.span, f"a VECTOR has fields .X .Y .Z, not .{e.name.text}")
            return T.ANY
        self.error(e.name.span, f"{article(t)} has no fields")
        return T.ANY

    def expr_Index(self, e: A.Index) -> T.Type:
        return self._index_type(e, self.value(e.obj))

    def _index_type(self, e: A.Index, t: T.Type) -> T.Type:
        it = self.value(e.index)
        if it is not T.ANY and it != T.INTEGER:
            self.error(e.index.span, f"an array index must be an INTEGER, not {it}")
        if t is T.ANY:
            e.type = T.ANY
            return T.ANY
        if not isinstance(t, T.ArrayType):
            self.error(e.span, f"only arrays can be indexed, not {article(t)}")
            e.type = T.ANY
            return T.ANY
        e.type = t.element
        return t.element

    def expr_Call(self, e: A.Call) -> T.Type | None:
        return self.call(e)

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
        if target.name == "INV" and arg_types and T.is_frame(arg_types[0]):
            return T.inverse(arg_types[0])  # INV([a->b]) : [b->a]
        return target.result_for(arg_types)

    def _var_argument(self, a: A.Expr, p, routine: str, position: int) -> T.Type:
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

    def expr_UnOp(self, e: A.UnOp) -> T.Type:
        t = self.value(e.operand)
        if t is T.ANY:
            return T.ANY
        if e.op == "NOT":
            if t == T.BOOLEAN:
                return T.BOOLEAN
            self.error(e.span, f"NOT needs a BOOLEAN, not {article(t)}")
            return T.ANY
        if T.is_numeric(t) or (e.op == "-" and t == T.VECTOR):
            return t
        if T.is_frame(t):
            name = e.operand.ident.text if isinstance(e.operand, A.Name) else "..."
            self.error(e.span, f"a FRAME cannot be negated; use INV({name}) for the inverse")
        else:
            self.error(e.span, f"unary {e.op} needs a number, not {article(t)}")
        return T.ANY

    def expr_BinOp(self, e: A.BinOp) -> T.Type:
        op = e.op
        a = self.value(e.left)
        b = self.value(e.right)
        if a is T.ANY or b is T.ANY:
            return T.BOOLEAN if op in ORDERING or op in ("=", "<>", "AND", "OR") else T.ANY
        result = binop_type(op, a, b)
        if isinstance(result, T.Type):
            if T.is_frame(result) and T.is_frame(a) and T.is_frame(b):
                composed, problem = T.compose(a, b)
                if problem:
                    self.error(e.op_span, problem)
                return composed
            return result
        self.error(e.op_span, result)
        return T.ANY


def p_span(decl: A.RoutineDecl, name: str) -> A.Span:
    """Where parameter name is written in decl."""
    for group in decl.params:
        for p in group:
            if p.name.text == name:
                return p.name.span
    return decl.span
