"""Built-in routines: typed adapters from RCL calls to plain Python.

Each domain module (core, motion, vision, camera) holds one explicit table
``BUILTINS = {"RCL NAME": function}``. A function's annotations are its RCL
signature (see rcl.types) and its docstring is its help text. A function
whose first parameter is ``ctx: Context`` (rcl.context) receives the running Context
(output stream, robot, camera, the error being handled).
"""
from __future__ import annotations

import inspect
import typing
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

from ..types import INTEGER, NUMBER, REAL, ParamInfo, Type, from_annotation, inverse, is_frame, swaps_refs


@dataclass(eq=False)
class Builtin:
    """A routine implemented in Python."""

    name: str
    func: Callable
    params: tuple[ParamInfo, ...]
    result: Type | None  # None: a procedure
    variadic: Type | None  # the type of any further arguments, or None
    wants_ctx: bool
    doc: str
    swaps_refs: bool = False  # the result is the first argument's frame, its references swapped (INV)

    @classmethod
    def from_function(cls, name: str, func: Callable) -> Builtin:
        """Read the RCL signature off a Python function's annotations."""
        hints = typing.get_type_hints(func, include_extras=True)
        params: list[ParamInfo] = []
        variadic = None
        wants_ctx = False
        for i, p in enumerate(inspect.signature(func).parameters.values()):
            if i == 0 and p.name == "ctx":
                wants_ctx = True
                continue
            if p.name not in hints:
                raise TypeError(f"built-in {name}: parameter {p.name} has no annotation")
            typ, by_ref = from_annotation(hints[p.name])
            if p.kind is inspect.Parameter.VAR_POSITIONAL:
                variadic = typ
            elif p.kind in (inspect.Parameter.POSITIONAL_ONLY, inspect.Parameter.POSITIONAL_OR_KEYWORD):
                params.append(ParamInfo(p.name, typ, by_ref))
            else:
                raise TypeError(f"built-in {name}: parameter {p.name} must be positional")
        ret = hints.get("return", type(None))
        result = None if ret is type(None) else from_annotation(ret)[0]
        swaps = swaps_refs(ret)
        doc = inspect.getdoc(func) or ""
        return cls(name.upper(), func, tuple(params), result, variadic, wants_ctx, doc, swaps)

    def result_for(self, arg_types: list[Type]) -> Type | None:
        """The result type of a call with these argument types (resolves Number, swaps references)."""
        if self.swaps_refs and arg_types and is_frame(arg_types[0]):
            return inverse(arg_types[0])
        if self.result is not NUMBER:
            return self.result
        number_args = [t for p, t in zip(self.params, arg_types) if p.type is NUMBER]
        if self.variadic is NUMBER:
            number_args += arg_types[len(self.params):]
        return INTEGER if all(t == INTEGER for t in number_args) else REAL

    def signature(self) -> str:
        parts = [("VAR " if p.by_ref else "") + p.name.upper() + ("^" if is_frame(p.type) else "")
                 + f": {p.type}" for p in self.params]
        if self.variadic is not None:
            parts.append(f"...: {self.variadic}")
        text = f"{self.name}({'; '.join(parts)})"
        return text + (f" : {self.result}" if self.result is not None else "")


def default_builtins() -> dict[str, Builtin]:
    """A fresh table of every built-in, keyed by case-folded name (the Builtins are shared: never mutated)."""
    return dict(_builtin_table())


@lru_cache(maxsize=1)
def _builtin_table() -> tuple[tuple[str, Builtin], ...]:
    from . import camera, cell, core, motion, vision

    return tuple((name.lower(), Builtin.from_function(name, func))
                 for module in (core, motion, vision, camera, cell) for name, func in module.BUILTINS.items())
