"""The compiler's calls: arguments by value or by reference, built-ins through their adapters,
routines with their own activation (slots), depth and array limits."""
from __future__ import annotations

from collections.abc import Callable, Sequence

from .. import ast as A
from .. import types as T
from ..builtins import Builtin
from ..errors import StackEntry
from ..scope import Routine
from ..values import Ref
from .base import MAX_CALL_DEPTH, MAX_LIVE_ELEMENTS, USER_FACING, CompilerBase, _message


class Calls(CompilerBase):
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
        entry = StackEntry(r.name, self.module.filename, span)
        filename = self.module.filename
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
