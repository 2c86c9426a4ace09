"""Every example runs on the simulator, and the standard library passes the checker."""
from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pytest

from conftest import ROOT
from rcl import Session

EXAMPLES = sorted((ROOT / "examples").glob("*.rcl"))
STDLIB = sorted((ROOT / "stdlib").glob("*.rcl"))


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_example_runs(path: Path):
    out = io.StringIO()
    s = Session(out=out, step_budget=10_000_000)
    s.run_file(path)
    assert out.getvalue().endswith("\n")
    assert not s.robot.halted


@pytest.mark.parametrize("path", STDLIB, ids=lambda p: p.name)
def test_stdlib_passes_the_checker(path: Path):
    assert Session().check_file(path) == []


def test_the_pick_example_moves_through_the_solved_frames():
    s = Session(out=io.StringIO())
    s.run_file(ROOT / "examples" / "pick.rcl")
    moves = [e for e in s.robot.log if e[0] in ("move", "moves")]
    assert len(moves) == 3 * 4
    # the last grasp (Z^ is the identity): the fingers, E^ beyond T5, are on the wire
    # 15 mm from its end, pointing straight down into the tray
    w = s["W^"].matrix
    fingers = moves[-3][1] @ s["E^"].matrix
    np.testing.assert_allclose(fingers[:3, 3], w[:3, 3] + 15 * w[:3, 2], atol=1e-9)
    np.testing.assert_allclose(fingers[:3, 2], [0, 0, -1], atol=1e-12)
    assert abs(fingers[:3, 1] @ w[:3, 2]) < 1e-12  # the fingers close across the wire
