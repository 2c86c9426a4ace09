"""Symbols: what a name means, as the checker resolves it and the interpreter uses it.

A Session owns one GlobalScope. The checker works on a copy (`fork`) and
the session adopts it only when the program passed, so a rejected program
leaves no trace.
"""
from __future__ import annotations

import copy
from dataclasses import dataclass, field
from typing import Any

from .ast import RoutineDecl, Span
from .types import ParamInfo, Type


@dataclass(eq=False)
class Variable:
    """A variable, constant or parameter."""

    name: str  # as first written
    type: Type | None  # None while not yet inferred
    is_global: bool
    slot: int
    kind: str = "var"  # var | const | param | ref (a VAR parameter)
    declared: bool = False  # by VAR, CONST or a parameter list: its type never widens
    value: Any = None  # a constant's value
    filename: str = ""
    span: Span | None = None
    origin: Any = None  # the statement that declared it (so later passes know it again)


@dataclass(eq=False)
class Routine:
    """A PROCEDURE or FUNCTION written in RCL."""

    name: str
    params: list[ParamInfo]
    result: Type | None  # None for a procedure
    decl: RoutineDecl
    module: Any  # the ast.Module it is written in
    locals: dict[str, Variable] = field(default_factory=dict)
    code: Any = None  # set by the interpreter: the compiled body

    @property
    def is_function(self) -> bool:
        return self.result is not None

    @property
    def frame_size(self) -> int:
        """Slots in an activation: parameters and locals, then the result."""
        return len(self.locals) + 1


@dataclass(eq=False)
class GlobalScope:
    """Everything a session knows between runs."""

    variables: dict[str, Variable] = field(default_factory=dict)
    routines: dict[str, Routine] = field(default_factory=dict)
    builtins: dict[str, Any] = field(default_factory=dict)
    modules: dict[str, Any] = field(default_factory=dict)  # resolved path -> Module, once loaded
    slots: int = 0

    def fork(self) -> GlobalScope:
        """A copy the checker may change freely (symbols copied, built-ins shared)."""
        return GlobalScope(
            variables={k: copy.copy(v) for k, v in self.variables.items()},
            routines=dict(self.routines),
            builtins=self.builtins,
            modules=dict(self.modules),
            slots=self.slots,
        )

    def new_global(self, name: str, type: Type | None, **kw) -> Variable:
        v = Variable(name, type, True, self.slots, **kw)
        self.slots += 1
        self.variables[name.lower()] = v
        return v


