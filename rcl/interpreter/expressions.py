"""The compiler's expressions but the operators (operators.py): each expr_<Node> gives a closure
f(fr) -> value, doing only what the static types say and the checks only run time can make
(unset variables, array bounds)."""
from __future__ import annotations

from collections.abc import Callable

from .. import ast as A
from .. import types as T
from ..scope import Variable
from .base import _FIELD_COLUMN, _VECTOR_AXIS, CompilerBase


class Expressions(CompilerBase):
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
        if self._in_frame(v):
            def get(fr):
                x = fr[i]
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
            g = self.values

            def get(fr):
                x = g[i]
                if x is None:
                    raise unset()
                return x
        return get

    def expr_Field(self, e: A.Field):
        obj = self.expr(e.obj)
        field = e.name.key
        if T.is_frame(e.obj.type):
            column = _FIELD_COLUMN[field]
            return lambda fr: obj(fr).matrix[:3, column]
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
