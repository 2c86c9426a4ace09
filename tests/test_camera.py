"""Camera models and calibration against independent references, and bad input."""
from __future__ import annotations

import io
import json

import numpy as np
import pytest
from conftest import rcl
from PIL import Image

from rcl import RclRuntimeError, Session
from rcl.camera import (
    BicubicWarp,
    CameraModelError,
    ImageError,
    ImageFiles,
    LinearCamera,
    fileformat,
    find_mark,
    read_image,
)
from rcl.camera.simulated import PinholeCamera, render_disc

RNG = np.random.default_rng(7)


def grid(n=6, lo=0.0, hi=511.0):
    g = np.linspace(lo, hi, n)
    u, v = np.meshgrid(g, g)
    return np.stack([u.ravel(), v.ravel()], axis=1)


# The warp -------------------------------------------------------------------

def test_warp_recovers_a_known_bicubic_exactly():
    # x and y are bicubics of raw (u, v), written out by hand, not through the code under test
    def truth(u, v):
        s, t = u / 100.0, v / 100.0
        x = 3 + 2 * s - 0.5 * t + 0.1 * s * t + 0.02 * s ** 3 - 0.03 * s ** 2 * t ** 3 + 0.001 * s ** 3 * t ** 3
        y = -7 + 0.2 * s + 1.5 * t - 0.04 * t ** 3 + 0.05 * s ** 3 * t - 0.002 * s ** 2 * t ** 2
        return x, y
    uv = np.concatenate([grid(6), RNG.uniform(0, 511, (20, 2))])
    warp, report = BicubicWarp.fit(uv, np.stack(truth(*uv.T), axis=1))
    assert report.rms < 1e-9 and report.loo_rms < 1e-9
    q = RNG.uniform(0, 511, (100, 2))
    np.testing.assert_allclose(np.stack(warp(*q.T), axis=1), np.stack(truth(*q.T), axis=1), atol=1e-8)


def test_normalisation_keeps_the_fit_well_conditioned():
    uv = grid(6)
    xy = uv * 0.4 + 5.0
    _, normalised = BicubicWarp.fit(uv, xy)
    _, raw = BicubicWarp.fit(uv, xy, normalise=False)
    assert normalised.condition < 1e3
    assert raw.condition > 1e13


def test_inverse_warp_round_trips_on_a_real_camera():
    cam = PinholeCamera.over_tray(height_mm=600, tilt_deg=10, k1=-0.05)
    g = np.linspace(-90, 90, 6)
    x, y = (a.ravel() for a in np.meshgrid(g, g))
    u, v = cam.project(x, y, 0 * x)
    warp, report = BicubicWarp.fit(np.stack([u, v], 1), np.stack([x, y], 1))
    assert report.rms < 0.01
    qx, qy = RNG.uniform(-85, 85, (2, 50))
    qu, qv = warp.inverse(qx, qy)
    bx, by = warp(qu, qv)
    np.testing.assert_allclose(bx, qx, atol=1e-9)
    np.testing.assert_allclose(by, qy, atol=1e-9)


def test_leave_one_out_matches_refitting():
    uv = np.concatenate([grid(5), RNG.uniform(0, 511, (6, 2))])
    xy = np.stack([np.sin(uv[:, 0] / 200) * 50, np.cos(uv[:, 1] / 150) * 40], axis=1)
    _, report = BicubicWarp.fit(uv, xy)
    errs = []
    for i in range(len(uv)):
        keep = np.arange(len(uv)) != i
        w, _ = BicubicWarp.fit(uv[keep], xy[keep])
        errs.append(np.sum((np.stack(w(*uv[i]), axis=0) - xy[i]) ** 2))
    assert report.loo_rms == pytest.approx(np.sqrt(np.mean(errs)), rel=1e-6)


def _camera_grid(cam, noise_mm=0.0):
    """A 6 x 6 calibration grid over +-90 mm seen by cam: ((u, v) px, (x, y) mm)."""
    g = np.linspace(-90, 90, 6)
    x, y = (a.ravel() for a in np.meshgrid(g, g))
    u, v = cam.project(x, y, 0 * x)
    xy = np.stack([x, y], 1) + RNG.normal(0, noise_mm, (len(x), 2))
    return np.stack([u, v], 1), xy


