"""Session: the embedding API. The CLI, the REPL and the tests all go through it.

    s = Session()
    s.run("W^ := TRANS(300, 0, 20) * ROTY(180)")
    s["W^"].matrix            # a 4x4 numpy array
    s.register(my_function)   # a Python function becomes a typed built-in

A session owns its variables, routines, built-ins, robot and camera; two
sessions share nothing. Variables and routines persist from one run to the
next. A program is parsed and checked whole before anything runs: a static
error raises RclStaticError and nothing moves; a runtime error halts the
robot and raises RclRuntimeError.
"""
from __future__ import annotations

import contextlib
import gc
import math
import os
import sys
import time
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

import numpy as np

from . import types as T
from .ast import Span
from .builtins import Builtin, default_builtins
from .checker import Checker
from .context import Context
from .errors import Diagnostic, RclCancelled, RclError, RclRuntimeError, RclStaticError
from .files import Files
from .frame import Frame, FrameError
from .interpreter import Compiler
from .keywords import is_name
from .loader import describe_read_error, load, read_source
from .robots import SimRobot
from .scope import GlobalScope, Routine
from .values import Array, default_factory

RECURSION_LIMIT = 100_000  # Python frames; RCL's own limit (MAX_CALL_DEPTH) is what users meet


class RclInternalError(RclError):
    """A fault in RCL itself (not in the user's program); the robot has been halted."""


