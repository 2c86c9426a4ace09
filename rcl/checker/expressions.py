"""The checker's expressions: each expr_<Node> gives the type of one kind of expression
(None for a call of a procedure) and records it on the node for the interpreter.
"""
from __future__ import annotations

from .. import ast as A
from .. import types as T
from ..rules import ORDERING, article, binop_type
from .base import CheckerBase


class Expressions(CheckerBase):
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
