"""A simulated camera: a pinhole with radial lens distortion, tilted over the tray.

It maps world points (mm) to image points (px, u = column, v = row) the way a
real camera would, imperfections included, and renders simple scenes. The
calibration benchmark and the tests use it; the simulated work cell renders
with it.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..frame import Frame


@dataclass(frozen=True)
class PinholeCamera:
    """pose: the camera frame in the world (it looks along its own +Z, image v along its +Y).
    k1, k2: radial distortion of the normalised image coordinates, r' = r (1 + k1 r^2 + k2 r^4)."""

    width: int
    height: int
    focal_px: float
    pose: np.ndarray
    k1: float = 0.0
    k2: float = 0.0

    @classmethod
    def over_tray(cls, centre_xy=(0.0, 0.0), height_mm: float = 600.0, fov_mm: float = 220.0,
                  width: int = 512, tilt_deg: float = 0.0, k1: float = 0.0, k2: float = 0.0) -> PinholeCamera:
        """A camera height_mm above the tray point centre_xy, seeing about fov_mm across,
        its optical axis tilted by tilt_deg about the world Y axis."""
        pose = (Frame.trans(centre_xy[0], centre_xy[1], 0.0) * Frame.roty(tilt_deg)
                * Frame.trans(0.0, 0.0, height_mm) * Frame.rotx(180.0))
        focal = width * height_mm / fov_mm
        return cls(width, width, focal, pose.matrix.copy(), k1, k2)

    def project(self, x, y, z) -> tuple[np.ndarray, np.ndarray]:
        """World points to (distorted) image points."""
        pts = np.stack(np.broadcast_arrays(*(np.asarray(t, float) for t in (x, y, z))), axis=-1)
        inv = np.linalg.inv(self.pose)
        cam = pts @ inv[:3, :3].T + inv[:3, 3]
        xn, yn = cam[..., 0] / cam[..., 2], cam[..., 1] / cam[..., 2]
        r2 = xn * xn + yn * yn
        f = 1.0 + self.k1 * r2 + self.k2 * r2 * r2
        cx, cy = (self.width - 1) / 2.0, (self.height - 1) / 2.0
        return cx + self.focal_px * xn * f, cy + self.focal_px * yn * f

    def depth(self, x, y, z) -> np.ndarray:
        """Distance along the optical axis, mm (for the size of things in the image)."""
        p = np.stack(np.broadcast_arrays(*(np.asarray(t, float) for t in (x, y, z))), axis=-1)
        inv = np.linalg.inv(self.pose)
        return (p @ inv[:3, :3].T + inv[:3, 3])[..., 2]


def render_disc(shape: tuple[int, int], centre_uv: tuple[float, float], radius_px: float,
                level: float, background: float = 0.5, supersample: int = 8) -> np.ndarray:
    """An image of a uniform disc with exactly anti-aliased edges (area coverage, supersampled)."""
    img = np.full(shape, float(background))
    u0, v0 = centre_uv
    r = radius_px
    r0, r1 = max(int(np.floor(v0 - r - 1)), 0), min(int(np.ceil(v0 + r + 2)), shape[0])
    c0, c1 = max(int(np.floor(u0 - r - 1)), 0), min(int(np.ceil(u0 + r + 2)), shape[1])
    if r0 >= r1 or c0 >= c1:
        return img
    offsets = (np.arange(supersample) + 0.5) / supersample - 0.5
    rows = np.arange(r0, r1)[:, None, None, None] + offsets[None, None, :, None]
    cols = np.arange(c0, c1)[None, :, None, None] + offsets[None, None, None, :]
    inside = (cols - u0) ** 2 + (rows - v0) ** 2 <= r * r
    coverage = inside.mean(axis=(2, 3))
    img[r0:r1, c0:c1] = background + (level - background) * coverage
    return img