class Session:
    """One RCL interpreter with its own state, robot and camera."""

    def __init__(self, *, robot=None, camera=None, camera_model=None, wire_finder=None, out=None,
                 step_budget: int | None = None, search_path: Iterable[str | Path] = (), cell=None,
                 data: Iterable[str | Path] = (), any_file: bool = False,
                 time_limit: float | None = None) -> None:
        """robot: a rcl.robots.Robot (default: a SimRobot of the smartarms model); camera: anything with
        grab() -> image array, such as rcl.camera.ImageFiles (default: none);
        camera_model: a rcl.camera.Calibration (default: a new, empty one);
        wire_finder: f(image, method) -> rcl.vision.Sighting | None for FINDWIRE (method 'ridge'),
            GREYWIRE, BINWIRE and FINDMIDDLE ('middle')
        (default: the paper's systems, rcl.vision.find_wires);
        out: where WRITE goes (default: sys.stdout); step_budget: stop a run after this many
        loop iterations and routine calls; search_path: extra folders for IMPORT;
        cell: a rcl.workcell.Cell (open_cell()): its robot and camera unless robot or camera are
        given, a camera model on its tray's plane, its stations, and IMPORT 'cell';
        data: folders programs may read and write files in besides their own (the first is
        where a relative name in LOADWARP or SAVEWARP starts; the cell file's folder is added);
        any_file: let programs name any path the user may (rcl.files says what is otherwise allowed);
        time_limit: stop a run after this many seconds of wall-clock time (at its next loop
        iteration or call, as cancel() does; the robot is halted)."""
        from .camera import Calibration

        self.cell = cell
        if cell is not None:
            robot = robot if robot is not None else cell.robot
            camera = camera if camera is not None else cell.camera
        self.robot = robot if robot is not None else SimRobot()
        self.camera = camera
        tray_z = cell.tray_z if cell is not None else 0.0
        self.camera_model = camera_model if camera_model is not None else Calibration(z=tray_z)
        self.step_budget = step_budget
        if time_limit is not None and not (math.isfinite(time_limit) and time_limit > 0):
            raise ValueError(f"time_limit must be a positive number of seconds, not {time_limit}")
        self.time_limit = time_limit
        self.search_path = [Path(p) for p in search_path]
        folders = [Path(p) for p in data]
        if cell is not None and cell.config.from_file:
            folders.append(cell.config.folder)
        self.files = Files(folders, self.search_path, anywhere=any_file)
        # the camera's scale, for the vision systems' millimetre sizes
        self.px_per_mm = cell.config.px_per_mm() if cell is not None else 4.0
        self.on_look: Callable | None = None  # f(image, vision result, ms) after every FINDWIRE/GREYWIRE/BINWIRE
        if wire_finder is None:
            wire_finder = self._find_wire
        sim = cell.sim if cell is not None and self.robot is cell.robot and self.camera is cell.camera else None
        self._made = {"cell": ("cell.rcl", cell.module_source())} if cell is not None else {}
        self._ctx = Context(self.robot, self.camera, self.camera_model, wire_finder, out, cell=sim, files=self.files)
        self._scope = GlobalScope(builtins=default_builtins())
        self._values: list = []
        self._ran: set[str] = set()

    # Running ---------------------------------------------------------------

    def run(self, source: str, filename: str = "<string>", *, forget_on_error: bool = False) -> None:
        """Check and run RCL source text (IMPORTs are found from the current folder). With
        forget_on_error (the REPL's rule), a run that fails declares nothing: the variables,
        routines and imports it brought are forgotten, as if it had not been typed (values it
        gave to variables declared before stay)."""
        self._run(source, filename, "", Path.cwd(), forget_on_error)

    def run_file(self, path: str | Path) -> None:
        """Check and run an .rcl file."""
        source, key = self._read(path)
        self._run(source, str(path), key, Path(key).parent)

    def check(self, source: str, filename: str = "<string>") -> list[Diagnostic]:
        """Every static error of the source, without running it or changing the session."""
        return self._check(source, filename, "", Path.cwd())[1]

    def check_file(self, path: str | Path) -> list[Diagnostic]:
        source, key = self._read(path)
        return self._check(source, str(path), key, Path(key).parent)[1]

    def evaluate(self, text: str, filename: str = "<expression>") -> tuple[Any, str | None]:
        """Check and evaluate one expression: (its value as Python sees it, its RCL type).

        A procedure call is run and gives (None, None). Raises as run() does."""
        expr, t, scope, module = self._check_expression(text, filename)
        self._adopt(scope, [])
        compiler = Compiler(self._scope, self._values, self._ctx, self._ran)
        value = self._execute(lambda: compiler.expression_code(expr, module)(), filename, text)
        return (None, None) if t is None else (_to_python(value), str(t))

    def type_of(self, text: str) -> str | None:
        """The static type of an expression (None for a procedure call); RclStaticError if it has errors."""
        return None if (t := self._check_expression(text, "<expression>")[1]) is None else str(t)

    def _check_expression(self, text: str, filename: str):
        from .ast import Block, Module
        from .parser import parse_expression

        with _deep_recursion():
            expr = parse_expression(text, filename)
            scope = self._scope.fork()
            module = Module(filename, text, Block([], span=expr.span))
            t, diagnostics = Checker(scope).check_expression(expr, module)
        if diagnostics:
            raise RclStaticError([_assignment_hint(expr, d) for d in diagnostics])
        return expr, t, scope, module

    def _find_wire(self, image, method: str):
        """The default wire finder: the best candidate of the finder by that name (rcl.vision.METHODS)."""
        from .camera import ImageError
        from .errors import BuiltinError
        from .vision import VisionError, find_wires

        try:
            began = time.perf_counter()
            result = find_wires(image, method, self.px_per_mm)
            ms = (time.perf_counter() - began) * 1000.0
        except (VisionError, ImageError) as e:
            raise BuiltinError(str(e)) from None
        if self.on_look is not None:
            self.on_look(image, result, ms)
        return result.candidates[0] if result.candidates else None

    @property
    def sim_cell(self):
        """The simulated cell (rcl.cell.SimCell) this session's robot and camera act on, or None."""
        return self._ctx.cell

    @property
    def out(self):
        """Where WRITE and WRITELN go: a text stream (sys.stdout unless `out` was given)."""
        return self._ctx.out

    @out.setter
    def out(self, stream) -> None:
        self._ctx.out = stream

    def cancel(self, reason: str = "cancelled", by_user: bool = False) -> None:
        """Stop the running program at its next loop iteration or call (safe from any thread).
        by_user: it was the user's Ctrl-C (the CLI then exits 130)."""
        self._ctx.cancel(reason, by_user)

    # Variables and built-ins -------------------------------------------------

    def __getitem__(self, name: str) -> Any:
        v = self._scope.variables.get(name.lower())
        if v is None:
            raise KeyError(name)
        if v.kind == "const":
            return v.value
        return _to_python(self._values[v.slot])

    def get(self, name: str, default: Any = None) -> Any:
        try:
            return self[name]
        except KeyError:
            return default

    def __setitem__(self, name: str, value: Any) -> None:
        key = name.lower()
        v = self._scope.variables.get(key)
        if v is None:
            t = _infer_type(value)
            if T.contains_frame(t) and not name.endswith("^"):
                raise TypeError(f"{name} is not a frame name: only names ending in ^ hold frames")
            if name.endswith("^") and not T.contains_frame(t):
                raise TypeError(f"{name} is a frame name; it can only hold a frame")
            if not is_name(name):
                raise ValueError(f"{name!r} is not an RCL name")
            v = self._scope.new_global(name, t, declared=True)
            self._values.append(None)
        elif v.kind == "const":
            raise TypeError(f"{v.name} is a constant")
        assert v.type is not None  # a variable always has one
        self._values[v.slot] = _to_rcl(value, v.type, v.name)

    set = __setitem__

    def variables(self) -> dict[str, str]:
        """Every global variable and constant, as first written, with its type."""
        return {v.name: str(v.type) for v in self._scope.variables.values()}

    def routines(self) -> dict[str, Routine]:
        """Every PROCEDURE and FUNCTION the session knows (its own and its imports'), by lower-case name."""
        return dict(self._scope.routines)

    def register(self, func: Callable, name: str | None = None) -> Builtin:
        """Make a Python function a built-in of this session; its annotations are its RCL signature."""
        b = Builtin.from_function(name or func.__name__, func)
        if b.name.lower() in self._scope.routines:
            raise ValueError(f"{b.name} is already a routine of this session")
        self._scope.builtins = dict(self._scope.builtins)
        self._scope.builtins[b.name.lower()] = b
        return b

    def builtins(self) -> dict[str, Builtin]:
        return {b.name: b for b in self._scope.builtins.values()}

    # Internals ---------------------------------------------------------------

    def _read(self, path: str | Path) -> tuple[str, str]:
        p = Path(path)
        try:
            return read_source(p), str(p.resolve())
        except (OSError, UnicodeDecodeError) as e:
            raise FileNotReadable(describe_read_error(path, e)) from None

    def _check(self, source, filename, key, base):
        self.files.program = Path(os.path.realpath(base))  # the program's own folder, for its files
        with _deep_recursion(), _no_gc_pauses():
            try:
                modules = load(source, filename, key, base, self._scope.modules, self.search_path, self._made,
                               self.files)
            except RclStaticError as e:
                return None, e.diagnostics, None
            scope = self._scope.fork()
            diagnostics = Checker(scope).check(modules)
        return modules, diagnostics, scope

    def _run(self, source: str, filename: str, key: str, base: Path, forget_on_error: bool = False) -> None:
        modules, diagnostics, scope = self._check(source, filename, key, base)
        if diagnostics:
            raise RclStaticError(diagnostics)
        before = (self._scope, len(self._values), set(self._ran))
        # a routine defined again is updated in place (callers compiled earlier hold it): no going back
        redefines = any(self._scope.routines.get(k, r) is not r for k, r in scope.routines.items())
        self._adopt(scope, modules)

        def main():
            code = self._compile(modules)
            if key:
                self._ran.add(key)
            code()
        try:
            self._execute(main, filename, source)
        except (RclRuntimeError, RclCancelled):
            if forget_on_error and not redefines:
                self._scope, self._ran = before[0], before[2]
                del self._values[before[1]:]
            raise

    def _execute(self, action: Callable[[], Any], filename: str, source: str) -> Any:
        """Run compiled code with the robot halted on any error."""
        ctx = self._ctx
        ctx.start(self.step_budget)
        timer = None
        if self.time_limit is not None:
            import threading

            timer = threading.Timer(self.time_limit, ctx.cancel, (f"the time limit of {self.time_limit:g} s is spent",))
            timer.daemon = True
            timer.start()
        try:
            with _deep_recursion(), np.errstate(all="ignore"):
                return action()
        except (RclRuntimeError, RclCancelled):
            self._halt()
            raise
        except KeyboardInterrupt:
            self._halt()
            raise RclCancelled("interrupted (Ctrl-C)", by_user=True) from None
        except RecursionError:
            self._halt()
            raise RclRuntimeError("the program nests too deeply to run", filename, Span(1, 1, 1, 1),
                                  source) from None
        except Exception as e:
            self._halt()
            raise RclInternalError(f"internal error: {type(e).__name__}: {e}") from e
        finally:
            if timer is not None:
                timer.cancel()

    def _adopt(self, scope: GlobalScope, modules) -> None:
        """Make a checked program's declarations the session's (new globals get their initial values)."""
        first_new = len(self._values)
        self._values.extend([None] * (scope.slots - first_new))
        for v in scope.variables.values():
            if v.slot >= first_new and v.declared and v.kind == "var" and v.type is not None:
                self._values[v.slot] = default_factory(v.type)()
        for m in modules:
            if m.key:
                scope.modules[m.key] = m
        old = self._scope.routines
        for key, r in scope.routines.items():
            prior = old.get(key)
            if prior is not None and prior is not r:
                # Redefined with the same signature: callers compiled earlier hold `prior`.
                prior.decl, prior.locals, prior.module, prior.code = r.decl, r.locals, r.module, None
                scope.routines[key] = prior
        self._scope = scope

    def _compile(self, modules):
        compiler = Compiler(self._scope, self._values, self._ctx, self._ran)
        for r in self._scope.routines.values():
            if r.code is None:
                compiler.routine_code(r, r.module)
        for m in modules[1:]:
            compiler.module_codes[m.key] = compiler.module_code(m)
        return compiler.module_code(modules[0])

    def _halt(self) -> None:
        with contextlib.suppress(Exception):
            self.robot.halt()


