"""The simulated cell: the camera's view of the tray, the cell's physics, cell files, the main job."""
from __future__ import annotations

import io
import json
import math
import re

import numpy as np
import pytest
from conftest import ROOT, rcl

from rcl import Session
from rcl.camera import as_grey
from rcl.camera.simulated import PinholeCamera
from rcl.cell import CellConfigError, SimCell, TrayView, load_config
from rcl.frame import Frame
from rcl.vision.synth import Wire, resample
from rcl.workcell import open_cell


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


# The cell's physics ------------------------------------------------------------------

EXACT_ARM = ("[robot]\ninaccuracy_mm = 0.0\nrepeatability_mm = 0.0\n[gripper]\ndrop_rate = 0.0\n"
             "[tray]\nlook = 'plain_dark'\n")


def exact_cell(tmp_path, extra: str = "") -> SimCell:
    """A cell whose arm goes exactly where it is sent, with one straight wire along world X:
    tray (20..100, 60) mm, i.e. world x 306..386 at y = -4, lying alone on the tray."""
    (tmp_path / "exact.toml").write_text(EXACT_ARM + extra)
    sim = SimCell(load_config(tmp_path / "exact.toml"), seed=0)
    for n in list(sim.tray.wires):
        sim.tray.remove(n)
    xs = np.arange(20.0, 100.01, 0.5)
    sim.tray.put(1, np.stack([xs, np.full_like(xs, 60.0)], axis=1), Wire(np.zeros((2, 2)), 2.0, 0, (0.2,)))
    return sim


def send_tool(sim: SimCell, tool: Frame) -> None:
    sim.arm.move((Frame(sim.Z).inv() * tool * Frame(sim.E).inv()).matrix)


def grasp_at(x: float, y: float, turn: float = 0.0, z: float = 0.0) -> Frame:
    """The tool pointing down at (x, y, z), its fingers closing along world Y turned by `turn` degrees."""
    return Frame.trans(x, y, z) * Frame.rotz(turn) * Frame.rotx(180)


@pytest.mark.parametrize("x, y, turn, z, taken, why", [
    (336.0, -4.0, 0.0, 0.0, True, ""),
    (336.0, -3.2, 0.0, 0.0, True, ""),           # 0.8 mm off the centre line: the fingers centre it
    (336.0, -2.5, 0.0, 0.0, False, "closed on nothing"),  # 1.5 mm off
    (336.0, -4.0, 12.0, 0.0, True, ""),          # 12 degrees off square
    (336.0, -4.0, 25.0, 0.0, False, "off square"),
    (336.0, -4.0, 0.0, 6.0, False, "above the tray"),
])
def test_the_gripper_takes_a_wire_only_close_and_square(tmp_path, x, y, turn, z, taken, why):
    sim = exact_cell(tmp_path)
    send_tool(sim, grasp_at(x, y, turn, z))
    sim.arm.close()
    assert sim.arm.gripped() is taken
    assert sim.attempts == 1
    failures = [e for e in sim.events if not e.ok]
    assert (not failures) if taken else why in failures[0].why
    assert (len(sim.tray) == 0) is taken


def test_the_gripper_needs_the_wire_on_top_and_room_for_its_fingers(tmp_path):
    sim = exact_cell(tmp_path)
    ys = np.arange(30.0, 90.01, 0.5)
    sim.tray.put(2, np.stack([np.full_like(ys, 50.0), ys], axis=1), Wire(np.zeros((2, 2)), 2.0, 0, (0.2,)))
    send_tool(sim, grasp_at(286 + 51.5, -64 + 60.0))  # on wire 1, 1.5 mm beside where wire 2 crosses over it
    sim.arm.close()
    assert not sim.arm.gripped() and "lies under wire 2" in sim.events[-1].why
    sim.arm.open()
    send_tool(sim, grasp_at(286 + 53.0, -64 + 60.0, z=20.0))
    send_tool(sim, grasp_at(286 + 53.0, -64 + 60.0))  # 3 mm beside wire 2: no room
    sim.arm.close()
    assert not sim.arm.gripped() and "no room for the fingers" in sim.events[-1].why


