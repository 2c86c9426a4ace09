"""Shared helpers: run the `rcl` command as a user would; hypothesis without its per-example
deadline (no test is timed: a busy machine must not fail one)."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import settings

settings.register_profile("untimed", deadline=None)
settings.load_profile("untimed")

ROOT = Path(__file__).resolve().parent.parent


def benchmark(name: str):
    """benchmarks/NAME.py as a module (benchmarks/ is no package: loaded by path)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(f"benchmark_{name}", ROOT / "benchmarks" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


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


class MarkerCamera:
    """A scripted camera for tests: it renders the marker disc carried by the arm where
    the arm's (recorded) pose puts it, seen through a simulated camera, optionally with
    the arm's real position off from the commanded one by error(x, y) -> (dx, dy)."""

    def __init__(self, robot, camera=None, marker=None, error=None, noise=0.01, seed=0):
        import numpy as np

        from rcl.camera.simulated import PinholeCamera

        self.robot = robot
        self.camera = camera or PinholeCamera.over_tray(centre_xy=(350.0, 0.0), height_mm=600.0,
                                                       tilt_deg=8.0, k1=-0.04)
        self.marker = marker if marker is not None else np.array([[1, 0, 0, 0], [0, 1, 0, 0],
                                                                  [0, 0, 1, 130], [0, 0, 0, 1.0]])
        self.error = error
        self.noise = noise
        self.rng = np.random.default_rng(seed)

    def marker_position(self):
        p = (self.robot.here() @ self.marker)[:3, 3].copy()
        if self.error is not None:
            dx, dy = self.error(p[0], p[1])
            p[0] += dx
            p[1] += dy
        return p

    def grab(self):
        from rcl.camera.simulated import render_disc

        x, y, z = self.marker_position()
        u, v = self.camera.project(x, y, z)
        radius = 4.0 * self.camera.focal_px / float(self.camera.depth(x, y, z))  # a 4 mm disc
        img = render_disc((self.camera.height, self.camera.width), (float(u), float(v)), radius, 0.9, 0.35)
        return img + self.rng.normal(0.0, self.noise, img.shape)


def lit_wires(wires, size=(512, 512), ppm=4.0, board=0.8, gloss=0.5, shadow=0.25, lamp=(0.5, 0.3, 0.81)):
    """An image of straight dark wires on a plain board, lit from one side: each round wire
    shaded with a specular line along it and casting a soft shadow. wires: (tip (x, y) mm,
    angle deg, length mm, width mm) each. Returns the grey image and each wire's centre line
    (mm, from its tip)."""
    import math

    import numpy as np

    from rcl.vision.scenes import Scene, WireLook, finish, paint
    from rcl.vision.synth import Wire

    drawn, looks, lines = [], [], []
    for i, (tip, angle, length, width) in enumerate(wires):
        d = np.array([math.cos(math.radians(angle)), math.sin(math.radians(angle))])
        centre = np.array(tip, float) + np.arange(0.0, length, 0.5)[:, None] * d
        drawn.append(Wire(centre, width, i, (0.1,)))
        looks.append(WireLook("black", (0.1, 0.1, 0.1), ("flat", "flat"), (0.0, 0.0), gloss))
        lines.append(centre)
    h, w = size
    lamp = np.array(lamp) / np.linalg.norm(lamp)
    scene = Scene(w, h, ppm, False, len(wires), len(wires), ("straight",), (1.0, 3.0), ("black",), ("flat",),
                  "plain", (board,) * 3, 0.0, (0.0, 0.0, 0.0), tuple(lamp), shadow, 0.0, 0.0, 0.01, 0, False,
                  0, 0.0, False)
    under = np.broadcast_to(np.array((board,) * 3, np.float32), (h, w, 3)).copy()
    image = finish(scene, paint(scene, drawn, looks, under), np.random.default_rng(0))
    return image.mean(axis=2) if image.ndim == 3 else image, lines


def assert_both_ends_at_tips(candidates, centre, ppm: float = 4.0) -> None:
    """Both ends of a straight wire drawn by lit_wires (its centre line in mm, from one tip to the
    other) are among the candidates: each within 0.8 mm of its tip, pointing into the wire to
    10 degrees."""
    import math

    import numpy as np

    for tip, inward in ((centre[0], centre[1] - centre[0]), (centre[-1], centre[-2] - centre[-1])):
        near = [s for s in candidates if np.linalg.norm(np.array(s.end) / ppm - tip) < 3.0]
        assert near, f"the end at {tip} is not seen"
        assert np.linalg.norm(np.array(near[0].end) / ppm - tip) < 0.8
        a = math.radians(near[0].end_angle)
        assert np.dot([math.cos(a), math.sin(a)], inward / np.linalg.norm(inward)) > math.cos(math.radians(10))
