"""The compiler's shared state and the limits it enforces at run time; the other parts
(statements, expressions, operators, calls) each extend CompilerBase, and the methods at its end are
the entry points they call in one another."""
from __future__ import annotations

import operator
from collections.abc import Callable
from typing import Any

from .. import ast as A
from .. import types as T
from ..context import Context
from ..errors import BuiltinError, RclRuntimeError
from ..frame import FrameError
from ..scope import GlobalScope, Routine, Variable

RETURN = "return"  # what a statement closure gives when a RETURN ran
MAX_CALL_DEPTH = 1000
POLL_TURNS = 256  # a loop whose turns are short looks for a cancel this often (well under a millisecond)
MAX_STRING = 16 * 1024 * 1024  # characters in one STRING
MAX_LIVE_ELEMENTS = 20_000_000  # elements in the local arrays of all the routines running at once
USER_FACING = (BuiltinError, FrameError, ArithmeticError)

_FIELD_COLUMN = {"n": 0, "o": 1, "a": 2, "p": 3}
_VECTOR_AXIS = {"x": 0, "y": 1, "z": 2}
_COMPARE = {"=": operator.eq, "<>": operator.ne, "<": operator.lt, "<=": operator.le,
            ">": operator.gt, ">=": operator.ge}


class CompilerBase:
    """What every part of the compiler shares: the session's storage and where it is compiling."""

    def __init__(self, scope: GlobalScope, values: list, ctx: Context, ran: set) -> None:
        self.scope = scope
        self.values = values
        self.ctx = ctx
        self.ran = ran  # keys of the modules already executed in this session
        self.module_codes: dict[str, Callable[[], None]] = {}  # compiled imported modules, by key
        self._module: A.Module | None = None
        self.routine: Routine | None = None

    @property
    def module(self) -> A.Module:
        """The module being compiled (set by each entry point of Compiler)."""
        assert self._module is not None, "compiling outside a module"
        return self._module

    def _in_frame(self, v: Variable) -> bool:
        """Whether v is read and written straight in the activation list `fr`: a routine's own
        variable, or a global in top-level code (which runs with the globals as its activation)."""
        return v.kind != "ref" and (not v.is_global or self.routine is None)

    # Errors ----------------------------------------------------------------

    def _raiser(self) -> Callable[[str, A.Span], RclRuntimeError]:
        """A function making runtime errors located in the module being compiled."""
        filename, source, stack = self.module.filename, self.module.source, self.ctx.stack

        def make(message: str, span: A.Span) -> RclRuntimeError:
            return RclRuntimeError(message, filename, span, source, tuple(stack))
        return make

    # The parts' entry points, defined in statements.py, expressions.py, calls.py

    def block(self, b: A.Block) -> Callable:
        raise NotImplementedError

    def place(self, e: A.Expr) -> tuple[Callable, Callable]:
        raise NotImplementedError

    def store_symbol(self, v: Variable) -> Callable[[list, Any], None]:
        raise NotImplementedError

    def expr(self, e: A.Expr) -> Callable:
        raise NotImplementedError

    def _element_slot(self, e: A.Index) -> Callable:
        raise NotImplementedError

    def expr_as(self, e: A.Expr, target: T.Type | None) -> Callable:
        raise NotImplementedError

    def call(self, target, args: list[A.Expr], span: A.Span, result_type=None) -> Callable:
        raise NotImplementedError


def _message(e: Exception) -> str:
    if isinstance(e, ZeroDivisionError):
        return "division by zero"
    if isinstance(e, OverflowError):
        return "number too large"
    return str(e)