def test_the_press_crimps_only_an_end_in_the_die(tmp_path):
    for offset, ok, why in [(0.0, True, ""), (0.7, True, ""), (1.6, False, "off the die's axis")]:
        sim = exact_cell(tmp_path)
        end_x = 286 + 20.0
        send_tool(sim, grasp_at(end_x + 15.0, -4.0))  # 15 mm from the wire's end (tray x = 20)
        sim.arm.close()
        assert sim.arm.gripped()
        # W^ as vision gives it: origin at the end, X up, Z along the wire away from the end
        w = Frame(np.array([[0, 0, 1, end_x], [0, -1, 0, -4.0], [1, 0, 0, 0.0], [0, 0, 0, 1.0]]))
        wg = w.inv() * grasp_at(end_x + 15.0, -4.0)
        press = sim.config.frame("PRESS") * Frame.trans(0.0, offset, 0.0)
        send_tool(sim, press * wg)
        assert sim.crimp() is ok
        assert ok or why in sim.events[-1].why
        sim.arm.open()
        assert sim.results[1] == ("crimped" if ok else "rejected")


def test_the_arm_strays_smoothly_by_one_to_three_mm():
    sim = SimCell(load_config(), seed=0)
    xs, ys = np.meshgrid(np.linspace(286, 414, 30), np.linspace(-64, 64, 30))
    errs = np.array([sim.error([x, y, 0.0]) for x, y in zip(xs.ravel(), ys.ravel())])
    size = np.linalg.norm(errs, axis=1)
    assert 0.9 <= size.min() and size.max() <= 3.1
    step = np.linalg.norm(np.diff(errs.reshape(30, 30, 3), axis=1), axis=2).max()
    assert step < 0.15  # 4.4 mm apart: smooth


def test_a_wire_let_go_over_the_tray_lies_there_again_and_a_slipping_wire_falls_back(tmp_path):
    sim = exact_cell(tmp_path)
    before = sim.tray.wires[1].centre.copy()
    send_tool(sim, grasp_at(318.0, -4.0))  # 12 mm from its end: it does not hang
    sim.arm.close()
    send_tool(sim, grasp_at(318.0, -4.0, z=30.0))
    sim.arm.open()
    assert len(sim.tray) == 1 and sim.results == {}
    assert np.abs(resample(sim.tray.wires[1].centre, 0.5)[[0, -1]] - before[[0, -1]]).max() < 0.6
    (tmp_path / "slip.toml").write_text(EXACT_ARM.replace("drop_rate = 0.0", "drop_rate = 1.0"))
    slippy = SimCell(load_config(tmp_path / "slip.toml"), seed=0)
    for n in list(slippy.tray.wires):
        slippy.tray.remove(n)
    slippy.tray.put(1, sim.tray.wires[1].centre, sim.tray.wires[1])
    send_tool(slippy, grasp_at(318.0, -4.0))
    slippy.arm.close()
    assert slippy.arm.gripped()
    send_tool(slippy, grasp_at(318.0, -4.0, z=30.0))
    assert not slippy.arm.gripped() and len(slippy.tray) == 1
    assert "slipped out of the fingers and fell back on the tray" in slippy.events[-1].why


def test_every_look_is_a_fresh_picture_of_the_tray_as_it_now_is(tmp_path):
    sim = exact_cell(tmp_path)
    first = as_grey(sim.camera.grab())
    u, v = sim.lens.project(336.0, -4.0, 1.0)
    assert first[int(round(float(v))), int(round(float(u)))] < 0.3  # the wire, dark
    send_tool(sim, grasp_at(336.0, -4.0))
    sim.arm.close()
    send_tool(sim, grasp_at(336.0, -4.0, z=200.0))
    second = as_grey(sim.camera.grab())
    assert second[int(round(float(v))), int(round(float(u)))] > 0.45  # gone: the tray shows
    assert not np.array_equal(first, sim.camera.grab())  # fresh noise every look
    assert sim.camera.grabs == 3


