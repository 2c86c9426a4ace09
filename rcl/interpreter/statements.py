"""The compiler's statements: each stmt_<Node> gives a closure f(fr) -> None | RETURN."""
from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from .. import ast as A
from .. import types as T
from ..builtins import Builtin
from ..errors import RclRuntimeError
from ..scope import Routine, Variable
from .base import POLL_TURNS, RETURN, CompilerBase


def _counts_steps(root: A.Node) -> bool:
    """Whether running root may count steps of the budget itself: it holds a loop, a call of a
    routine written in RCL, or an IMPORT (whose module runs)."""
    todo = [root]
    while todo:
        n = todo.pop()
        if isinstance(n, (A.While, A.Repeat, A.For, A.Import)) or isinstance(getattr(n, "symbol", None), Routine):
            return True
        todo.extend(A.children(n))
    return False


def _turns_are_short(body: A.Block) -> bool:
    """Whether every turn of a loop with this body takes a short time: it calls nothing (a
    built-in may move the arm) and makes no STRING or whole array (copying or comparing one
    may take milliseconds); an array's element is read in place."""
    todo: list[A.Node] = [body]
    while todo:
        n = todo.pop()
        if isinstance(n, A.Call) or isinstance(getattr(n, "symbol", None), (Routine, Builtin)):
            return False
        if isinstance(n, A.Expr) and (n.type == T.STRING or isinstance(n.type, T.ArrayType)):
            return False
        if isinstance(n, A.Index) and isinstance(n.obj, A.Name):
            todo.append(n.index)
        else:
            todo.extend(A.children(n))
    return True


