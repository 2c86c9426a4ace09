"""Arm models, kinematics, the simulator and the SSC-32 arm (on a fake controller)."""
from __future__ import annotations

import io
import math
import time

import numpy as np
import pytest
from conftest import rcl
from fake_ssc32 import FakeSSC32
from PIL import Image

from rcl import Frame, RclRuntimeError, Session
from rcl.robots import IKError, RobotError, SimRobot, fk, load_model, solve
from rcl.robots.kinematics import solutions
from rcl.robots.serial_arm import SerialRobot

MODELS = ["smartarms", "al5d", "puma560"]


def random_joints(model, rng, n):
    lo = np.array([j.min for j in model.joints])
    hi = np.array([j.max for j in model.joints])
    return rng.uniform(lo, hi, size=(n, model.axes))


# Forward kinematics against independent references ----------------------------------

def test_puma560_forward_kinematics_matches_the_robotics_toolbox():
    m = load_model("puma560")
    np.testing.assert_allclose(fk(m, [0] * 6)[:3, 3], [452.1, -150.05, 431.8], atol=1e-9)
    # Corke's qr (ready: arm straight up) and qn (nominal); positions from the Toolbox's documentation
    np.testing.assert_allclose(fk(m, [0, 90, -90, 0, 0, 0])[:3, 3], [20.3, -150.05, 863.6], atol=1e-9)
    np.testing.assert_allclose(fk(m, [0, 45, 180, 0, 45, 0])[:3, 3], [596.3, -150.05, -14.4], atol=0.1)


@pytest.mark.parametrize("name", ["smartarms", "al5d"])
def test_five_axis_forward_kinematics_is_the_planar_arm_geometry(name):
    m = load_model(name)
    j = m.joints
    rng = np.random.default_rng(1)
    for q in random_joints(m, rng, 200):
        t1, t2, t3, t4 = (math.radians(x + jj.offset) for x, jj in zip(q[:4], j[:4]))
        pitch = t2 + t3 + t4  # the approach points along pitch - 90 degrees in the arm's plane
        r = j[1].a * math.cos(t2) + j[2].a * math.cos(t2 + t3) + j[4].d * math.sin(pitch)
        h = j[0].d + j[1].a * math.sin(t2) + j[2].a * math.sin(t2 + t3) - j[4].d * math.cos(pitch)
        t = fk(m, q)
        np.testing.assert_allclose(t[:3, 3], [r * math.cos(t1), r * math.sin(t1), h], atol=1e-9)
        np.testing.assert_allclose(t[:3, 2], [math.sin(pitch) * math.cos(t1), math.sin(pitch) * math.sin(t1),
                                              -math.cos(pitch)], atol=1e-12)


# Inverse kinematics -----------------------------------------------------------------

@pytest.mark.slow
@pytest.mark.parametrize("name", MODELS)
def test_ik_round_trips_10000_random_reachable_poses(name):
    m = load_model(name)
    rng = np.random.default_rng(42)
    current = list(m.home)
    worst = 0.0
    for q in random_joints(m, rng, 10_000):
        t = fk(m, q)
        back = fk(m, solve(m, t, current))
        worst = max(worst, float(np.abs(back[:3, 3] - t[:3, 3]).max()), float(np.abs(back[:3, :3] - t[:3, :3]).max()))
    assert worst < 1e-6


def test_puma_returns_every_branch_and_picks_the_nearest():
    m = load_model("puma560")
    q = [20.0, 30.0, -60.0, 40.0, 50.0, 60.0]
    t = fk(m, q)
    sols = solutions(m, t)
    assert len(sols) == 8
    for s in sols:
        np.testing.assert_allclose(fk(m, s), t, atol=1e-9)
    assert len({tuple(np.round(s, 6)) for s in sols}) == 8  # all different: left/right, up/down, flip
    near = [x + 3 for x in q]
    np.testing.assert_allclose(solve(m, t, near), q, atol=1e-9)


def test_unreachable_and_limit_violating_targets_are_refused_with_the_reason():
    m = load_model("smartarms")
    down = Frame.rotx(180)
    with pytest.raises(IKError, match="out of reach: the wrist centre would be .* the arm reaches at most 600.0 mm"):
        solve(m, (Frame.trans(900, 0, 200) * down).matrix, m.home)
    with pytest.raises(IKError, match=r"leans 19.9 degrees out of the arm's vertical plane \(tolerance 0.01\)"):
        solve(m, (Frame.trans(350, 0, 200) * Frame.rotx(160)).matrix, m.home)
    solve(m, (Frame.trans(350, 0, 200) * Frame.rotx(179.995)).matrix, m.home)  # within the tolerance
    with pytest.raises(IKError, match="breaks a joint limit"):
        solve(m, (Frame.trans(-350, 10, 200) * down).matrix, m.home)  # behind: the waist stops at 170
    puma = load_model("puma560")
    with pytest.raises(IKError, match="out of reach"):
        solve(puma, Frame.trans(2000, 0, 0).matrix, puma.home)


