"""The simulated cell: the camera's view of the tray."""
from __future__ import annotations

import numpy as np

from rcl.camera.simulated import PinholeCamera
from rcl.cell import TrayView


def test_every_pixel_looks_where_the_camera_projects_it():
    cam = PinholeCamera.over_tray(centre_xy=(300.0, 0.0), height_mm=500.0, fov_mm=140.0, tilt_deg=8.0,
                                  k1=-0.08, k2=0.02)
    view = TrayView(cam, tray_z=-20.0)
    rng = np.random.default_rng(0)
    v = rng.integers(0, cam.height, 200)
    u = rng.integers(0, cam.width, 200)
    x, y = view.x[v, u], view.y[v, u]
    pu, pv = cam.project(x, y, np.full_like(x, -20.0))
    np.testing.assert_allclose(pu, u, atol=1e-6)
    np.testing.assert_allclose(pv, v, atol=1e-6)


def test_a_look_resamples_a_tray_picture_through_the_optics():
    cam = PinholeCamera.over_tray(centre_xy=(64.0, 64.0), height_mm=500.0, fov_mm=140.0, tilt_deg=5.0, k1=-0.05)
    view = TrayView(cam)
    picture = np.full((1024, 1024), 0.8)
    picture[400:420, 600:620] = 0.2  # a 2.5 mm dark square at x 75-77.5, y 50-52.5 (8 px/mm)
    image = view.look(picture, (0.0, 0.0), 8.0)
    dark = image < 0.5
    rows, cols = np.nonzero(dark)
    x, y = view.where(cols.mean(), rows.mean())
    assert abs(x - 76.25) < 0.3 and abs(y - 51.25) < 0.3
    assert image[0, 0] == 0.8 or abs(image[0, 0] - 0.8) < 1e-9
