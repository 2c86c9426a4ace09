"""What a real camera over the tray sees: each image pixel's ray met with the tray plane.

A TrayView pairs a simulated camera (tilted, with radial distortion) with the
tray's plane and computes, once, where every pixel looks on the tray; a look is
then one resampling of a picture of the tray drawn in tray millimetres.
"""
from __future__ import annotations

import numpy as np

from ..camera.simulated import PinholeCamera


class TrayView:
    """The camera's view of the plane z = tray_z; tray pictures have their pixel (0, 0)
    at world (origin_x, origin_y) and px_per_mm pixels to the millimetre."""

    def __init__(self, camera: PinholeCamera, tray_z: float = 0.0) -> None:
        self.camera = camera
        self.tray_z = float(tray_z)
        self.x, self.y = self._rays_to_plane()

    def _rays_to_plane(self) -> tuple[np.ndarray, np.ndarray]:
        cam = self.camera
        v, u = np.mgrid[0:cam.height, 0:cam.width].astype(float)
        cx, cy = (cam.width - 1) / 2.0, (cam.height - 1) / 2.0
        xd, yd = (u - cx) / cam.focal_px, (v - cy) / cam.focal_px
        # undo the radial distortion: r_d = r (1 + k1 r^2 + k2 r^4), by fixed-point iteration
        xn, yn = xd.copy(), yd.copy()
        for _ in range(30):
            r2 = xn * xn + yn * yn
            f = 1.0 + cam.k1 * r2 + cam.k2 * r2 * r2
            xn, yn = xd / f, yd / f
        pose = np.asarray(cam.pose)
        rays = np.stack([xn, yn, np.ones_like(xn)], axis=-1) @ pose[:3, :3].T
        origin = pose[:3, 3]
        t = (self.tray_z - origin[2]) / rays[..., 2]
        return origin[0] + t * rays[..., 0], origin[1] + t * rays[..., 1]

    def look(self, picture: np.ndarray, origin_xy: tuple[float, float], px_per_mm: float,
             background: float | tuple = 0.8) -> np.ndarray:
        """The camera image of a tray picture (grey (H, W) or colour (H, W, 3), values 0-1)."""
        from scipy import ndimage

        cols = (self.x - origin_xy[0]) * px_per_mm - 0.5
        rows = (self.y - origin_xy[1]) * px_per_mm - 0.5
        if picture.ndim == 2:
            grey = float(np.mean(background))  # a colour background on a grey picture: its grey
            return ndimage.map_coordinates(picture, [rows, cols], order=1, mode="constant", cval=grey)
        bg = np.broadcast_to(np.asarray(background, float), (picture.shape[2],))
        return np.stack([ndimage.map_coordinates(picture[..., c], [rows, cols], order=1, mode="constant",
                                                 cval=float(bg[c])) for c in range(picture.shape[2])], axis=-1)

    def where(self, u: float, v: float) -> tuple[float, float]:
        """The tray point (x, y) that pixel (u, v) sees (bilinear between pixel centres)."""
        from scipy import ndimage

        at = [[v], [u]]
        return (float(ndimage.map_coordinates(self.x, at, order=1, mode="nearest")[0]),
                float(ndimage.map_coordinates(self.y, at, order=1, mode="nearest")[0]))