@pytest.mark.parametrize("bad", [(5,), (0,), (14,), (5, 30)])
def test_calibration_leaves_out_a_marker_found_on_something_else(bad):
    """A grid point whose marker was found elsewhere in the picture (as in the cell, a dark hole in
    a loop of light wire taken for it) is left out, worst first; the warp is then as good as
    without it, against the camera's own projection."""
    from rcl.camera import Calibration

    cam = PinholeCamera.over_tray(height_mm=600, tilt_deg=8, k1=-0.04)
    uv, xy = _camera_grid(cam)
    for i, to in zip(bad, ((235.0, 222.0), (330.0, 150.0))):
        uv[i] = to  # the corner (0), an edge (5) or the middle (14)
    cal = Calibration()
    for p, q in zip(uv, xy):
        cal.add_point(*p, *q)
    rms = cal.fit()
    assert sorted(i for i, _ in cal.left_out) == sorted(bad)
    assert all(miss > 20 for _, miss in cal.left_out)
    assert rms < 0.01 and cal.report.points == 36 - len(bad)
    qx, qy = RNG.uniform(-85, 85, (2, 40))
    qu, qv = cam.project(qx, qy, 0 * qx)
    got = np.array([cal.warp(a, b)[:2] for a, b in zip(qu, qv)])
    assert np.max(np.hypot(got[:, 0] - qx, got[:, 1] - qy)) < 0.05
    plain, _ = BicubicWarp.fit(uv, xy)  # every point kept: off by millimetres
    assert np.max(np.hypot(*(np.stack(plain(qu, qv), 1) - np.stack([qx, qy], 1)).T)) > 2.0


def test_calibration_keeps_every_honest_point():
    """Points only as far off as a real marker and arm are (0.3 mm, or none) are all kept."""
    from rcl.camera import Calibration

    cam = PinholeCamera.over_tray(height_mm=600, tilt_deg=8, k1=-0.04)
    for noise in (0.0, 0.3):
        for _ in range(5):
            uv, xy = _camera_grid(cam, noise)
            cal = Calibration()
            for p, q in zip(uv, xy):
                cal.add_point(*p, *q)
            cal.fit()
            assert cal.left_out == [] and cal.report.points == 36


@pytest.mark.parametrize("uv, message", [
    (grid(3), "needs at least 16 points, not 9"),
    (np.stack([np.linspace(0, 500, 20), np.linspace(0, 300, 20)], 1), "lie on a line"),
    (np.concatenate([grid(4), grid(4)[:1]]), "image points 1 and 17 are the same point"),
    (np.array([(u, v) for u in (0.0, 100.0, 200.0) for v in np.linspace(0, 500, 6)]),
     "do not determine a bicubic"),
])
def test_warp_rejects_points_that_cannot_determine_it(uv, message):
    xy = uv * 0.3
    with pytest.raises(CameraModelError, match=message):
        BicubicWarp.fit(uv, xy)


def test_warp_rejects_nan():
    uv = grid(5)
    xy = uv.copy()
    xy[3, 1] = np.nan
    with pytest.raises(CameraModelError, match="point 4 of the tray points is not a finite number"):
        BicubicWarp.fit(uv, xy)


# The linear camera ------------------------------------------------------------

def random_camera_matrix():
    # K [R | t], built by hand: focal 900 px, centre (256, 240), a rotation about a random axis
    k = np.array([[900.0, 0, 256], [0, 900, 240], [0, 0, 1]])
    axis = RNG.normal(size=3)
    axis /= np.linalg.norm(axis)
    a = 0.3
    kx = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    r = np.eye(3) + np.sin(a) * kx + (1 - np.cos(a)) * kx @ kx
    c = k @ np.hstack([r, [[10.0], [-20.0], [800.0]]])
    return c / c[2, 3]