class Statements(CompilerBase):
    def block(self, b: A.Block) -> Callable:
        stmts: Sequence[Callable] = [c for c in (self.stmt(s) for s in b.body) if c is not None]
        if not stmts:
            return lambda fr: None
        if len(stmts) == 1:
            return stmts[0]
        stmts = tuple(stmts)

        def run(fr):
            for s in stmts:
                if s(fr) is not None:
                    return RETURN
        return run

    def stmt(self, s: A.Stmt) -> Callable | None:
        return getattr(self, "stmt_" + type(s).__name__)(s)

    def stmt_VarDecl(self, s):
        return None

    stmt_ConstDecl = stmt_RoutineDecl = stmt_VarDecl

    def stmt_Assign(self, s: A.Assign):
        here = self._assignment_here(s)
        if here is not None:  # the commonest statement, without a call to a setter
            i, value, real = here
            if real:
                def run_real(fr):
                    fr[i] = float(value(fr))
                return run_real

            def run_here(fr):
                fr[i] = value(fr)
            return run_here
        value = self.expr_as(s.value, s.target.type)
        if isinstance(s.target.type, T.ArrayType):
            inner = value
            value = lambda fr: inner(fr).copy()  # arrays assign by value
        store = self.place(s.target)[1]

        def run(fr):
            store(fr, value(fr))
        return run

    def _assignment_here(self, s: A.Stmt) -> tuple[int, Callable, bool] | None:
        """(slot, value, whether REAL) of an assignment of one value to a variable in the
        activation, else None. A REAL variable holds a Python float whatever made the value."""
        if not isinstance(s, A.Assign):
            return None
        t = s.target
        if not isinstance(t, A.Name) or isinstance(t.type, T.ArrayType) or not self._in_frame(t.symbol):
            return None
        return t.symbol.slot, self.expr_as(s.value, t.type), t.type == T.REAL

    def stmt_CallStmt(self, s: A.CallStmt):
        c = s.call
        call = self.call(c.symbol, [], c.span) if isinstance(c, A.Name) else self.expr(c)

        def run(fr):
            call(fr)
        return run

    def stmt_If(self, s: A.If):
        pairs = tuple((self.expr(c), self.block(b)) for c, b in s.branches)
        otherwise = self.block(s.otherwise) if s.otherwise is not None else None
        if len(pairs) == 1:
            (cond, body), = pairs
            if otherwise is None:
                return lambda fr: body(fr) if cond(fr) else None

            return lambda fr: body(fr) if cond(fr) else otherwise(fr)

        def run(fr):
            for cond, body in pairs:
                if cond(fr):
                    return body(fr)
            if otherwise is not None:
                return otherwise(fr)
        return run

    def stmt_While(self, s: A.While):
        # Each loop counts its turns against the step budget written out (WHILE, REPEAT, FOR):
        # a call a turn would cost the tightest loops about a sixth of their time.
        cond, body, ctx = self.expr(s.cond), self.block(s.body), self.ctx
        filename, span = self.module.filename, s.span

        def run(fr):
            while cond(fr):
                ctx.steps += 1
                if ctx.steps > ctx.limit:
                    ctx.interrupt(filename, span)
                if body(fr) is not None:
                    return RETURN
        return run

    def stmt_Repeat(self, s: A.Repeat):
        cond, body, ctx = self.expr(s.cond), self.block(s.body), self.ctx
        filename, span = self.module.filename, s.span

        def run(fr):
            while True:
                ctx.steps += 1
                if ctx.steps > ctx.limit:
                    ctx.interrupt(filename, span)
                if body(fr) is not None:
                    return RETURN
                if cond(fr):
                    return None
        return run

    def stmt_For(self, s: A.For):
        start, stop = self.expr(s.start), self.expr(s.stop)
        step = self.expr(s.step) if s.step is not None else (lambda fr: 1)
        body, ctx, make = self.block(s.body), self.ctx, self._raiser()
        filename, span, down = self.module.filename, s.span, s.down

        def turns(fr):
            a, b, k = start(fr), stop(fr), step(fr)
            if k <= 0:
                raise make(f"a FOR step must be positive, not {k}", s.step.span)
            return range(a, b - 1, -k) if down else range(a, b + 1, k)

        if self._in_frame(s.symbol) and not _counts_steps(s.body):
            # The tightest loops: the counter stored without a call to a setter, and the steps
            # counted in a local (the body counts none itself), written back however the loop ends.
            # The limit (which a cancel lowers) is read every turn, or every POLL_TURNS turns of
            # a body whose every turn is short.
            slot, poll = s.symbol.slot, POLL_TURNS if _turns_are_short(s.body) else 1
            here = self._assignment_here(s.body.body[0]) if len(s.body.body) == 1 else None
            if here is not None and not here[2]:
                # and a body of one assignment run in place (a sum, a table): one call a turn
                target, value = here[:2]

                def run_assign(fr):
                    steps = ctx.steps
                    stop = min(ctx.limit, steps + poll - 1)
                    try:
                        for i in turns(fr):
                            fr[slot] = i
                            steps += 1
                            if steps > stop:
                                if steps > ctx.limit:
                                    ctx.steps = steps
                                    ctx.interrupt(filename, span)
                                stop = min(ctx.limit, steps + poll - 1)
                            fr[target] = value(fr)
                    finally:
                        ctx.steps = steps
                return run_assign

            def run_tight(fr):
                steps = ctx.steps
                stop = min(ctx.limit, steps + poll - 1)
                try:
                    for i in turns(fr):
                        fr[slot] = i
                        steps += 1
                        if steps > stop:
                            if steps > ctx.limit:
                                ctx.steps = steps
                                ctx.interrupt(filename, span)
                            stop = min(ctx.limit, steps + poll - 1)
                        if body(fr) is not None:
                            return RETURN
                finally:
                    ctx.steps = steps
            return run_tight
        store = self.store_symbol(s.symbol)

        def run(fr):
            for i in turns(fr):
                store(fr, i)
                ctx.steps += 1
                if ctx.steps > ctx.limit:
                    ctx.interrupt(filename, span)
                if body(fr) is not None:
                    return RETURN
        return run

    def stmt_Return(self, s: A.Return):
        if s.value is None or self.routine is None:
            return lambda fr: RETURN
        value = self.expr_as(s.value, s.result_type)
        slot = self.routine.frame_size - 1

        def run(fr):
            fr[slot] = value(fr)
            return RETURN
        return run

    def stmt_Try(self, s: A.Try):
        body, handler, ctx = self.block(s.body), self.block(s.handler), self.ctx

        def run(fr):
            depth = len(ctx.stack)
            try:
                return body(fr)
            except RclRuntimeError as e:
                del ctx.stack[depth:]
                ctx.errmsgs.append(e.message)
                try:
                    return handler(fr)
                finally:
                    ctx.errmsgs.pop()
        return run

    def stmt_Raise(self, s: A.Raise):
        message, make, span = self.expr(s.message), self._raiser(), s.span

        def run(fr):
            raise make(message(fr), span)
        return run

    def stmt_Solve(self, s: A.Solve):
        value, store = self.expr(s.solution), self.store_symbol(s.symbol)

        def run(fr):
            store(fr, value(fr))
        return run

    def stmt_Import(self, s: A.Import):
        if s.module is None:
            return None
        key, ran, codes = s.module.key, self.ran, self.module_codes

        def run(fr):
            if key not in ran:
                ran.add(key)
                codes[key]()
        return run

    # Places (assignment targets) -------------------------------------------

    def store_symbol(self, v: Variable) -> Callable[[list, Any], None]:
        """A setter for a variable's storage."""
        i = v.slot
        if self._in_frame(v):
            def store(fr, x):
                fr[i] = x
        elif v.kind == "ref":
            def store(fr, x):
                r = fr[i]
                r.c[r.i] = x
        else:
            g = self.values

            def store(fr, x):
                g[i] = x
        if v.type == T.REAL:
            inner = store

            def store(fr, x):
                inner(fr, float(x))
        return store
