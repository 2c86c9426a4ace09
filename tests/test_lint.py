"""The code passes ruff with the project's rules ([tool.ruff] in pyproject.toml): CI runs it
through this test, so the README's one test command checks lint too."""
from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


def test_ruff_finds_nothing():
    try:
        import ruff  # noqa: F401 - installed with the test extra
    except ImportError:
        if shutil.which("ruff") is None:
            pytest.skip("ruff is not installed (pip install '.[test]')")
    r = subprocess.run([sys.executable, "-m", "ruff", "check", "--no-cache", "rcl", "tests", "benchmarks"],
                       cwd=ROOT, capture_output=True, text=True, check=False)
    assert r.returncode == 0, r.stdout + r.stderr
