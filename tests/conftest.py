"""Shared helpers: run the `rcl` command as a user would."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


def rcl(*args: str, cwd=None, timeout: float = 60, input: str | None = None) -> subprocess.CompletedProcess:
    """Run `python -m rcl ARGS` and capture its output."""
    return subprocess.run([sys.executable, "-m", "rcl", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=timeout, input=input, stdin=None if input is not None else subprocess.DEVNULL)


@pytest.fixture
def write(tmp_path):
    """write('name.rcl', text) -> path of a new file in a fresh folder."""
    def make(name: str, text: str) -> Path:
        path = tmp_path / name
        path.write_text(text)
        return path
    return make
