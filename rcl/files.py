"""Which files a program may touch.

An RCL program names files in three places: IMPORT, LOADWARP and SAVEWARP.
A program reads and writes only inside its own folder and the folders its
session declares: data folders (`rcl run --data DIR`, the cell file's folder)
for reading and writing, the search path (IMPORT) and the standard library for
reading. A name is resolved with every symlink followed before it is judged, so
neither `..` nor a link leads out. Only regular files are read (not a device, a
pipe or a folder), and none larger than MAX_BYTES; a name holding NUL, or longer
than MAX_NAME characters, is refused. The embedding API may widen this:
Session(any_file=True) lets a program name any path the user may.

A relative name in LOADWARP or SAVEWARP starts in the first data folder, or in
the program's own folder when there is none (IMPORT looks beside the importing
file first, as before).
"""
from __future__ import annotations

import os
import stat
from collections.abc import Iterable
from pathlib import Path

MAX_NAME = 1024  # characters in a file name as the program gives it
MAX_BYTES = 64 * 1024 * 1024  # the largest file a program may read


class FileRefused(Exception):
    """A file the program may not touch, or a name that is no name; the message says why."""


class Files:
    """The folders a session's programs may read and write (resolved, symlinks followed)."""

    def __init__(self, data: Iterable[str | Path] = (), search: Iterable[str | Path] = (),
                 anywhere: bool = False) -> None:
        from .resources import stdlib_dir

        self.data = [_real(p) for p in data]
        self.search = [_real(p) for p in search]
        self.stdlib = _real(stdlib_dir())
        self.anywhere = anywhere
        self.program: Path | None = None  # the running program's folder (set by the session)

    def _own(self) -> Path:
        """The program's folder (the working folder before a program has run)."""
        return self.program if self.program is not None else _real(Path.cwd())

    def home(self) -> Path:
        """Where a relative name starts: the first data folder, else the program's folder."""
        return self.data[0] if self.data else self._own()

    def _roots(self, writing: bool) -> list[Path]:
        mine = [self._own(), *self.data]
        return mine if writing else [*mine, *self.search, self.stdlib]

    def allowed(self, path: Path, writing: bool = False) -> bool:
        """Whether a resolved path lies inside a folder programs may read (or write)."""
        return self.anywhere or any(path == r or path.is_relative_to(r) for r in self._roots(writing))

    def where(self, writing: bool = False) -> str:
        """The allowed folders, for a message."""
        what = ["the program's folder"]
        if self.data:
            what.append("the data folder" + ("s" if len(self.data) > 1 else "") + " ("
                        + ", ".join(str(d) for d in self.data) + ")")
        if not writing:
            what.append("the search path and the standard library" if self.search else "the standard library")
        return ", ".join(what[:-1]) + " and " + what[-1] if len(what) > 1 else what[0]

    def resolve(self, name: str, writing: bool = False) -> Path:
        """The real path a program's file name stands for; FileRefused if it may not be touched."""
        check_name(name)
        path = _real(self.home() / name)
        if not self.allowed(path, writing):
            raise FileRefused(f"{name!r} is outside the folders a program may "
                              f"{'write' if writing else 'read'}: {self.where(writing)}")
        if writing and path.exists() and not path.is_file():
            raise FileRefused(f"{name!r} is not a regular file")
        return path


def check_name(name: str) -> None:
    """FileRefused unless name could name a file."""
    if not name:
        raise FileRefused("an empty file name")
    if "\0" in name:
        raise FileRefused(f"a file name with a NUL character in it: {name[:60]!r}")
    if len(name) > MAX_NAME:
        raise FileRefused(f"a file name of {len(name)} characters (at most {MAX_NAME})")


def read_limited(path: Path, shown: str | Path, limit: int = MAX_BYTES) -> bytes:
    """The bytes of a regular file of at most limit bytes; FileRefused or OSError say why not."""
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))  # a pipe must not block the open
    with open(fd, "rb") as f:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            kind = "a folder" if stat.S_ISDIR(info.st_mode) else "a device, pipe or socket"
            raise FileRefused(f"{shown} is {kind}, not a regular file")
        data = f.read(limit + 1)
    if len(data) > limit:
        raise FileRefused(f"{shown} is larger than {limit // (1024 * 1024)} MB")
    return data


def _real(p: str | Path) -> Path:
    """The path with every symlink followed, absolute (it need not exist)."""
    try:
        return Path(os.path.realpath(p))
    except (OSError, ValueError) as e:
        raise FileRefused(f"{p}: {e}") from None
