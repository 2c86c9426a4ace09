"""The running program's Context (see the class); built-ins that take it as their first
parameter annotate it ``ctx: Context``. A Session makes one and its compiled code shares it."""
from __future__ import annotations

import math
import sys

from . import ast as A
from .errors import RclCancelled, StackEntry
from .files import Files


class Context:
    """What a running program shares with its host (starlark's "thread").

    Output stream, robot, camera, the call stack, the error being handled,
    and the step counter that cancellation and the step budget use.
    """

    def __init__(self, robot=None, camera=None, camera_model=None, wire_finder=None, out=None, cell=None,
                 files: Files | None = None) -> None:
        self.robot = robot
        self.cell = cell  # the simulated cell (rcl.cell.SimCell) with its stations, or None
        self.camera = camera
        self.camera_model = camera_model
        self.wire_finder = wire_finder
        self._out = out
        self.stack: list[StackEntry] = []
        self.errmsgs: list[str] = []
        self.steps = 0
        self.limit: float = math.inf
        self.budget: int | None = None
        self.cancel_reason: str | None = None
        self.cancel_by_user = False
        self.live_elements = 0  # in the local arrays of the routines running (MAX_LIVE_ELEMENTS)
        self.files = files if files is not None else Files()  # the folders programs may touch (rcl.files)

    @property
    def out(self):
        return self._out if self._out is not None else sys.stdout

    @out.setter
    def out(self, stream) -> None:
        self._out = stream

    def start(self, budget: int | None) -> None:
        self.stack.clear()
        self.errmsgs.clear()
        self.steps = 0
        self.budget = budget
        self.live_elements = 0
        self.cancel_reason = None
        self.limit = math.inf if budget is None else budget

    def cancel(self, reason: str = "cancelled", by_user: bool = False) -> None:
        """Ask the running program to stop at its next loop iteration or call (any thread)."""
        self.cancel_reason = reason
        self.cancel_by_user = by_user
        self.limit = -1

    def interrupt(self, filename: str, span: A.Span) -> None:
        """Called when the step counter passes its limit."""
        if self.cancel_reason is not None:
            raise RclCancelled(self.cancel_reason, filename, span, by_user=self.cancel_by_user,
                               stack=tuple(self.stack))
        raise RclCancelled(f"the step budget of {self.budget} loop iterations and calls is spent",
                           filename, span, stack=tuple(self.stack))
