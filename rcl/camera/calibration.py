"""Calibration: the camera model a session works with, and the points it is fitted to.

This is what the RCL built-ins CALPOINT, FITWARP, SAVEWARP, LOADWARP and WARP
drive; it is plain Python and usable without RCL.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from . import fileformat
from .models import BicubicWarp, CameraModelError, FitReport, LinearCamera

OUTLIER_MM = 2.0  # a point the fit of the others misses by this much (mm) ...
OUTLIER_TIMES = 10.0  # ... and by this many times the median point's miss: the marker was found on something else
KEEP_AT_LEAST = 20  # points never left out below this many (the warp's 16 terms, and some to spare)


class Calibration:
    """Correspondences (u, v) px <-> (x, y) mm on the tray plane z, and the fitted model."""

    def __init__(self, z: float = 0.0) -> None:
        self.z = float(z)  # the tray plane, mm
        self.points: list[tuple[float, float, float, float]] = []
        self.model: BicubicWarp | LinearCamera | None = None
        self.report: FitReport | None = None
        self.left_out: list[tuple[int, float]] = []  # (index into points, mm the others' fit misses it by)

    def add_point(self, u: float, v: float, x: float, y: float) -> None:
        values = np.array([u, v, x, y], dtype=float)
        if not np.all(np.isfinite(values)):
            raise CameraModelError(f"a calibration point must be finite numbers, not ({u}, {v}, {x}, {y})")
        self.points.append((float(values[0]), float(values[1]), float(values[2]), float(values[3])))

    def fit(self) -> float:
        """Fit the bicubic warp to the points added; the RMS residual in mm of the points kept.

        A point that the fit of all the others misses grossly (by OUTLIER_MM and by OUTLIER_TIMES
        the median point's miss: its leave-one-out residual) is left out, the worst first, one at
        a time, while more than KEEP_AT_LEAST remain: where the marker finder took something else
        for the marker (a dark hole in a loop of light wire), one such pair would pull the whole
        warp off by millimetres. `left_out` says which were left out."""
        if not self.points:
            raise CameraModelError("no calibration points yet: add them with CALPOINT(u, v, x, y)")
        pts = np.array(self.points)
        kept = list(range(len(pts)))
        self.left_out = []
        model, report = BicubicWarp.fit(pts[:, :2], pts[:, 2:], self.z)
        while report.loo is not None and len(kept) > KEEP_AT_LEAST:
            worst = int(np.argmax(report.loo))
            miss = float(report.loo[worst])
            if miss < max(OUTLIER_MM, OUTLIER_TIMES * float(np.median(report.loo))):
                break
            rest = kept[:worst] + kept[worst + 1:]
            try:
                model, report = BicubicWarp.fit(pts[rest, :2], pts[rest, 2:], self.z)
            except CameraModelError:  # (the others alone do not determine a warp: keep it)
                break
            self.left_out.append((kept[worst], miss))
            kept = rest
        self.model, self.report = model, report
        return report.rms

    def save(self, path: str | Path) -> None:
        if self.model is None:
            raise CameraModelError("no camera model to save: fit one first (FITWARP)")
        fileformat.save(path, self.model, self.z, self.report)

    def load(self, path: str | Path) -> None:
        self.model, self.z, self.report = fileformat.load(path)

    def warp(self, u: float, v: float) -> tuple[float, float, float]:
        """The tray-plane point (x, y, z) mm seen at image point (u, v) px."""
        if self.model is None:
            raise CameraModelError("no camera model yet: fit one (CALPOINT, then FITWARP) or load one (LOADWARP)")
        if isinstance(self.model, BicubicWarp):
            x, y = self.model(u, v)
        else:
            x, y = self.model.inverse_perspective(u, v, self.z)
        return float(x), float(y), self.z

    def unwarp(self, x: float, y: float) -> tuple[float, float]:
        """The image point (u, v) px at which the tray point (x, y) is seen."""
        if self.model is None:
            raise CameraModelError("no camera model yet")
        if isinstance(self.model, BicubicWarp):
            u, v = self.model.inverse(x, y)
        else:
            u, v = self.model.project(x, y, self.z)
        return float(u), float(v)
