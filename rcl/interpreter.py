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

import operator
from collections.abc import Callable, Sequence
from typing import Any

from . import ast as A
from . import types as T
from .builtins import Builtin
from .context import Context
from .errors import BuiltinError, RclRuntimeError, StackEntry
from .frame import Frame, FrameError
from .scope import GlobalScope, Routine, Variable
from .types import INT_MAX, INT_MIN  # bound here: read on every INTEGER operation
from .values import Ref, default_factory

RETURN = "return"  # what a statement closure gives when a RETURN ran
MAX_CALL_DEPTH = 1000
MAX_STRING = 16 * 1024 * 1024  # characters in one STRING
MAX_LIVE_ELEMENTS = 20_000_000  # elements in the local arrays of all the routines running at once
USER_FACING = (BuiltinError, FrameError, ArithmeticError)

_FIELD_COLUMN = {"n": 0, "o": 1, "a": 2, "p": 3}
_VECTOR_AXIS = {"x": 0, "y": 1, "z": 2}
_COMPARE = {"=": operator.eq, "<>": operator.ne, "<": operator.lt, "<=": operator.le,
            ">": operator.gt, ">=": operator.ge}


class Compiler:
    """Turns checked modules and routines into closures over one session's storage."""

    def __init__(self, scope: GlobalScope, values: list, ctx: Context, ran: set) -> None:
        self.scope = scope
        self.values = values
        self.ctx = ctx
        self.ran = ran  # keys of the modules already executed in this session
        self.module_codes: dict[str, Callable[[], None]] = {}  # compiled imported modules, by key
        self.module: A.Module | None = None
        self.routine: Routine | None = None

    # Units -----------------------------------------------------------------

    @property
    def _here(self) -> A.Module:
        """The module being compiled."""
        assert self.module is not None, "compiling outside a module"
        return self.module

    def module_code(self, m: A.Module) -> Callable[[], None]:
        self.module, self.routine = m, None
        body = self.block(m.body)
        top: list = []
        return lambda: body(top)

    def expression_code(self, e: A.Expr, m: A.Module) -> Callable[[], Any]:
        """A checked top-level expression (the REPL's), ready to evaluate."""
        self.module, self.routine = m, None
        f = self.expr(e)
        top: list = []
        return lambda: f(top)

    def routine_code(self, r: Routine, m: A.Module) -> None:
        self.module, self.routine = m, r
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

    # Errors ----------------------------------------------------------------

    def _raiser(self) -> Callable[[str, A.Span], RclRuntimeError]:
        """A function making runtime errors located in the module being compiled."""
        filename, source, stack = self._here.filename, self._here.source, self.ctx.stack

        def make(message: str, span: A.Span) -> RclRuntimeError:
            return RclRuntimeError(message, filename, span, source, tuple(stack))
        return make

    # Statements ------------------------------------------------------------

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
        value = self.expr_as(s.value, s.target.type)
        if isinstance(s.target.type, T.ArrayType):
            inner = value
            value = lambda fr: inner(fr).copy()  # arrays assign by value
        store = self.place(s.target)[1]

        def run(fr):
            store(fr, value(fr))
        return run

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
        cond, body, ctx = self.expr(s.cond), self.block(s.body), self.ctx
        filename, span = self._here.filename, s.span

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
        filename, span = self._here.filename, s.span

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
        store = self.store_symbol(s.symbol)
        filename, span, down = self._here.filename, s.span, s.down

        def run(fr):
            a, b, k = start(fr), stop(fr), step(fr)
            if k <= 0:
                raise make(f"a FOR step must be positive, not {k}", s.step.span)
            for i in (range(a, b - 1, -k) if down else range(a, b + 1, k)):
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
        if v.is_global:
            g = self.values

            def store(fr, x):
                g[i] = x
        elif v.kind == "ref":
            def store(fr, x):
                r = fr[i]
                r.c[r.i] = x
        else:
            def store(fr, x):
                fr[i] = x
        if v.type == T.REAL:
            inner = store

            def store(fr, x):
                inner(fr, float(x))
        return store

    def place(self, e: A.Expr) -> tuple[Callable, Callable]:
        """(get, set) for an assignable expression."""
        if isinstance(e, A.Name):
            return self.expr_Name(e), self.store_symbol(e.symbol)
        if isinstance(e, A.Index):
            array, slot = self.expr(e.obj), self._element_slot(e)

            def get(fr):
                return slot(fr, array(fr))

            def set_(fr, x):
                arr = array(fr)
                arr.items[slot(fr, arr, read=False)] = x
            if e.type == T.REAL:
                inner = set_

                def set_(fr, x):
                    inner(fr, float(x))
            return get, set_
        if isinstance(e, A.Field):
            pget, pset = self.place(e.obj)
            get = self.expr_Field(e)
            field = e.name.key
            if field == "p":
                def set_(fr, x):
                    pset(fr, pget(fr).with_p(x))
            else:
                axis = _VECTOR_AXIS[field]

                def set_(fr, x):
                    v = pget(fr).copy()
                    v[axis] = x
                    v.flags.writeable = False
                    pset(fr, v)
            return get, set_
        raise AssertionError(f"not a place: {e!r}")  # the checker allows no other targets

    # Expressions -------------------------------------------------------------

    def expr(self, e: A.Expr) -> Callable:
        return getattr(self, "expr_" + type(e).__name__)(e)

    def expr_as(self, e: A.Expr, target: T.Type | None) -> Callable:
        """An expression whose value goes where target is expected (INTEGER widens to REAL)."""
        f = self.expr(e)
        if target == T.REAL and e.type != T.REAL:
            return lambda fr: float(f(fr))
        return f

    def expr_Integer(self, e):
        value = int(e.text)
        return lambda fr: value

    def expr_Real(self, e):
        value = float(e.text)
        return lambda fr: value

    def expr_String(self, e):
        value = e.value
        return lambda fr: value

    def expr_Boolean(self, e):
        value = e.value
        return lambda fr: value

    def expr_Name(self, e: A.Name):
        v = e.symbol
        if not isinstance(v, Variable):
            return self.call(v, [], e.span)  # a routine called without ()
        if v.kind == "const":
            value = float(v.value) if v.type == T.REAL else v.value
            return lambda fr: value
        i, make, span, name = v.slot, self._raiser(), e.span, v.name

        def unset():
            return make(f"{name} has no value yet", span)
        if v.is_global:
            g = self.values

            def get(fr):
                x = g[i]
                if x is None:
                    raise unset()
                return x
        elif v.kind == "ref":
            def get(fr):
                r = fr[i]
                x = r.c[r.i]
                if x is None:
                    raise unset()
                return x
        else:
            def get(fr):
                x = fr[i]
                if x is None:
                    raise unset()
                return x
        return get

    def expr_Field(self, e: A.Field):
        obj = self.expr(e.obj)
        field = e.name.key
        if T.is_frame(e.obj.type):
            column = _FIELD_COLUMN[field]
            return lambda fr: obj(fr)._m[:3, column]
        axis = _VECTOR_AXIS[field]
        return lambda fr: float(obj(fr)[axis])

    def _element_slot(self, e: A.Index) -> Callable:
        """slot(fr, array, read=True): the checked list position of e's index (and the element, when reading)."""
        index, make, span = self.expr(e.index), self._raiser(), e.span

        def slot(fr, arr, read=True):
            i = index(fr)
            k = i - arr.low
            if not 0 <= k < len(arr.items):
                raise make(f"index {i} is outside the array bounds {arr.low}..{arr.high}", e.index.span)
            if not read:
                return k
            x = arr.items[k]
            if x is None:
                raise make(f"element {i} has no value yet", span)
            return x
        return slot

    def expr_Index(self, e: A.Index):
        return self.place(e)[0]

    def expr_Call(self, e: A.Call):
        return self.call(e.symbol, e.args, e.span, e.type)

    def call(self, target, args: list[A.Expr], span: A.Span, result_type=None) -> Callable:
        if isinstance(target, Builtin):
            return self._builtin_call(target, args, span, result_type)
        return self._routine_call(target, args, span)

    def _argument(self, a: A.Expr, want: T.Type, by_ref: bool) -> Callable:
        if not by_ref:
            return self.expr_as(a, want)
        if isinstance(a, A.Name):
            v = a.symbol
            i = v.slot
            if v.kind == "ref":
                return lambda fr: fr[i]
            if v.is_global:
                g = self.values
                return lambda fr: Ref(g, i)
            return lambda fr: Ref(fr, i)
        assert isinstance(a, A.Index)  # the checker lets only a name or an element be passed by VAR
        array, slot = self.expr(a.obj), self._element_slot(a)

        def ref(fr):
            arr = array(fr)
            return Ref(arr.items, slot(fr, arr, read=False))
        return ref

    def _builtin_call(self, b: Builtin, args: list[A.Expr], span: A.Span, result_type) -> Callable:
        wants = [(p.type, p.by_ref) for p in b.params]
        if b.variadic is not None:
            wants += [(b.variadic, False)] * (len(args) - len(b.params))
        fs: Sequence[Callable] = [self._argument(a, t, by_ref) for a, (t, by_ref) in zip(args, wants)]
        func, make = b.func, self._raiser()
        if b.wants_ctx:
            ctx = self.ctx
            func = lambda *xs, f=b.func: f(ctx, *xs)
        if len(fs) == 0:
            def call(fr):
                try:
                    return func()
                except USER_FACING as e:
                    raise make(_message(e), span) from None
        elif len(fs) == 1:
            a0, = fs

            def call(fr):
                try:
                    return func(a0(fr))
                except USER_FACING as e:
                    raise make(_message(e), span) from None
        elif len(fs) == 2:
            a0, a1 = fs

            def call(fr):
                try:
                    return func(a0(fr), a1(fr))
                except USER_FACING as e:
                    raise make(_message(e), span) from None
        else:
            fs = tuple(fs)

            def call(fr):
                try:
                    return func(*[a(fr) for a in fs])
                except USER_FACING as e:
                    raise make(_message(e), span) from None
        if b.result is T.NUMBER and result_type == T.REAL:
            inner = call
            return lambda fr: float(inner(fr))
        return call

    def _routine_call(self, r: Routine, args: list[A.Expr], span: A.Span) -> Callable:
        fs = tuple(self._argument(a, p.type, p.by_ref) for a, p in zip(args, r.params))
        ctx, stack, make = self.ctx, self.ctx.stack, self._raiser()
        entry = StackEntry(r.name, self._here.filename, span)
        filename = self._here.filename
        is_function, name = r.is_function, r.name

        def call(fr):
            body, template, fresh, elements = r.code
            new = template.copy()
            for k, a in enumerate(fs):
                new[k] = a(fr)
            ctx.steps += 1
            if ctx.steps > ctx.limit:
                ctx.interrupt(filename, span)
            if len(stack) >= MAX_CALL_DEPTH:
                raise make(f"recursion too deep: more than {MAX_CALL_DEPTH} nested calls", span)
            if elements:
                if ctx.live_elements + elements > MAX_LIVE_ELEMENTS:
                    raise make(f"too much array memory: the local arrays of the routines running would hold "
                               f"{ctx.live_elements + elements:,} elements (at most {MAX_LIVE_ELEMENTS:,})", span)
                ctx.live_elements += elements
                for k, mk in fresh:
                    new[k] = mk()
            stack.append(entry)
            try:
                status = body(new)
            except RecursionError:  # deep calls within deeply nested blocks: Python's stack is spent
                raise make("the program nests too deeply to run: calls within deeply nested blocks", span) from None
            finally:
                stack.pop()
                ctx.live_elements -= elements
            if is_function:
                if status is None:
                    raise make(f"function {name} ended without RETURN", span)
                return new[-1]
        return call

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
        op, a, b = e.op, self.expr(e.left), self.expr(e.right)
        ta, tb = e.left.type, e.right.type
        if op == "AND":
            return lambda fr: a(fr) and b(fr)
        if op == "OR":
            return lambda fr: a(fr) or b(fr)
        if op in _COMPARE:
            cmp = _COMPARE[op]
            return lambda fr: cmp(a(fr), b(fr))
        if T.is_frame(ta):
            if T.is_frame(tb):
                trusted = Frame._trusted
                return lambda fr: trusted(a(fr)._m @ b(fr)._m)
            return lambda fr: a(fr).apply(b(fr))
        if op in ("/", "DIV", "MOD"):
            return self._division(op, a, b, e)
        if e.type == T.INTEGER:
            return self._integer_arithmetic(op, a, b, e.op_span)
        if e.type == T.STRING:
            return self._concatenation(a, b, e.op_span)
        if op == "+":
            return lambda fr: a(fr) + b(fr)
        if op == "-":
            return lambda fr: a(fr) - b(fr)
        return lambda fr: a(fr) * b(fr)

    def _integer_arithmetic(self, op: str, a: Callable, b: Callable, span: A.Span) -> Callable:
        """+ - * on INTEGERs, each written out: this is the inner loop of most programs."""
        make = self._raiser()

        def overflow():
            return make("INTEGER overflow (beyond 64 bits)", span)
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


def _message(e: Exception) -> str:
    if isinstance(e, ZeroDivisionError):
        return "division by zero"
    if isinstance(e, OverflowError):
        return "number too large"
    return str(e)

