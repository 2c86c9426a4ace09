"""The two camera models of the paper, fitted by least squares.

Image coordinates: u is the column and v the row, in pixels of the image as
stored (pixel (row i, column j) has its centre at u = j, v = i). World
coordinates are millimetres.

- LinearCamera: the 3x4 matrix C of a pinhole camera, C[2, 3] = 1, with
  [u w, v w, w] = C [x, y, z, 1]. It needs points at more than one height.
- BicubicWarp: x = Wx(u, v), y = Wy(u, v), each a full bicubic polynomial,
  sum of a_ij u^i v^j for i, j = 0..3, mapping image points straight onto
  the tray plane z. u and v are normalised to [-1, 1] over the calibration
  points before the powers are formed: raw pixel powers (up to 512^6) make
  the least-squares problem so ill-conditioned that a factor of ten in
  accuracy is lost.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

WARP_TERMS = 16
LINEAR_UNKNOWNS = 11
DEGENERATE = 1e-9  # relative singular value below which a point set does not determine a model


class CameraModelError(ValueError):
    """Points that cannot determine a model, or a model that cannot answer."""


@dataclass
class FitReport:
    """How well a model fits its calibration points (millimetres on the tray)."""

    points: int
    rms: float
    max: float
    loo_rms: float | None  # leave-one-out RMS; None when every point is needed
    residuals: np.ndarray = field(repr=False)  # (N, 2): model minus measured x, y
    condition: float = float("nan")  # condition number of the least-squares design
    loo: np.ndarray | None = field(default=None, repr=False)  # (N,): each point's leave-one-out miss, mm


# Checks shared by both fits -------------------------------------------------


def _as_points(name: str, a, columns: int) -> np.ndarray:
    try:
        arr = np.asarray(a, dtype=float)
    except (TypeError, ValueError):
        raise CameraModelError(f"{name} must be numbers") from None
    if arr.ndim != 2 or arr.shape[1] != columns:
        raise CameraModelError(f"{name} must be {columns} numbers per point")
    bad = np.flatnonzero(~np.all(np.isfinite(arr), axis=1))
    if bad.size:
        raise CameraModelError(f"point {bad[0] + 1} of {name} is not a finite number")
    return arr


def _check_distinct(uv: np.ndarray) -> None:
    _, first, counts = np.unique(uv, axis=0, return_index=True, return_counts=True)
    if np.any(counts > 1):
        k = int(first[np.argmax(counts > 1)])
        again = [i for i in range(len(uv)) if i != k and np.array_equal(uv[i], uv[k])][0]
        raise CameraModelError(f"image points {k + 1} and {again + 1} are the same point: "
                               f"each calibration point must be seen at its own place")


def _check_not_collinear(uv: np.ndarray, what: str) -> None:
    s = np.linalg.svd(uv - uv.mean(axis=0), compute_uv=False)
    if s[0] == 0.0 or s[-1] / s[0] < 1e-6:
        raise CameraModelError(f"the {what} lie on a line: they must spread over the image in both directions")


def _hat_diagonal(a: np.ndarray) -> np.ndarray:
    q, _ = np.linalg.qr(a)
    return np.einsum("ij,ij->i", q, q)


# The bicubic warp -------------------------------------------------------------


@dataclass(frozen=True)
class Normalisation:
    """t -> (t - centre) / half_range, per axis, mapping the calibration points into [-1, 1]."""

    centre: tuple[float, float]
    scale: tuple[float, float]

    @classmethod
    def spanning(cls, pts: np.ndarray) -> Normalisation:
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        half = (hi - lo) / 2.0
        half[half == 0.0] = 1.0
        return cls((float((lo[0] + hi[0]) / 2), float((lo[1] + hi[1]) / 2)), (float(half[0]), float(half[1])))

    def apply(self, a, b) -> tuple[np.ndarray, np.ndarray]:
        return ((np.asarray(a, float) - self.centre[0]) / self.scale[0],
                (np.asarray(b, float) - self.centre[1]) / self.scale[1])


NO_NORMALISATION = Normalisation((0.0, 0.0), (1.0, 1.0))


def bicubic_terms(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The 16 terms a^i b^j (i major: i = 0..3, then j = 0..3), one row per point."""
    pa = np.stack([np.ones_like(a), a, a * a, a * a * a], axis=-1)
    pb = np.stack([np.ones_like(b), b, b * b, b * b * b], axis=-1)
    return (pa[..., :, None] * pb[..., None, :]).reshape(*np.shape(a), WARP_TERMS)


