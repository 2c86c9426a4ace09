"""The typed RCL syntax tree: one dataclass per construct, each with its span.

The parser builds these; the checker fills in the fields marked "set by the
checker" (types, resolved symbols) that the interpreter then relies on.
"""
from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field, fields
from typing import Any


@dataclass(frozen=True, slots=True)
class Span:
    """Source position: 1-based line and column of the first and last character."""

    line: int
    col: int
    end_line: int
    end_col: int

    def to(self, other: Span) -> Span:
        """The span from the start of self to the end of other."""
        return Span(self.line, self.col, other.end_line, other.end_col)


@dataclass(eq=False)
class Node:
    span: Span = field(kw_only=True)


# Names -------------------------------------------------------------------

@dataclass(eq=False)
class Ident:
    """A name as written; `key` is its case-folded identity."""

    text: str
    span: Span

    @property
    def key(self) -> str:
        return self.text.lower()

    @property
    def is_frame(self) -> bool:
        return self.text.endswith("^")


# Types as written ----------------------------------------------------------

@dataclass(eq=False)
class TypeExpr(Node):
    pass


@dataclass(eq=False)
class NamedType(TypeExpr):
    name: Ident


@dataclass(eq=False)
class FrameTypeExpr(TypeExpr):
    refs: tuple[str, str] | None  # (from, to) in lower case (types.parse_refs), or None


@dataclass(eq=False)
class ArrayTypeExpr(TypeExpr):
    low: Expr | None  # None for an open array parameter
    high: Expr | None
    element: TypeExpr


# Expressions ---------------------------------------------------------------

@dataclass(eq=False)
class Expr(Node):
    type: Any = field(default=None, repr=False, compare=False, kw_only=True)  # set by the checker


@dataclass(eq=False)
class Integer(Expr):
    text: str


@dataclass(eq=False)
class Real(Expr):
    text: str


@dataclass(eq=False)
class String(Expr):
    value: str


@dataclass(eq=False)
class Boolean(Expr):
    value: bool


@dataclass(eq=False)
class Name(Expr):
    ident: Ident
    # set by the checker: a variable, constant or routine
    symbol: Any = field(default=None, repr=False, compare=False, kw_only=True)


@dataclass(eq=False)
class Field(Expr):
    obj: Expr
    name: Ident


@dataclass(eq=False)
class Index(Expr):
    obj: Expr
    index: Expr


@dataclass(eq=False)
class Call(Expr):
    callee: Ident
    args: list[Expr]
    symbol: Any = field(default=None, repr=False, compare=False, kw_only=True)  # set by the checker: the routine or built-in


@dataclass(eq=False)
class BinOp(Expr):
    op: str  # upper case: + - * / DIV MOD = <> < <= > >= AND OR
    left: Expr
    right: Expr
    op_span: Span = field(default=None, repr=False, compare=False, kw_only=True)  # type: ignore[assignment]


@dataclass(eq=False)
class UnOp(Expr):
    op: str  # - + NOT
    operand: Expr


# Statements ----------------------------------------------------------------

@dataclass(eq=False)
class Stmt(Node):
    pass


@dataclass(eq=False)
class Block(Node):
    body: list[Stmt]


@dataclass(eq=False)
class Assign(Stmt):
    target: Expr
    value: Expr


@dataclass(eq=False)
class CallStmt(Stmt):
    call: Expr  # a Call, or a bare Name naming a procedure; anything else is an error


@dataclass(eq=False)
class If(Stmt):
    branches: list[tuple[Expr, Block]]
    otherwise: Block | None


@dataclass(eq=False)
class While(Stmt):
    cond: Expr
    body: Block


@dataclass(eq=False)
class Repeat(Stmt):
    body: Block
    cond: Expr


@dataclass(eq=False)
class For(Stmt):
    var: Ident
    start: Expr
    stop: Expr
    step: Expr | None
    down: bool
    body: Block
    symbol: Any = field(default=None, repr=False, compare=False, kw_only=True)


@dataclass(eq=False)
class Return(Stmt):
    value: Expr | None
    # set by the checker: the routine's result type
    result_type: Any = field(default=None, repr=False, compare=False, kw_only=True)


@dataclass(eq=False)
class Try(Stmt):
    body: Block
    handler: Block


@dataclass(eq=False)
class Raise(Stmt):
    message: Expr


@dataclass(eq=False)
class Solve(Stmt):
    lhs: Expr
    rhs: Expr
    unknown: Ident
    # set by the checker: an Expr computing the unknown
    solution: Any = field(default=None, repr=False, compare=False, kw_only=True)
    symbol: Any = field(default=None, repr=False, compare=False, kw_only=True)


@dataclass(eq=False)
class Import(Stmt):
    name: str
    module: Any = field(default=None, repr=False, compare=False, kw_only=True)  # set by the loader: the imported Module, or None


@dataclass(eq=False)
class VarDecl(Stmt):
    names: list[Ident]
    type: TypeExpr | None
    symbols: Any = field(default=None, repr=False, compare=False, kw_only=True)


@dataclass(eq=False)
class ConstDecl(Stmt):
    name: Ident
    value: Expr
    symbol: Any = field(default=None, repr=False, compare=False, kw_only=True)


@dataclass(eq=False)
class Param(Node):
    name: Ident
    by_ref: bool
    type: TypeExpr | None  # None: a frame name, or typed by the next typed name


@dataclass(eq=False)
class RoutineDecl(Stmt):
    name: Ident
    is_function: bool
    params: list[list[Param]]  # the groups between semicolons
    result: TypeExpr | None
    body: Block
    symbol: Any = field(default=None, repr=False, compare=False, kw_only=True)


@dataclass(eq=False)
class Module:
    """One parsed source file."""

    filename: str  # as the user named it, for diagnostics
    source: str
    body: Block
    imports: list[Import] = field(default_factory=list)
    key: str = ""  # the resolved path: one module per file and session


def children(node: Node) -> Iterator[Node]:
    """The nodes directly below node, those the checker has set included (a SOLVE's solution)."""
    for name in _node_fields(type(node)):
        value = getattr(node, name)
        if isinstance(value, Node):
            yield value
        elif isinstance(value, (list, tuple)):
            for item in value:
                if isinstance(item, Node):
                    yield item
                elif isinstance(item, (list, tuple)):  # an IF's branches: (condition, block) pairs
                    yield from (x for x in item if isinstance(x, Node))


_FIELDS: dict[type, tuple[str, ...]] = {}  # each node class's fields but its span


def _node_fields(cls: type) -> tuple[str, ...]:
    names = _FIELDS.get(cls)
    if names is None:
        names = _FIELDS[cls] = tuple(f.name for f in fields(cls) if f.name != "span")
    return names
