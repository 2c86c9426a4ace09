"""Load a program: parse the main source and, transitively, every file it IMPORTs.

``IMPORT 'name'`` finds name.rcl beside the importing file, then in the
session's search path, then in the standard library (stdlib/). A session may
also hold modules made in memory (``IMPORT 'cell'``: the frames of its work
cell), found before any file. Each module is loaded once per session, so
import cycles are harmless.
"""
from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path

from . import ast as A
from .errors import Diagnostic, RclStaticError, source_line
from .files import FileRefused, Files, check_name, read_limited
from .parser import parse
from .resources import stdlib_dir


def read_source(path: Path) -> str:
    """A source file's text; OSError, FileRefused or UnicodeDecodeError say what went wrong."""
    return read_limited(path, path).decode("utf-8-sig")


def describe_read_error(path, e: Exception) -> str:
    if isinstance(e, UnicodeDecodeError):
        return f"{path} is not UTF-8 text (byte 0x{e.object[e.start]:02x} at offset {e.start})"
    if isinstance(e, IsADirectoryError):
        return f"{path} is a folder, not a file"
    if isinstance(e, FileRefused):
        return str(e)
    if isinstance(e, OSError):
        return f"cannot read {path}: {e.strerror or e}"
    return f"cannot read {path}: {e}"


def load(source: str, filename: str, key: str, base: Path, known: dict[str, A.Module],
         search: Iterable[Path], made: dict[str, tuple[str, str]] | None = None,
         files: Files | None = None) -> list[A.Module]:
    """[main, new imported modules...]; raises RclStaticError with every load problem.
    made: modules held in memory, by lower-case name: (the name diagnostics show, source);
    files: the folders a program may read (rcl.files)."""
    main = parse(source, filename)
    main.key = key
    modules = [main]
    loaded: dict[str, A.Module] = {key: main} if key else {}
    errors: list[Diagnostic] = []
    queue = [(main, base)]
    while queue:
        module, folder = queue.pop(0)
        for imp in module.imports:
            held = (made or {}).get(imp.name.lower())
            try:
                path = _resolve(imp.name, folder, search, files) if held is None else Path(held[0])
            except FileRefused as e:
                errors.append(_error(module, imp.span, f"IMPORT '{imp.name[:80]}': {e}"))
                continue
            if path is None:
                why = (" (this session has no work cell to give its frames: `rcl run` has one, and "
                       "Session(cell=open_cell()) in Python)" if imp.name.lower() == "cell" else
                       f" (looked for {_file_name(imp.name)} beside this file, in the search path and "
                       f"in the standard library)")
                errors.append(_error(module, imp.span, f"cannot find module '{imp.name}'{why}"))
                continue
            mkey = f"<{imp.name.lower()}>" if held is not None else str(path)
            if mkey in known:
                imp.module = None  # loaded by an earlier run of this session
                continue
            if mkey in loaded:
                imp.module = loaded[mkey]
                continue
            if held is not None:
                shown, text = held
            else:
                try:
                    text = read_source(path)
                except (OSError, FileRefused, UnicodeDecodeError) as e:
                    errors.append(_error(module, imp.span, describe_read_error(path, e)))
                    continue
                shown = _display_name(path)
            try:
                m = parse(text, shown)
            except RclStaticError as e:
                errors.extend(e.diagnostics)
                continue
            m.key = mkey
            loaded[mkey] = m
            imp.module = m
            modules.append(m)
            queue.append((m, path.parent))
    if errors:
        raise RclStaticError(errors)
    return modules


def _file_name(name: str) -> str:
    return name if name.lower().endswith(".rcl") else name + ".rcl"


def _resolve(name: str, folder: Path, search: Iterable[Path], files: Files | None) -> Path | None:
    """The first name.rcl beside the importing file, in the search path, in the standard library;
    FileRefused for a name that is no name, or for a file found outside what files allow."""
    check_name(name)
    file = _file_name(name)
    for d in [folder, *search, stdlib_dir()]:
        candidate = Path(d) / file
        try:
            found = candidate.is_file()
        except (OSError, ValueError):  # a name too long for the file system
            found = False
        if found:
            real = candidate.resolve()
            if files is not None and not files.allowed(real):
                raise FileRefused(f"{real} is outside the folders a program may read: {files.where()}")
            return real
    return None


def _display_name(path: Path) -> str:
    try:
        rel = os.path.relpath(path)
    except ValueError:
        return str(path)
    return str(path) if rel.startswith("..") else rel


def _error(module: A.Module, span: A.Span, message: str) -> Diagnostic:
    return Diagnostic(module.filename, span, message, source_line(module.source, span.line))