@pytest.mark.slow
def test_numerical_fallback_for_a_user_model(tmp_path):
    text = (load_model("smartarms").source and open(load_model("smartarms").source).read())
    path = tmp_path / "mine.toml"
    path.write_text(text.replace('solver = "5dof"', 'solver = "numerical"').replace('"smartarms"', '"mine"'))
    m = load_model(path)
    q = [20.0, 70.0, -100.0, 40.0, 30.0]
    t = fk(m, q)
    np.testing.assert_allclose(fk(m, solve(m, t, m.home)), t, atol=1e-6)
    with pytest.raises(IKError, match="no joint angles within the limits reach the pose"):
        solve(m, Frame.trans(900, 0, 0).matrix, m.home)


@pytest.mark.parametrize("text, message", [
    ("name = 'x'", "not a valid arm model"),
    ("[[joints]]\na = 1\n", "not a valid arm model"),
    ("this is = not toml =", "not valid TOML"),
])
def test_bad_model_files(tmp_path, text, message):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(RobotError, match=message):
        load_model(path)
    with pytest.raises(RobotError, match="no arm model nosuch"):
        load_model("nosuch")


# The simulator -------------------------------------------------------------------------

def test_sim_checks_the_whole_move_before_it_starts():
    r = SimRobot()
    start, clock = r.joints(), r.clock
    with pytest.raises(RobotError, match="below the table plane"):
        r.move((Frame.trans(350, 0, -20) * Frame.rotx(180)).matrix)
    with pytest.raises(RobotError, match="outside its limits"):
        r.jmove([0, 0, 0, 0, 300])
    assert r.joints() == start and r.clock == clock and r.trajectory == []


def test_sim_time_comes_from_the_joint_speeds():
    r = SimRobot()  # home [0, 60, -110, 50, 0]; speeds 90, 60, 75, 120, 180 degrees/s
    r.jmove([45, 60, -110, 50, 0])
    assert r.clock == pytest.approx(45 / 90)
    r.speed(50)
    r.jmove([45, 30, -110, 50, 0])
    assert r.clock == pytest.approx(45 / 90 + 30 / 60 * 2)
    r.open()
    r.close()
    r.delay(1.5)
    assert r.clock == pytest.approx(0.5 + 1.0 + 0.8 + 1.5)
    assert [m.kind for m in r.trajectory] == ["jmove", "jmove"]


def test_sim_straight_line_keeps_t5_on_the_line():
    r = SimRobot()
    a = (Frame.trans(300, -100, 150) * Frame.rotz(20) * Frame.rotx(180)).matrix
    b = (Frame.trans(380, 80, 120) * Frame.rotz(-30) * Frame.rotx(180)).matrix
    r.move(a)
    r.moves(b)
    path = r.trajectory[-1].path
    assert len(path) > 50
    p0, p1 = a[:3, 3], b[:3, 3]
    for q in path:
        p = fk(r.model, q)[:3, 3]
        off = np.linalg.norm(np.cross(p - p0, p1 - p0)) / np.linalg.norm(p1 - p0)
        assert off < 1e-6
    np.testing.assert_allclose(r.here(), b, atol=1e-9)


def test_sim_plot_shows_axes_a_grid_and_each_kind_of_motion(tmp_path):
    from rcl.robots.plot import COLOURS, nice_step

    r = SimRobot()
    r.move((Frame.trans(350, 50, 150) * Frame.rotx(180)).matrix)
    r.moves((Frame.trans(350, 50, 120) * Frame.rotx(180)).matrix)
    r.home()
    r.save_plot(str(tmp_path / "path.png"))
    img = np.asarray(Image.open(tmp_path / "path.png").convert("RGB"))
    assert img.shape == (476, 840, 3)
    colours = {tuple(c) for c in img.reshape(-1, 3)[::3]}
    for kind in ("move", "moves", "home"):  # each motion in its colour, and the same in the legend
        assert COLOURS[kind] in colours, kind
    assert COLOURS["jmove"] not in colours  # the legend names only what ran
    assert (228, 228, 228) in colours  # the grid
    # the tick steps: 1, 2 or 5 times a power of ten, about five to a panel
    assert [nice_step(s) for s in (10.0, 47.0, 130.0, 900.0, 0.3)] == [2.0, 10.0, 50.0, 200.0, 0.1]


