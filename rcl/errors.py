"""Diagnostics and the exceptions that carry them.

Only the CLI and the REPL print; everything else raises these. Every
message renders as ``FILE:LINE:COL: error: MESSAGE`` followed by the source
line and a caret under the column.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass
from functools import lru_cache

from .ast import Span


@dataclass(frozen=True)
class Diagnostic:
    """One error at a place in a source file."""

    filename: str
    span: Span
    message: str
    source_line: str = ""

    def render(self) -> str:
        head = f"{self.filename}:{self.span.line}:{self.span.col}: error: {self.message}"
        if not self.source_line:
            return head
        line = self.source_line.rstrip("\n")
        # Keep tabs so the caret lines up under them.
        pad = "".join(c if c == "\t" else " " for c in line[: self.span.col - 1])
        width = 1
        if self.span.end_line == self.span.line:
            width = max(1, self.span.end_col - self.span.col + 1)
        width = min(width, max(1, len(line) - self.span.col + 1))
        return f"{head}\n{line}\n{pad}^{'~' * (width - 1)}"


@lru_cache(maxsize=4)  # a file with thousands of errors splits once (a str caches its own hash)
def source_lines(source: str) -> tuple[str, ...]:
    """The source's lines as the parser counts them: ended by LF alone (a CR before it is the
    line's end too, not a character of it; a bare CR, a form feed or U+2028 ends no line)."""
    return tuple(x.removesuffix("\r") for x in source.split("\n"))


_SHOWN = str.maketrans({c: " " for c in "\r\f\v\x1c\x1d\x1e\x85\u2028\u2029"})


def source_line(source: str, line: int) -> str:
    """Line `line` for showing under a message: a character that would move a terminal's cursor
    elsewhere shows as a space (one column, as the caret counts it)."""
    lines = source_lines(source)
    return lines[line - 1].translate(_SHOWN) if 0 < line <= len(lines) else ""


class RclError(Exception):
    """Base of every error RCL reports to a user."""


class RclStaticError(RclError):
    """The program was rejected before anything ran; carries every diagnostic."""

    def __init__(self, diagnostics: list[Diagnostic]) -> None:
        self.diagnostics = diagnostics
        super().__init__("\n".join(d.render() for d in diagnostics))


@dataclass(frozen=True)
class StackEntry:
    """One active RCL routine call: who is running and where it was called from."""

    routine: str
    filename: str
    span: Span


class RclRuntimeError(RclError):
    """An error while the program ran; the robot has been halted."""

    def __init__(self, message: str, filename: str = "", span: Span | None = None,
                 source: str = "", stack: tuple[StackEntry, ...] = ()) -> None:
        super().__init__(message)
        self.message = message
        self.filename = filename
        self.span = span
        self.source = source
        self.stack = stack

    @property
    def diagnostic(self) -> Diagnostic | None:
        if self.span is None:
            return None
        return Diagnostic(self.filename, self.span, self.message, source_line(self.source, self.span.line))

    def render(self) -> str:
        d = self.diagnostic
        text = d.render() if d else f"error: {self.message}"
        return text + render_stack(self.stack)

    def __str__(self) -> str:
        return self.render()


def render_stack(stack: tuple[StackEntry, ...]) -> str:
    """The RCL call stack, most recent call first, after a newline ('' for none)."""
    if not stack:
        return ""
    lines = ["RCL call stack (most recent call first):"]
    calls = [f"  {e.routine}, called at {e.filename}:{e.span.line}:{e.span.col}" for e in reversed(stack)]
    for line, same in itertools.groupby(calls):  # a recursion's calls, folded as Python folds them
        lines.append(line)
        more = sum(1 for _ in same) - 1
        if more:
            lines.append(f"  [the call above {more} more time{'s' if more > 1 else ''}]")
    return "\n" + "\n".join(lines)


class RclCancelled(RclError):
    """The program was stopped from outside (cancel(), Ctrl-C or the step budget); the robot is halted."""

    def __init__(self, reason: str, filename: str = "", span: Span | None = None,
                 by_user: bool = False, stack: tuple[StackEntry, ...] = ()) -> None:
        super().__init__(reason)
        self.reason = reason
        self.filename = filename
        self.span = span
        self.by_user = by_user  # Ctrl-C, as opposed to cancel() or the step budget
        self.stack = stack

    def render(self) -> str:
        if self.span is None:
            return f"stopped: {self.reason}"
        return (f"{self.filename}:{self.span.line}:{self.span.col}: error: stopped: {self.reason}"
                + render_stack(self.stack))


EXIT_OK, EXIT_RUNTIME, EXIT_STATIC, EXIT_INTERRUPTED = 0, 1, 2, 130  # rcl's exit statuses


def report(e: RclError) -> tuple[str, int]:
    """What a person is shown for an RCL error, and the exit status it means: a static error's
    diagnostics (2), a runtime error (1), a stopped run with the robot halted (130 when the
    user stopped it, else 1), anything else as `error: ...` (2: nothing ran)."""
    if isinstance(e, RclStaticError):
        return "\n".join(d.render() for d in e.diagnostics), EXIT_STATIC
    if isinstance(e, RclCancelled):
        return f"{e.render()}\nthe robot was halted", EXIT_INTERRUPTED if e.by_user else EXIT_RUNTIME
    if isinstance(e, RclRuntimeError):
        return e.render(), EXIT_RUNTIME
    return f"error: {e}", EXIT_STATIC


class BuiltinError(Exception):
    """Raised by a built-in's Python code for a user-facing failure (IK, limits, bad argument).

    The interpreter turns it into an RclRuntimeError at the calling expression.
    """