def test_linear_camera_recovers_a_known_matrix_exactly():
    c = random_camera_matrix()
    xyz = RNG.uniform([-100, -100, 0], [100, 100, 60], (12, 3))
    h = np.hstack([xyz, np.ones((12, 1))]) @ c.T
    uv = h[:, :2] / h[:, 2:]
    cam, report = LinearCamera.fit(xyz, uv)
    np.testing.assert_allclose(cam.C, c, rtol=1e-7, atol=1e-9)
    assert cam.C[2, 3] == 1.0 and report.rms < 1e-8


def test_projection_then_inverse_perspective_returns_the_point():
    cam = LinearCamera(random_camera_matrix())
    xyz = RNG.uniform([-100, -100, -20], [100, 100, 60], (50, 3))
    u, v = cam.project(*xyz.T)
    x, y = cam.inverse_perspective(u, v, xyz[:, 2])
    np.testing.assert_allclose(np.stack([x, y], 1), xyz[:, :2], atol=1e-8)


def test_linear_camera_rejects_flat_targets_and_too_few_points():
    c = random_camera_matrix()
    flat = np.hstack([grid(4, -100, 100), np.zeros((16, 1))])
    h = np.hstack([flat, np.ones((16, 1))]) @ c.T
    with pytest.raises(CameraModelError, match="flat target cannot determine"):
        LinearCamera.fit(flat, h[:, :2] / h[:, 2:])
    with pytest.raises(CameraModelError, match="at least 6 points, not 5"):
        LinearCamera.fit(RNG.uniform(size=(5, 3)), RNG.uniform(size=(5, 2)))


# Files ----------------------------------------------------------------------------

def test_model_files_round_trip_and_reject_other_versions(tmp_path):
    uv = grid(6)
    warp, report = BicubicWarp.fit(uv, uv * 0.35 + 3)
    path = tmp_path / "m.json"
    fileformat.save(path, warp, 12.5, report)
    back, z, rep = fileformat.load(path)
    assert z == 12.5 and rep.points == 36
    np.testing.assert_allclose(np.stack(back(*uv.T)), np.stack(warp(*uv.T)), atol=1e-12)
    doc = json.loads(path.read_text())
    doc["version"] = 2
    path.write_text(json.dumps(doc))
    with pytest.raises(CameraModelError, match="version 2 is not supported"):
        fileformat.load(path)
    path.write_text('{"format": "rcl-camera-model", "version": 1, "model": "warp", "z_mm": 0,')
    with pytest.raises(CameraModelError, match=r"m.json:1:\d+: not JSON"):
        fileformat.load(path)
    doc["version"] = 1
    doc["warp"]["x"] = doc["warp"]["x"][:15]
    path.write_text(json.dumps(doc))
    with pytest.raises(CameraModelError, match='"x" must be a list of 16 finite numbers'):
        fileformat.load(path)


# Images and the marker ------------------------------------------------------------

@pytest.mark.slow
@pytest.mark.parametrize("level, background", [(0.9, 0.3), (0.1, 0.6)])
def test_find_mark_locates_a_disc_to_a_small_fraction_of_a_pixel(level, background):
    errors = []
    for _ in range(20):
        centre = RNG.uniform(30, 200, 2)
        img = render_disc((240, 260), tuple(centre), RNG.uniform(3, 8), level, background)
        img += RNG.normal(0, 0.01, img.shape)
        u, v = find_mark(img)
        errors.append(np.hypot(u - centre[0], v - centre[1]))
    assert max(errors) < 0.1


def test_find_mark_ignores_wires_and_returns_none_without_a_disc():
    img = np.full((200, 200), 0.6)
    img[50:53, 10:190] = 0.1  # a dark wire across the image
    img[20:180, 120:123] = 0.1
    assert find_mark(img) is None
    disc = render_disc((200, 200), (80.3, 140.6), 5, 0.1, 0.6)
    img = np.minimum(img, disc)
    u, v = find_mark(img)
    assert abs(u - 80.3) < 0.1 and abs(v - 140.6) < 0.1
    assert find_mark(np.zeros((100, 100))) is None
    assert find_mark(RNG.uniform(size=(100, 100))) is None
    assert find_mark(np.ones((2, 2))) is None