def test_motion_errors_in_rcl_leave_the_arm_where_it_was():
    s = Session(out=io.StringIO())
    s.run("MOVE(TRANS(350, 0, 150) * ROTX(180))")
    before = s.robot.joints()
    with pytest.raises(RclRuntimeError) as e:
        s.run("MOVE(TRANS(350, 0, 150) * ROTX(150))")
    assert "out of the arm's vertical plane" in e.value.message and e.value.span.line == 1
    assert s.robot.joints() == before
    s.run("TRY\n  MOVE(TRANS(2000, 0, 0))\nEXCEPT\n  WRITELN(ERRMSG())\nEND\nVAR q : ARRAY [1..5] OF REAL\nJOINTS(q)")
    assert s["q"] == before


# The SSC-32 arm ---------------------------------------------------------------------------

AL5D_PROGRAM = """VAR q : ARRAY [1..5] OF REAL
q[1] := 30
JMOVE(q)
OPEN
SPEED(50)
q[1] := 0; q[2] := 10; q[3] := -20; q[4] := 5; q[5] := -45
JMOVE(q)
CLOSE
JOINTS(q)
WRITELN(q)
HOME
"""

# By hand: pulse = 1500 + direction * 10 us/degree * angle (the shoulder's direction is -1);
# time = the slowest joint's angle / its speed, doubled at SPEED(50); the gripper 1200 us open,
# 2000 us closed, 0.5 s; Q is polled until it answers '.' (the fake says '+' once per move).
AL5D_LOG = (b"VER\rQP0\rQP1\rQP2\rQP3\rQP4\r"
            b"#0P1800#1P1500#2P1500#3P1500#4P1500T667\rQ\rQ\r"  # home (0,0,0,-60,0) -> 30 at base: 60/90 s
            b"#5P1200T500\rQ\rQ\r"
            b"#0P1500#1P1400#2P1300#3P1550#4P1050T750\rQ\rQ\r"  # 45 degrees of wrist rotate at 120/s, doubled
            b"#5P2000T500\rQ\rQ\r"
            b"#0P1500#1P1500#2P1500#3P900#4P1500T1444\rQ\rQ\r")  # 65 degrees of wrist at 90/s, doubled


def test_al5d_session_log_against_the_fake_ssc32_byte_for_byte():
    fake = FakeSSC32()
    try:
        robot = SerialRobot(fake.path, "al5d")
        out = io.StringIO()
        Session(robot=robot, out=out).run(AL5D_PROGRAM)
        robot.close_port()
        time.sleep(0.05)
        assert out.getvalue() == "[0, 10, -20, 5, -45]\n"
        assert bytes(fake.received) == AL5D_LOG
    finally:
        fake.close()


@pytest.mark.slow
@pytest.mark.parametrize("mode, message", [("garbage", "answered b'x' to Q"), ("silent", "did not answer Q")])
def test_a_faulty_controller_ends_the_program_within_seconds_with_a_halt(mode, message):
    fake = FakeSSC32(mode)
    try:
        robot = SerialRobot(fake.path, "al5d", answer_timeout=0.5)
        t0 = time.monotonic()
        with pytest.raises(RclRuntimeError, match=message):
            Session(robot=robot, out=io.StringIO()).run("HOME\nWRITELN('never')")
        assert time.monotonic() - t0 < 3
        time.sleep(0.05)
        assert b"\x1bSTOP 0\rSTOP 1\rSTOP 2\rSTOP 3\rSTOP 4\r" in bytes(fake.received)
        robot.close_port()
    finally:
        fake.close()


def test_a_device_that_is_not_an_ssc32_is_refused():
    with pytest.raises(RobotError, match="not an SSC-32"):
        SerialRobot("loop://", "al5d", answer_timeout=0.3)
    with pytest.raises(RobotError, match="cannot open the serial port"):
        SerialRobot("/dev/no-such-port", "al5d")
    with pytest.raises(RobotError, match="has no \\[ssc32\\] section"):
        SerialRobot("loop://", "smartarms")