def _bicubic_derivatives(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """d/da and d/db of bicubic_terms."""
    one, zero = np.ones_like(a), np.zeros_like(a)
    pa = np.stack([one, a, a * a, a * a * a], axis=-1)
    pb = np.stack([one, b, b * b, b * b * b], axis=-1)
    da = np.stack([zero, one, 2 * a, 3 * a * a], axis=-1)
    db = np.stack([zero, one, 2 * b, 3 * b * b], axis=-1)
    shape = (*np.shape(a), WARP_TERMS)
    return ((da[..., :, None] * pb[..., None, :]).reshape(shape),
            (pa[..., :, None] * db[..., None, :]).reshape(shape))


@dataclass(frozen=True)
class Bicubic:
    """A pair of bicubic polynomials (p, q) of normalised (a, b)."""

    norm: Normalisation
    p: np.ndarray  # (16,)
    q: np.ndarray  # (16,)

    def __call__(self, a, b) -> tuple[np.ndarray, np.ndarray]:
        t = bicubic_terms(*self.norm.apply(a, b))
        return t @ self.p, t @ self.q

    @classmethod
    def fit(cls, ab: np.ndarray, pq: np.ndarray, normalise: bool = True) -> tuple[Bicubic, np.ndarray, float]:
        """Least squares; also the design matrix and its condition number."""
        norm = Normalisation.spanning(ab) if normalise else NO_NORMALISATION
        design = bicubic_terms(*norm.apply(ab[:, 0], ab[:, 1]))
        coef, *_ = np.linalg.lstsq(design, pq, rcond=None)
        return cls(norm, coef[:, 0], coef[:, 1]), design, float(np.linalg.cond(design))


@dataclass(frozen=True)
class BicubicWarp:
    """Image (u, v) px -> tray (x, y) mm on the plane z, and back."""

    forward: Bicubic  # (u, v) -> (x, y)
    backward: Bicubic  # (x, y) -> (u, v): the starting guess of inverse()
    z: float = 0.0

    def __call__(self, u, v) -> tuple[np.ndarray, np.ndarray]:
        return self.forward(u, v)

    def inverse(self, x, y, iterations: int = 20) -> tuple[np.ndarray, np.ndarray]:
        """The image point that the warp maps to (x, y): Newton's method on the forward warp."""
        x, y = np.asarray(x, float), np.asarray(y, float)
        u, v = self.backward(x, y)
        f, n = self.forward, self.forward.norm
        for _ in range(iterations):
            a, b = n.apply(u, v)
            t = bicubic_terms(a, b)
            ex, ey = t @ f.p - x, t @ f.q - y
            da, db = _bicubic_derivatives(a, b)
            j11, j12 = da @ f.p / n.scale[0], db @ f.p / n.scale[1]
            j21, j22 = da @ f.q / n.scale[0], db @ f.q / n.scale[1]
            det = j11 * j22 - j12 * j21
            det = np.where(det == 0.0, np.nan, det)
            du = (j22 * ex - j12 * ey) / det
            dv = (j11 * ey - j21 * ex) / det
            u, v = u - du, v - dv
            if np.nanmax(np.abs(np.concatenate([np.ravel(du), np.ravel(dv)])), initial=0.0) < 1e-10:
                break
        return u, v

    @classmethod
    def fit(cls, uv, xy, z: float = 0.0, normalise: bool = True) -> tuple[BicubicWarp, FitReport]:
        """The warp from >= 16 correspondences of image points uv (px) and tray points xy (mm)."""
        uv = _as_points("the image points", uv, 2)
        xy = _as_points("the tray points", xy, 2)
        if len(uv) != len(xy):
            raise CameraModelError(f"{len(uv)} image points but {len(xy)} tray points")
        if len(uv) < WARP_TERMS:
            raise CameraModelError(f"a bicubic warp has {WARP_TERMS} terms, so it needs at least "
                                   f"{WARP_TERMS} points, not {len(uv)}")
        _check_distinct(uv)
        _check_not_collinear(uv, "image points")
        _check_not_collinear(xy, "tray points")
        check = bicubic_terms(*Normalisation.spanning(uv).apply(uv[:, 0], uv[:, 1]))
        s = np.linalg.svd(check, compute_uv=False)
        if s[-1] / s[0] < DEGENERATE:
            raise CameraModelError("the points do not determine a bicubic: they must lie on at least "
                                   "4 different rows and 4 different columns of the image, spread out")
        forward, design, cond = Bicubic.fit(uv, xy, normalise)
        backward, _, _ = Bicubic.fit(xy, uv, True)
        warp = cls(forward, backward, float(z))
        residuals = np.stack(warp(uv[:, 0], uv[:, 1]), axis=1) - xy
        return warp, _report(residuals, _hat_diagonal(check), cond)


def _report(residuals: np.ndarray, hat: np.ndarray, cond: float) -> FitReport:
    d = np.hypot(residuals[:, 0], residuals[:, 1])
    loo, misses = None, None
    if np.all(hat < 1.0 - 1e-9):
        e = residuals / (1.0 - hat)[:, None]  # the residual each point would have, left out
        misses = np.hypot(e[:, 0], e[:, 1])
        loo = float(np.sqrt(np.mean(misses * misses)))
    return FitReport(len(d), float(np.sqrt(np.mean(d * d))), float(d.max()), loo, residuals, cond, misses)


# The linear (pinhole) camera -----------------------------------------------------


@dataclass(frozen=True)
class LinearCamera:
    """The 3x4 camera matrix C with C[2, 3] = 1: [u w, v w, w] = C [x, y, z, 1]."""

    C: np.ndarray

    def project(self, x, y, z) -> tuple[np.ndarray, np.ndarray]:
        """World points (mm) to image points (px)."""
        x, y, z = (np.asarray(t, float) for t in (x, y, z))
        c = self.C
        w = c[2, 0] * x + c[2, 1] * y + c[2, 2] * z + c[2, 3]
        return ((c[0, 0] * x + c[0, 1] * y + c[0, 2] * z + c[0, 3]) / w,
                (c[1, 0] * x + c[1, 1] * y + c[1, 2] * z + c[1, 3]) / w)

    def inverse_perspective(self, u, v, z) -> tuple[np.ndarray, np.ndarray]:
        """The world point (x, y) on the plane z that is seen at image point (u, v)."""
        u, v, z = np.broadcast_arrays(*(np.asarray(t, float) for t in (u, v, z)))
        c = self.C
        # u (c31 x + c32 y + c33 z + 1) = c11 x + c12 y + c13 z + c14, likewise v: two linear equations.
        a11, a12 = c[0, 0] - u * c[2, 0], c[0, 1] - u * c[2, 1]
        a21, a22 = c[1, 0] - v * c[2, 0], c[1, 1] - v * c[2, 1]
        b1 = u * (c[2, 2] * z + c[2, 3]) - c[0, 2] * z - c[0, 3]
        b2 = v * (c[2, 2] * z + c[2, 3]) - c[1, 2] * z - c[1, 3]
        det = a11 * a22 - a12 * a21
        if np.any(np.abs(det) < 1e-12 * (np.abs(a11 * a22) + np.abs(a12 * a21) + 1e-300)):
            raise CameraModelError("the camera looks along the plane z: its rays do not cross it")
        return (b1 * a22 - a12 * b2) / det, (a11 * b2 - a21 * b1) / det

    @classmethod
    def fit(cls, xyz, uv) -> tuple[LinearCamera, FitReport]:
        """C from >= 6 world points xyz (mm, not all in one plane) and their image points uv (px)."""
        xyz = _as_points("the world points", xyz, 3)
        uv = _as_points("the image points", uv, 2)
        if len(uv) != len(xyz):
            raise CameraModelError(f"{len(xyz)} world points but {len(uv)} image points")
        if len(uv) < 6:
            raise CameraModelError(f"the 3x4 camera model has {LINEAR_UNKNOWNS} unknowns, so it needs "
                                   f"at least 6 points, not {len(uv)}")
        s = np.linalg.svd(xyz - xyz.mean(axis=0), compute_uv=False)
        if s[0] == 0.0 or s[-1] / s[0] < 1e-6:
            raise CameraModelError("the world points lie in one plane: a flat target cannot determine the "
                                   "3x4 camera model (use points at two or more heights, or the warp)")
        _check_distinct(uv)
        camera, cond = cls._solve(xyz, uv)
        x_hat, y_hat = camera.inverse_perspective(uv[:, 0], uv[:, 1], xyz[:, 2])
        residuals = np.stack([x_hat - xyz[:, 0], y_hat - xyz[:, 1]], axis=1)
        loo: list[float] = []
        if len(uv) > 6:
            for i in range(len(uv)):
                keep = np.arange(len(uv)) != i
                try:
                    other, _ = cls._solve(xyz[keep], uv[keep])
                    xi, yi = other.inverse_perspective(uv[i, 0], uv[i, 1], xyz[i, 2])
                except CameraModelError:
                    loo = []
                    break
                loo.append((float(xi) - xyz[i, 0]) ** 2 + (float(yi) - xyz[i, 1]) ** 2)
        report = _report(residuals, np.zeros(len(uv)), cond)
        report.loo_rms = float(np.sqrt(np.mean(loo))) if loo else None
        return camera, report

    @classmethod
    def _solve(cls, xyz: np.ndarray, uv: np.ndarray) -> tuple[LinearCamera, float]:
        # The paper's least squares with C[2, 3] = 1: 2 equations per point in the 11 other entries.
        n = len(uv)
        x, y, z = xyz.T
        u, v = uv.T
        zero, one = np.zeros(n), np.ones(n)
        rows_u = np.stack([x, y, z, one, zero, zero, zero, zero, -u * x, -u * y, -u * z], axis=1)
        rows_v = np.stack([zero, zero, zero, zero, x, y, z, one, -v * x, -v * y, -v * z], axis=1)
        a = np.concatenate([rows_u, rows_v])
        b = np.concatenate([u, v])
        scale = np.linalg.norm(a, axis=0)  # equilibrate the columns: the same solution, well conditioned
        scale[scale == 0.0] = 1.0
        s = np.linalg.svd(a / scale, compute_uv=False)
        if s[-1] / s[0] < DEGENERATE:
            raise CameraModelError("the points do not determine the 3x4 camera model (too few distinct "
                                   "directions: spread them over the image and over two or more heights)")
        c, *_ = np.linalg.lstsq(a / scale, b, rcond=None)
        c = c / scale
        return cls(np.append(c, 1.0).reshape(3, 4)), float(s[0] / s[-1])