def test_the_tray_looks_as_the_randomized_generator_draws_it_from_its_seed():
    same = [SimCell(load_config(), seed=4).tray.picture() for _ in range(2)]
    assert np.array_equal(same[0], same[1])
    scenes = [SimCell(load_config(), seed=s).tray.scene for s in range(12)]
    assert len({sc.board for sc in scenes}) >= 3 and len({sc.board_colour for sc in scenes}) == 12
    assert {sc.colour for sc in scenes} == {True, False}
    config = load_config()
    config.data["tray"]["look"] = "plain_dark"  # a slice of the generator: the paper's conditions
    tray = SimCell(config, seed=4).tray
    assert tray.scene.board == "plain" and {lk.insulation for lk in tray.looks.values()} == {"black"}


@pytest.mark.slow
@pytest.mark.parametrize("seed, points", [
    (0, ()), (1, ()), (2, ()), (3, ()), (5, ()),
    # the corner of the calibration grid: a dark hole inside a loop of light wire makes a more
    # disc-like dark disc, and the wires' light ends and bends outdid the marker in the centre-surround
    # response, so it was not among the candidates tried (the warp fitted to it was 11.6 mm off)
    (707, ((290.0, 60.0),)),
])
def test_the_marker_is_found_where_the_fingertips_are_on_any_tray(seed, points):
    from rcl.camera import find_mark

    sim = SimCell(load_config(), seed=seed)
    sim.arm.close()
    for x, y in points or ((300.0, -50.0), (350.0, 0.0), (400.0, 45.0)):
        send_tool(sim, grasp_at(x, y))
        u, v = find_mark(sim.camera.grab())
        pu, pv = sim.lens.project(*sim.tool()[:3, 3])
        assert math.hypot(u - float(pu), v - float(pv)) < 0.15


# The cell file ----------------------------------------------------------------------------

@pytest.mark.parametrize("text, message", [
    ("[robot]\nkind = 'kuka'\n", "robot.kind"),
    ("[tray]\nlook = 'shiny'\n", "tray.look must be one of random, sparse"),
    ("[gripper]\ntolerance = 1.0\n", "unknown key 'gripper.tolerance'"),
    ("[tray]\nwires = [3]\n", "'tray.wires' must be a list of 2 numbers"),
    ("[camera]\nwidth = 'big'\n", "'camera.width' must be a number"),
    ("[frames.PRESS]\nxyz = [1, 2]\n", "'frames.PRESS.xyz' must be a list of 3 numbers"),
    ("[frames.PRESS]\nrot = [1, 2, 3]\n", "unknown key 'frames.PRESS.rot'"),
    ("[robot]\nkind = 'ssc32'\n", "robot.port"),
    ("[robot]\nkind = 'ssc32'\nport = 'x'\n", "simulated camera"),
    ("name = \n", "not a valid TOML file"),
])
@pytest.mark.slow
def test_bad_cell_files_are_refused_with_the_key_named(tmp_path, text, message):
    path = tmp_path / "cell.toml"
    path.write_text(text)
    with pytest.raises(CellConfigError, match=re.escape(message)):
        load_config(path)
    r = rcl("run", str(ROOT / "examples" / "crimp.rcl"), "--cell", str(path))
    assert r.returncode == 2 and "rcl: error: --cell:" in r.stderr and "Traceback" not in r.stderr


@pytest.mark.slow
def test_a_missing_cell_file_and_a_cell_camera_with_no_images(tmp_path):
    r = rcl("run", str(ROOT / "examples" / "crimp.rcl"), "--cell", str(tmp_path / "nope.toml"))
    assert r.returncode == 2 and "no such file" in r.stderr
    (tmp_path / "empty").mkdir()
    (tmp_path / "files.toml").write_text("[camera]\nkind = 'files'\nfolder = 'empty'\n")
    r = rcl("run", str(ROOT / "examples" / "crimp.rcl"), "--cell", str(tmp_path / "files.toml"))
    assert r.returncode == 2 and "holds no image files" in r.stderr and "Traceback" not in r.stderr


