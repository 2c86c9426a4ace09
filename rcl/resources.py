"""Where the grammar and the RCL standard library live.

In an installed wheel they sit inside the package (rcl/grammar, rcl/stdlib);
in a source checkout they are the top-level grammar/ and stdlib/ folders.
"""
from __future__ import annotations

from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent


def _data_dir(name: str) -> Path:
    inside = _PACKAGE / name
    if inside.is_dir():
        return inside
    return _PACKAGE.parent / name


def grammar_path() -> Path:
    return _data_dir("grammar") / "rcl.lark"


def docs_dir() -> Path:
    """The project's docs (the language reference for the REPL's :help)."""
    return _data_dir("docs")


def stdlib_dir() -> Path:
    return _data_dir("stdlib")
