"""Camera calibration accuracy, the paper's way. Run by hand: python benchmarks/calibration.py

A simulated camera (tilted, with radial lens distortion of several mm at the
corners) watches a robot whose real position differs smoothly from the
commanded one by 1-3 mm. The robot carries the marker over a 6 x 6 grid; each
image is rendered and the marker found in it (rcl.camera.find_mark), giving 36
pairs (image point, commanded point). Models fitted to them are judged on 400
held-out commanded points: the error is how far the model's answer is from
where the robot must be commanded so that the marker is seen there.

Models: the bicubic warp (normalised, as rcl fits it), the same warp on raw
pixel powers, the linear 3x4 camera (it needs two heights, so the grid is
visited at z = 0 and z = 40 mm: 72 points) and a plane homography.
"""
from __future__ import annotations

import numpy as np

from rcl.camera import BicubicWarp, LinearCamera, find_mark
from rcl.camera.simulated import PinholeCamera, render_disc

CENTRE = (350.0, 0.0)
HALF = 90.0  # the grid spans CENTRE +- HALF mm
MARKER_MM = 4.0
NOISE = 0.01  # image noise, in units of the full grey range



def robot_error(x, y):
    """Where the arm really goes minus where it was told to: smooth, 1-3 mm."""
    s, t = (np.asarray(x) - CENTRE[0]) / HALF, (np.asarray(y) - CENTRE[1]) / HALF
    return (1.7 + 0.8 * np.sin(1.3 * s + 0.4) * np.cos(1.1 * t),
            -1.1 + 0.7 * np.cos(1.2 * s) * np.sin(1.4 * t + 1.0) + 0.3 * s * t)


def cameras():
    straight = PinholeCamera.over_tray(CENTRE, height_mm=600, fov_mm=220, tilt_deg=10)
    return straight, PinholeCamera.over_tray(CENTRE, height_mm=600, fov_mm=220, tilt_deg=10, k1=-0.45)


def seen(camera, x, y, z, rng, with_error=True):
    """The image point at which the marker commanded to (x, y, z) is found."""
    dx, dy = robot_error(x, y) if with_error else (0.0, 0.0)
    u, v = camera.project(x + dx, y + dy, z)
    radius = MARKER_MM * camera.focal_px / float(camera.depth(x + dx, y + dy, z))
    img = render_disc((camera.height, camera.width), (float(u), float(v)), radius, 0.9, 0.35)
    img += rng.normal(0.0, NOISE, img.shape)
    found = find_mark(img)
    assert found is not None, (x, y, z)
    return found


def fit_homography(uv, xy):
    """The plane homography (u, v) -> (x, y), by the normalised direct linear transform."""
    def normaliser(p):
        c = p.mean(axis=0)
        s = np.sqrt(2) / np.mean(np.linalg.norm(p - c, axis=1))
        return np.array([[s, 0, -s * c[0]], [0, s, -s * c[1]], [0, 0, 1]])
    ta, tb = normaliser(uv), normaliser(xy)
    a = np.c_[uv, np.ones(len(uv))] @ ta.T
    b = np.c_[xy, np.ones(len(xy))] @ tb.T
    rows = []
    for (u, v, w), (x, y, _) in zip(a, b):
        rows.append([u, v, w, 0, 0, 0, -x * u, -x * v, -x * w])
        rows.append([0, 0, 0, u, v, w, -y * u, -y * v, -y * w])
    h = np.linalg.svd(np.array(rows))[2][-1].reshape(3, 3)
    h = np.linalg.inv(tb) @ h @ ta

    def apply(u, v):
        p = np.stack([u, v, np.ones_like(u)]).T @ h.T
        return p[:, 0] / p[:, 2], p[:, 1] / p[:, 2]
    return apply