@pytest.mark.slow
def test_a_camera_that_runs_out_of_images_stops_the_task_with_a_clear_error(tmp_path):
    from PIL import Image

    from rcl.camera import Calibration

    (tmp_path / "shots").mkdir()
    tray = SimCell(load_config(), seed=1)
    Image.fromarray((tray.camera.grab() * 255).astype(np.uint8)).save(tmp_path / "shots" / "a.png")
    cal = Calibration()
    for x in np.linspace(290, 410, 6):
        for y in np.linspace(-60, 60, 6):
            cal.add_point(*(float(t) for t in tray.lens.project(x, y, 0.0)), x, y)
    cal.fit()
    cal.save(tmp_path / "warp.json")
    (tmp_path / "files.toml").write_text("warp = 'warp.json'\n[camera]\nkind = 'files'\nfolder = 'shots'\n")
    (tmp_path / "look.rcl").write_text("IMPORT 'cell'\nLOADWARP(WARP_FILE)\nVAR W^, WG^ : FRAME\n"
                                       "WHILE GREYWIRE(W^, WG^) DO\n  WRITELN('seen at ', W^.P)\nEND\n")
    r = rcl("run", str(tmp_path / "look.rcl"), "--cell", str(tmp_path / "files.toml"))
    assert r.returncode == 1, r.stderr
    assert "look.rcl:4:7: error: GREYWIRE: no more images" in r.stderr and r.stdout.count("seen at") == 1


@pytest.mark.slow
def test_a_missing_warp_file_is_calibrated_and_saved_then_loaded(tmp_path):
    (tmp_path / "cell.toml").write_text("warp = 'warp.json'\n")
    for expect in ("calibrating instead", "camera model: " + str(tmp_path / "warp.json")):
        out = io.StringIO()
        s = Session(out=out, cell=open_cell(tmp_path / "cell.toml", seed=2, wires=(0, 0)))
        s.run("IMPORT 'wires'\nGETWARP\n")
        assert expect in out.getvalue()
        assert (tmp_path / "warp.json").exists()


def test_stations_and_sensors_need_a_cell_that_has_them():
    s = Session(out=io.StringIO())
    for call in ("CRIMP()", "TRAYEMPTY()"):
        with pytest.raises(Exception, match="has no"):
            s.run(f"b := {call}")
    from rcl.errors import RclStaticError
    with pytest.raises(RclStaticError, match="no work cell"):
        s.run("IMPORT 'cell'")


@pytest.mark.slow
def test_the_main_job_from_the_command_line_reports_and_draws_every_look(tmp_path):
    """Seed 0: one pick finds no room for the fingers (another wire lies against the one taken).
    The output, the report and the pictures number wires and looks alike and say the same words
    for the same event."""
    r = rcl("run", str(ROOT / "examples" / "crimp.rcl"), "--seed", "0", "--report", str(tmp_path / "r.json"),
            "--pictures", str(tmp_path / "pics"), "--frames", str(tmp_path / "frames"), cwd=tmp_path, timeout=120)
    assert r.returncode == 0, r.stderr
    report = json.loads((tmp_path / "r.json").read_text())
    assert set(report) >= {"wires_total", "wires_done", "attempts", "failures", "sensing_ms", "robot_time_s"}
    assert 10 <= report["wires_total"] <= 15 and report["wires_done"] >= 1
    assert report["wires_done"] + report["wires_left"] <= report["wires_total"]
    assert report["attempts"] >= report["wires_done"] and report["robot_time_s"] > 0
    assert all(isinstance(ms, float) and ms > 0 for ms in report["sensing_ms"])
    assert len(list((tmp_path / "pics").glob("look-*.png"))) == len(report["sensing_ms"]) == report["looks"]
    # the raw frames, numbered as the pictures, are images `rcl vision` reads
    frames = sorted((tmp_path / "frames").glob("frame-*.png"))
    assert [f.name[6:] for f in frames] == [p.name[5:] for p in sorted((tmp_path / "pics").glob("look-*.png"))]
    from rcl.camera import read_image
    assert read_image(frames[0]).shape[:2] == (512, 512)
    assert r.stdout.count(", crimped\n") == report["wires_done"]
    assert f"cell: {report['wires_total']} wires" in r.stdout
    # one numbering: the wires the output calls crimped are those the report does
    said = re.findall(r"^wire (\d+): taken at .*, crimped$", r.stdout, re.M)
    assert sorted(said, key=int) == sorted((n for n, v in report["results"].items() if v == "crimped"), key=int)
    # the same words: each failure as the report words it, and numbered by the look it followed
    assert report["failures"], "seed 0 has a pick with no room: the test needs a failure"
    for f in report["failures"]:
        assert f"{f['what']} failed: {f['why']}" in r.stdout
        assert 1 <= f["look"] <= report["looks"] < report["camera_grabs"]  # calibration images are no looks
    assert not math.isnan(report["robot_time_s"])