class FileNotReadable(RclError):
    """A source file that cannot be read (missing, a folder, not UTF-8)."""


@contextlib.contextmanager
def _deep_recursion():
    old = sys.getrecursionlimit()
    sys.setrecursionlimit(max(old, RECURSION_LIMIT))
    try:
        yield
    finally:
        sys.setrecursionlimit(old)


def _assignment_hint(expr, d: Diagnostic) -> Diagnostic:
    """`x = 5` typed as a statement, read as a comparison of an unknown x: say that := assigns."""
    from .ast import BinOp, Name

    if (isinstance(expr, BinOp) and expr.op == "=" and isinstance(expr.left, Name)
            and d.span == expr.left.span and d.message.startswith("unknown name")):
        message = f"unknown name {expr.left.ident.text}; to assign, write {expr.left.ident.text} := ..."
        return Diagnostic(d.filename, d.span, message, d.source_line)
    return d


@contextlib.contextmanager
def _no_gc_pauses():
    """Parsing and checking allocate many objects and free none: the cycle collector, run every
    few hundred allocations, would rescan the growing syntax tree each time (40 % of the time of a
    100,000-line check). It is paused while they run and left as it was."""
    was_on = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_on:
            gc.enable()


def _infer_type(value: Any) -> T.Type:
    if isinstance(value, Frame):
        return T.FRAME
    if isinstance(value, bool):
        return T.BOOLEAN
    if isinstance(value, int):
        return T.INTEGER
    if isinstance(value, float):
        return T.REAL
    if isinstance(value, str):
        return T.STRING
    a = np.asarray(value) if not isinstance(value, (list, tuple)) or _numeric_seq(value) else None
    if a is not None and a.shape == (4, 4):
        return T.FRAME
    if a is not None and a.shape == (3,):
        return T.VECTOR
    if isinstance(value, (list, tuple)) and value:
        return T.ArrayType(_infer_type(value[0]), 0, len(value) - 1)
    raise TypeError(f"no RCL type for {type(value).__name__} values")