@pytest.mark.slow
def test_cli_robot_options(tmp_path):
    program = tmp_path / "p.rcl"
    program.write_text("MOVE(TRANS(350, 0, 150) * ROTX(180))\nHOME\nWRITELN('ok')\n")
    r = rcl("run", str(program), "--plot", str(tmp_path / "path.png"))
    assert r.returncode == 0 and r.stdout == "ok\n" and (tmp_path / "path.png").exists()
    far = tmp_path / "far.rcl"
    far.write_text("WRITELN('start')\nMOVE(TRANS(2000, 0, 150) * ROTX(180))\nWRITELN('no')\n")
    r = rcl("run", str(far))
    assert r.returncode == 1 and "out of reach" in r.stderr and r.stdout == "start\n"
    # the built-in cell with another arm: refused before anything runs when it cannot reach the tray
    r = rcl("run", str(program), "--model", "al5d")
    assert r.returncode == 2 and r.stdout == ""
    assert "--model: the built-in cell: the al5d arm cannot reach the tray's corner (290, -60, 0) mm" in r.stderr
    # a cell file that brings the tray within the al5d's reach but not the press: refused, naming it
    cell = tmp_path / "al5d.toml"
    cell.write_text('[robot]\nmodel = "al5d"\n[tray]\ncentre = [210.0, 0.0]\n'
                    '[frames.E]\nxyz = [0.0, 0.0, 0.0]\nrpy = [0.0, 0.0, 0.0]\n'
                    '[frames.PRESS]\nxyz = [200.0, 180.0, 60.0]\nrpy = [0.0, -90.0, 0.0]\n')
    r = rcl("run", str(program), "--cell", str(cell))
    assert r.returncode == 2 and r.stdout == ""
    assert "the al5d arm cannot bring a wire's end to the station PRESS at (200, 180, 60) mm" in r.stderr
    r = rcl("run", str(program), "--robot", "bogus")
    assert r.returncode == 2 and "unknown robot" in r.stderr
    r = rcl("run", str(program), "--model", "nosuch")
    assert r.returncode == 2 and "no arm model nosuch" in r.stderr
    fake = FakeSSC32()
    try:
        jmove = tmp_path / "j.rcl"
        jmove.write_text("VAR q : ARRAY [1..5] OF REAL\nq[1] := 30\nJMOVE(q)\nWRITELN('moved')\n")
        r = rcl("run", str(jmove), "--robot", f"ssc32:{fake.path}@115200")
        assert (r.returncode, r.stdout) == (0, "moved\n"), r.stderr
        assert b"#0P1800#1P1500#2P1500#3P1500#4P1500T667\r" in bytes(fake.received)
    finally:
        fake.close()


def test_realtime_sim_takes_the_time_and_halt_cuts_a_motion_short():
    import threading

    r = SimRobot(realtime=True)
    t0 = time.monotonic()
    r.jmove([9, 60, -110, 50, 0])  # 9 degrees of waist at 90/s: 0.1 s
    assert 0.08 < time.monotonic() - t0 < 1.0
    threading.Timer(0.1, r.halt).start()
    t0 = time.monotonic()
    with pytest.raises(RobotError, match="halted"):
        r.jmove([-160, 60, -110, 50, 0])  # 169 degrees: almost 2 s, cut after 0.1 s
    assert time.monotonic() - t0 < 1.0
    assert -30 < r.joints()[0] < 9  # it stopped early on the way, where it was when halted


@pytest.mark.slow
def test_the_built_in_cell_is_laid_out_for_the_puma560():
    # --model puma560 on the built-in cell: its layout (base on a pedestal 700 mm above the tray,
    # the bath farther out), and the main job runs on it to the end
    from rcl.cell import load_config
    from rcl.workcell import open_cell

    config = load_config(arm="puma560")
    assert config.source == "the built-in cell laid out for puma560" and not config.from_file
    assert config["robot"]["model"] == "puma560" and config.frame("Z").p[2] == 700.0
    assert load_config(arm="al5d")["robot"]["model"] == "al5d"  # no layout ships: the arm alone
    open_cell(config)  # reaches the tray and every station
    r = rcl("run", "examples/crimp.rcl", "--model", "puma560", "--seed", "3")
    assert r.returncode == 0, r.stderr
    assert "crimped" in r.stdout and "the tray is empty" in r.stdout


def test_station_check_turns_as_stdlib_radial_does():
    # the up-front station check's RADIAL^ against stdlib/frames.rcl's own, on random poses
    from rcl.workcell import _radial

    s = Session()
    s.run("IMPORT 'frames'")
    rng = np.random.default_rng(5)
    for _ in range(20):
        roll, pitch, yaw = (float(v) for v in rng.uniform(-180, 180, 3))
        x, y, z = (float(v) for v in rng.uniform(-400, 400, 3))
        g = Frame.trans(x, y, z) * Frame.rotz(yaw) * Frame.roty(pitch) * Frame.rotx(roll)
        want, _ = s.evaluate(f"RADIAL^(TRANS({x!r}, {y!r}, {z!r}) * ROTZ({yaw!r}) * ROTY({pitch!r}) * ROTX({roll!r}))")
        assert np.allclose(np.asarray(_radial(g).matrix), np.asarray(want.matrix), atol=1e-9)