@pytest.mark.parametrize("picture, message", [
    (None, "the camera returned no image"),
    ("junk", "the camera returned str instead of an image of numbers"),
    (np.zeros((4, 4, 4, 4)), "an image is rows x columns"),
])
def test_a_camera_that_returns_nothing_is_a_clear_runtime_error_with_the_arm_halted(picture, message):
    from rcl.errors import RclRuntimeError

    class Camera:
        def grab(self):
            return picture
    s = Session(camera=Camera(), out=io.StringIO())
    for call, col in (("GREYWIRE(W^, WG^)", 6), ("FINDMARK(u, v)", 6)):
        with pytest.raises(RclRuntimeError) as e:
            s.run(f"VAR W^, WG^ : FRAME\nb := {call}")
        assert e.value.render().startswith(f"<string>:2:{col}: error: {call.split('(')[0]}: {message}")
        assert s.robot.halted


def test_captions_on_the_pictures_keep_their_spaces():
    """The default font's space is 2 px, which the text's shadow filled: '4 free endsseen'."""
    from PIL import Image, ImageDraw

    from rcl.runreport import caption

    picture = Image.new("RGB", (200, 20), (200, 200, 200))  # a light tray
    pen = ImageDraw.Draw(picture)
    caption(pen, (4, 4), "ends seen")
    ink = np.any(np.abs(np.asarray(picture).astype(int) - 200).sum(axis=2) > 30, axis=0)  # text or shadow
    columns = np.flatnonzero(ink)
    assert (np.diff(columns) - 1).max() >= 3  # bare tray between the words (1 px before)


def test_a_loop_taken_by_its_middle_and_dropped_lands_in_a_new_shape(tmp_path):
    """A wire that crosses itself near both ends (no end free, by the ground truth's rules):
    held by its middle it hangs, and let go over the tray it lands anew where it was let go,
    as long as before; over ten drops most land with a free end."""
    from rcl.vision.synth import ground_truth

    t = np.linspace(0.0, 1.0, 400)
    # a figure of eight: it crosses itself in the middle; ends tucked against its own loops
    loop = np.column_stack([60 + 25 * np.sin(2 * np.pi * t), 60 + 12 * np.sin(4 * np.pi * t)])
    length = float(np.sum(np.linalg.norm(np.diff(loop, axis=0), axis=1)))
    freed = 0
    for seed in range(10):
        sim = exact_cell(tmp_path)
        sim.tray.rng = np.random.default_rng(seed)
        sim.tray.remove(1)
        sim.tray.put(1, loop, Wire(np.zeros((2, 2)), 2.0, 0, (0.2,)))
        assert not any(e.graspable for e in ground_truth([sim.tray.wires[1]], sim.tray.size))
        middle = sim.tray.dense(1)[len(sim.tray.dense(1)) // 4]  # a quarter of the way along
        x, y = middle + sim.tray.origin
        tangent = sim.tray.touch(1, middle).tangent
        send_tool(sim, grasp_at(x, y, turn=float(np.degrees(np.arctan2(tangent[1], tangent[0])))))
        sim.arm.close()
        assert sim.arm.gripped()
        send_tool(sim, grasp_at(x, y, z=30.0))
        sim.arm.open()
        assert sim.events[-1].what == "drop" and sim.events[-1].ok
        again = sim.tray.wires[1].centre
        assert abs(np.sum(np.linalg.norm(np.diff(again, axis=0), axis=1)) - length) < 0.02 * length
        held = resample(again, 0.25)[round(length / 4 / 0.25)]
        assert sim.tray.inside(held)
        freed += any(e.graspable for e in ground_truth([sim.tray.wires[1]], sim.tray.size))
    assert freed >= 7