def evaluate(name, predict, cal_points, held, fit_rms, condition=None):
    uv, xy = held
    px, py = predict(uv[:, 0], uv[:, 1])
    d = np.hypot(px - xy[:, 0], py - xy[:, 1])
    cond = f"{condition:9.1e}" if condition is not None else f"{'-':>9}"
    print(f"{name:<34} {cal_points:>6} {fit_rms:9.4f} {np.sqrt(np.mean(d * d)):9.4f} {d.max():9.4f} {cond}")


def main() -> None:
    # benchmarks/machine.py, imported here as tests load some of these files as modules
    from machine import describe

    print(describe())
    rng = np.random.default_rng(2024)
    straight, camera = cameras()
    corners = np.array([[CENTRE[0] + sx * HALF, CENTRE[1] + sy * HALF] for sx in (-1, 1) for sy in (-1, 1)])
    ud, vd = camera.project(corners[:, 0], corners[:, 1], 0 * corners[:, 0])
    us, vs = straight.project(corners[:, 0], corners[:, 1], 0 * corners[:, 0])
    mm_per_px = 2 * HALF / np.ptp(us)
    shift = np.hypot(ud - us, vd - vs) * mm_per_px
    g = np.linspace(-HALF, HALF, 61)
    ex, ey = robot_error(*np.meshgrid(CENTRE[0] + g, CENTRE[1] + g))
    mag = np.hypot(ex, ey)
    print(f"camera: 512 x 512 px, {1 / mm_per_px:.2f} px/mm, tilted 10 degrees; lens distortion at the "
          f"grid corners {shift.min():.1f}-{shift.max():.1f} mm")
    print(f"robot: real minus commanded position {mag.min():.2f}-{mag.max():.2f} mm over the tray")

    grid = np.linspace(-HALF, HALF, 6)
    cmd = np.array([(CENTRE[0] + a, CENTRE[1] + b) for a in grid for b in grid])
    held_cmd = np.c_[rng.uniform(CENTRE[0] - HALF, CENTRE[0] + HALF, 400),
                     rng.uniform(CENTRE[1] - HALF, CENTRE[1] + HALF, 400)]

    for title, with_error in (("camera + robot error (the paper's situation)", True),
                              ("camera only (the robot goes exactly where told)", False)):
        print(f"\n{title}; held out: 400 random points, marker found in rendered images")
        uv = np.array([seen(camera, x, y, 0.0, rng, with_error) for x, y in cmd])
        uv40 = np.array([seen(camera, x, y, 40.0, rng, with_error) for x, y in cmd])
        held_uv = np.array([seen(camera, x, y, 0.0, rng, with_error) for x, y in held_cmd])
        held = (held_uv, held_cmd)
        print(f"{'model':<34} {'points':>6} {'fit rms':>9} {'held rms':>9} {'held max':>9} {'condition':>9}   (mm)")
        warp, rep = BicubicWarp.fit(uv, cmd)
        evaluate("bicubic warp, normalised u, v", warp, 36, held, rep.rms, rep.condition)
        raw, rep_raw = BicubicWarp.fit(uv, cmd, normalise=False)
        evaluate("bicubic warp, raw pixel powers", raw, 36, held, rep_raw.rms, rep_raw.condition)
        xyz = np.r_[np.c_[cmd, np.zeros(36)], np.c_[cmd, np.full(36, 40.0)]]
        linear, rep_lin = LinearCamera.fit(xyz, np.r_[uv, uv40])
        evaluate("linear 3x4 camera (z = 0 and 40)", lambda u, v, m=linear: m.inverse_perspective(u, v, 0.0),
                 72, held, rep_lin.rms)
        h = fit_homography(uv, cmd)
        hx, hy = h(uv[:, 0], uv[:, 1])
        evaluate("plane homography", h, 36, held, float(np.sqrt(np.mean((hx - cmd[:, 0]) ** 2 + (hy - cmd[:, 1]) ** 2))))
    print("\ntarget: held-out rms of the normalised warp <= 0.05 mm with the robot error; "
          "the linear model and the homography about 1 mm")


if __name__ == "__main__":
    main()