@pytest.mark.slow
def test_find_mark_finds_a_disc_on_a_pad_over_wires_on_any_board():
    """The cell's marker (a light disc on a dark pad) over dark and light wires on a textured
    board of any brightness: found by its own surround, within a tenth of a pixel."""
    errors = []
    for board in (0.1, 0.5, 0.9):
        for _ in range(6):
            img = board + 0.08 * RNG.standard_normal((240, 260)).cumsum(axis=1) / 15  # streaky board
            img[60:64, :] = 0.05
            img[:, 100:103] = 0.95  # a light wire
            img[150:153, 20:240] = 0.05
            centre = RNG.uniform(60, 180, 2)
            pad = render_disc(img.shape, tuple(centre), 16.0, 1.0, 0.0)
            dot = render_disc(img.shape, tuple(centre), 8.0, 1.0, 0.0)
            img = img * (1 - pad) + 0.06 * pad
            img = img * (1 - dot) + 0.97 * dot + RNG.normal(0, 0.01, img.shape)
            u, v = find_mark(img)
            errors.append(np.hypot(u - centre[0], v - centre[1]))
    assert max(errors) < 0.1


def test_read_image_handles_formats_and_refuses_junk(tmp_path):
    grey = (RNG.uniform(size=(20, 30)) * 255).astype(np.uint8)
    Image.fromarray(grey).save(tmp_path / "g.png")
    np.testing.assert_allclose(read_image(tmp_path / "g.png"), grey / 255.0)
    deep = (RNG.uniform(size=(20, 30)) * 65535).astype(np.uint16)
    Image.fromarray(deep).save(tmp_path / "d.png")
    np.testing.assert_allclose(read_image(tmp_path / "d.png"), deep / 65535.0)
    Image.fromarray(grey).convert("P").save(tmp_path / "p.png")
    assert read_image(tmp_path / "p.png").shape == (20, 30, 3)
    Image.fromarray(np.dstack([grey] * 4)).save(tmp_path / "a.png")
    assert read_image(tmp_path / "a.png").shape == (20, 30, 3)
    Image.fromarray(RNG.uniform(size=(20, 30)).astype(np.float32)).save(tmp_path / "f.tif")
    assert read_image(tmp_path / "f.tif").max() <= 1.0
    nan = np.full((5, 5), np.nan, dtype=np.float32)
    Image.fromarray(nan).save(tmp_path / "nan.tif")
    with pytest.raises(ImageError, match="not finite"):
        read_image(tmp_path / "nan.tif")
    data = (tmp_path / "g.png").read_bytes()
    (tmp_path / "cut.png").write_bytes(data[: len(data) // 2])
    (tmp_path / "text.png").write_text("not an image")
    (tmp_path / "empty.png").write_bytes(b"")
    for name in ("cut.png", "text.png", "empty.png", "missing.png"):
        with pytest.raises(ImageError):
            read_image(tmp_path / name)


def test_read_image_turns_a_photograph_the_right_way_up(tmp_path):
    """A phone's photograph holds its pixels as the sensor saw them and an EXIF orientation that
    says how to turn them (6: a quarter turn clockwise); labels made on it, and what a user sees
    in any viewer, are upright. (mBEST S2's img8 is such a file: its labels did not fit.)"""
    raw = np.zeros((20, 30, 3), np.uint8)
    raw[0, 0] = 255  # the sensor's first pixel, seen at the top right once turned
    exif = Image.Exif()
    exif[0x0112] = 6
    Image.fromarray(raw).save(tmp_path / "turned.png", exif=exif)
    Image.fromarray(raw).save(tmp_path / "plain.png")
    turned = read_image(tmp_path / "turned.png")
    assert turned.shape == (30, 20, 3)
    assert turned[0, -1].min() == 1.0 and turned.sum() == 3.0
    np.testing.assert_array_equal(read_image(tmp_path / "plain.png"), raw / 255.0)


def test_image_files_camera_reads_a_folder_in_order(tmp_path):
    for i in range(3):
        Image.fromarray(np.full((4, 4), i * 100, np.uint8)).save(tmp_path / f"img{i}.png")
    cam = ImageFiles(tmp_path)
    assert [round(cam.grab()[0, 0] * 255) for _ in range(3)] == [0, 100, 200]
    with pytest.raises(ImageError, match="no more images"):
        cam.grab()
    with pytest.raises(ImageError):
        ImageFiles(tmp_path / "nothing")


# RCL built-ins and the CLI ----------------------------------------------------------

def test_calibration_builtins_in_rcl(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    cam = PinholeCamera.over_tray(height_mm=600, tilt_deg=6, k1=-0.03)
    g = np.linspace(-90, 90, 6)
    lines = []
    for x in g:
        for y in g:
            u, v = cam.project(x, y, 0.0)
            lines.append(f"CALPOINT({float(u)!r}, {float(v)!r}, {float(x)!r}, {float(y)!r})")
    u0, v0 = cam.project(12.0, -34.0, 0.0)
    out = io.StringIO()
    s = Session(out=out)
    s.run("\n".join(lines) + f"\nrms := FITWARP()\nSAVEWARP('w.json')\np := WARP({float(u0)!r}, {float(v0)!r})\n")
    assert s["rms"] < 0.01
    np.testing.assert_allclose(s["p"], [12.0, -34.0, 0.0], atol=0.02)
    t = Session(out=out)
    t.run(f"LOADWARP('w.json')\nq := WARP({float(u0)!r}, {float(v0)!r})")
    np.testing.assert_allclose(t["q"], s["p"], atol=1e-12)
    lines[5] = "CALPOINT(250.5, 260.25, 90.0, -18.0)"  # a marker found somewhere else
    out = io.StringIO()
    s = Session(out=out)
    s.run("\n".join(lines) + "\nrms := FITWARP()\n")
    assert s["rms"] < 0.01
    assert out.getvalue().startswith("FITWARP: point 6, (250.5, 260.2) px at (90, -18) mm, left out: "
                                     "the other points put it ")
    with pytest.raises(RclRuntimeError, match="no camera model yet"):
        Session().run("p := WARP(1, 2)")
    with pytest.raises(RclRuntimeError, match="FITWARP: a bicubic warp has 16 terms"):
        Session().run("CALPOINT(1, 2, 3, 4)\nx := FITWARP()")
    with pytest.raises(RclRuntimeError, match="LOADWARP: cannot read"):
        Session().run("LOADWARP('missing.json')")
    with pytest.raises(RclRuntimeError, match="FINDMARK: this session has no camera"):
        Session().run("IF FINDMARK(u, v) THEN END")


@pytest.mark.slow
def test_findmark_builtin_reads_the_session_camera(tmp_path):
    img = render_disc((120, 160), (70.25, 40.5), 5, 0.95, 0.2)
    Image.fromarray((img * 255).round().astype(np.uint8)).save(tmp_path / "mark.png")
    program = tmp_path / "find.rcl"
    program.write_text("IF FINDMARK(u, v) THEN WRITELN(ABS(u - 70.25) < 0.05, ' ', ABS(v - 40.5) < 0.05) END\n")
    r = rcl("run", str(program), "--camera", str(tmp_path / "mark.png"))
    assert r.returncode == 0, r.stderr
    assert r.stdout == "TRUE TRUE\n"
    r = rcl("run", str(program), "--camera", str(tmp_path / "nowhere"))
    assert r.returncode == 2 and "--camera" in r.stderr


@pytest.mark.slow
def test_calib_cli_fit_and_apply(tmp_path):
    cam = PinholeCamera.over_tray(height_mm=600, tilt_deg=8, k1=-0.05)
    g = np.linspace(-90, 90, 6)
    x, y = (a.ravel() for a in np.meshgrid(g, g))
    u, v = cam.project(x, y, 0 * x)
    rows = "\n".join(f"{a},{b},{c},{d}" for a, b, c, d in zip(u.tolist(), v.tolist(), x.tolist(), y.tolist()))
    (tmp_path / "pts.csv").write_text("u,v,x,y\n" + rows + "\n")
    r = rcl("calib", "fit", str(tmp_path / "pts.csv"), "--model", "warp", "-o", str(tmp_path / "m.json"))
    assert r.returncode == 0, r.stderr
    last = r.stdout.strip().splitlines()[-1]
    assert last.startswith("rms ") and last.endswith(" mm") and float(last.split()[1]) < 0.01
    qu, qv = cam.project(40.0, -25.0, 0.0)
    (tmp_path / "q.csv").write_text(f"u,v\n{float(qu)!r},{float(qv)!r}\n")
    r = rcl("calib", "apply", str(tmp_path / "m.json"), str(tmp_path / "q.csv"))
    assert r.returncode == 0 and r.stdout.splitlines()[0] == "x,y"
    xa, ya = map(float, r.stdout.splitlines()[1].split(","))
    assert abs(xa - 40) < 0.02 and abs(ya + 25) < 0.02
    # linear: points at two heights, z column
    c = random_camera_matrix()
    xyz = RNG.uniform([-100, -100, 0], [100, 100, 60], (20, 3))
    h = np.hstack([xyz, np.ones((20, 1))]) @ c.T
    uv = h[:, :2] / h[:, 2:]
    (tmp_path / "lin.csv").write_text("u,v,x,y,z\n" + "\n".join(
        f"{a},{b},{p},{q},{s}" for (a, b), (p, q, s) in zip(uv.tolist(), xyz.tolist())) + "\n")
    r = rcl("calib", "fit", str(tmp_path / "lin.csv"), "--model", "linear", "-o", str(tmp_path / "l.json"))
    assert r.returncode == 0 and float(r.stdout.split()[-2]) < 1e-6
    (tmp_path / "lq.csv").write_text(f"u,v,z\n{uv[0, 0]},{uv[0, 1]},{xyz[0, 2]}\n")
    r = rcl("calib", "apply", str(tmp_path / "l.json"), str(tmp_path / "lq.csv"))
    xa, ya = map(float, r.stdout.splitlines()[1].split(","))
    assert abs(xa - xyz[0, 0]) < 1e-6 and abs(ya - xyz[0, 1]) < 1e-6


@pytest.mark.parametrize("content, message", [
    ("u,v,x\n1,2,3\n", "missing y"),
    ("u,v,x,y\n1,2,3\n", "pts.csv:2: expected 4 values"),
    ("u,v,x,y\n1,2,three,4\n", "pts.csv:2: 'three' is not a number"),
    ("u,v,x,y\n1,2,nan,4\n", "not a finite number"),
    ("", "the file is empty"),
    ("u,v,x,y\n" + "".join(f"{i},{i},{i},{i}\n" for i in range(20)), "lie on a line"),
    ("u,v,x,y\n" + "".join(f"{i},{2 * i % 7},{i},{i}\n" for i in range(10)), "at least 16 points, not 10"),
])
def test_calib_cli_bad_input_exits_2(tmp_path, content, message):
    (tmp_path / "pts.csv").write_text(content)
    r = rcl("calib", "fit", str(tmp_path / "pts.csv"), "-o", str(tmp_path / "m.json"))
    assert r.returncode == 2 and message in r.stderr and "Traceback" not in r.stderr


@pytest.mark.slow
def test_calib_cli_bad_model_file_exits_2(tmp_path):
    (tmp_path / "q.csv").write_text("u,v\n1,2\n")
    for text in ("not json", '{"format": "rcl-camera-model", "version": 9}', "[]"):
        (tmp_path / "m.json").write_text(text)
        r = rcl("calib", "apply", str(tmp_path / "m.json"), str(tmp_path / "q.csv"))
        assert r.returncode == 2 and "rcl calib: error:" in r.stderr and "Traceback" not in r.stderr
