"""Every example runs on the simulator, and the standard library passes the checker."""
from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pytest

from conftest import ROOT, MarkerCamera
from rcl import Session
from rcl.camera import Calibration
from rcl.robots import SimRobot

EXAMPLES = sorted((ROOT / "examples").glob("*.rcl"))
STDLIB = sorted((ROOT / "stdlib").glob("*.rcl"))


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_example_runs(path: Path, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # examples may write files (calibrate.rcl: warp.json)
    out = io.StringIO()
    robot = SimRobot()
    s = Session(out=out, step_budget=10_000_000, robot=robot, camera=MarkerCamera(robot))
    s.run_file(path)
    assert out.getvalue().endswith("\n")
    assert not s.robot.halted


def test_calibrate_example_fits_a_warp_that_absorbs_distortion_and_robot_error(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    robot = SimRobot()

    def error(x, y):  # the arm lands 1-3 mm off, smoothly varying over the tray
        return 1.5 + np.sin(x / 90.0), -1.0 + 0.8 * np.cos(y / 70.0)
    camera = MarkerCamera(robot, error=error)
    out = io.StringIO()
    s = Session(out=out, robot=robot, camera=camera)
    s.run_file(ROOT / "examples" / "calibrate.rcl")
    assert "warp fitted to 36 points" in out.getvalue()
    assert (tmp_path / "warp.json").exists()
    # held out: where must the robot be sent so that the marker is seen at (u, v)?
    cal = Calibration()
    cal.load(tmp_path / "warp.json")
    rng = np.random.default_rng(3)
    errors = []
    for x, y in rng.uniform([270, -80], [430, 80], size=(50, 2)):
        dx, dy = error(x, y)
        u, v = camera.camera.project(x + dx, y + dy, 0.0)
        wx, wy, _ = cal.warp(float(u), float(v))
        errors.append(np.hypot(wx - x, wy - y))
    assert np.sqrt(np.mean(np.square(errors))) < 0.1


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