def _numeric_seq(value) -> bool:
    try:
        return np.asarray(value, dtype=float).ndim in (1, 2)
    except (TypeError, ValueError):
        return False


def _to_rcl(value: Any, t: T.Type, name: str) -> Any:
    """A Python value as the RCL value of type t, or TypeError/ValueError."""
    try:
        if T.is_frame(t):
            return value if isinstance(value, Frame) else Frame(np.asarray(value, dtype=float))
        if t == T.VECTOR:
            v = np.array(value, dtype=float)
            if v.shape != (3,):
                raise ValueError("a VECTOR has 3 components")
            v.flags.writeable = False
            return v
        if t == T.BOOLEAN and isinstance(value, (bool, np.bool_)):
            return bool(value)
        if t == T.INTEGER and isinstance(value, (int, np.integer)) and not isinstance(value, bool):
            return int(value)
        if t == T.REAL and isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool):
            return float(value)
        if t == T.STRING and isinstance(value, str):
            return value
        if isinstance(t, T.ArrayType) and t.low is not None and t.high is not None \
                and isinstance(value, (list, tuple, Array)):
            items = value.items if isinstance(value, Array) else list(value)
            size = t.high - t.low + 1
            if len(items) != size:
                raise ValueError(f"the array has {size} elements, not {len(items)}")
            return Array(t.low, [_to_rcl(x, t.element, name) for x in items])
    except FrameError as e:
        raise ValueError(f"{name}: {e}") from None
    raise TypeError(f"{name} is {t}; a {type(value).__name__} cannot be stored in it")


def _to_python(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return value.copy()
    if isinstance(value, Array):
        return [_to_python(x) for x in value.items]
    return value
