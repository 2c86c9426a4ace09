"""The embedding API: Session."""
from __future__ import annotations

import io
import threading
import time

import numpy as np
import pytest

from rcl import Frame, RclCancelled, RclRuntimeError, RclStaticError, Session
from rcl.robots import RecordingArm
from rcl.types import Var


def run(source: str, **kw) -> tuple[Session, str]:
    out = io.StringIO()
    s = Session(out=out, **kw)
    s.run(source)
    return s, out.getvalue()


def test_variables_persist_between_runs_and_frames_come_back_as_numpy():
    s, _ = run("W^ := TRANS(300, 20, 0) * ROTY(180)\nn := 3")
    w = s["W^"]
    assert isinstance(w, Frame)
    expected = np.array([[-1, 0, 0, 300], [0, 1, 0, 20], [0, 0, -1, 0], [0, 0, 0, 1]], float)
    np.testing.assert_allclose(np.asarray(w), expected, atol=1e-12)
    np.testing.assert_allclose(w.matrix, expected, atol=1e-12)
    assert s["n"] == 3 and s["N"] == 3  # names are case-insensitive
    s.run("n := n + 1")
    assert s["n"] == 4
    with pytest.raises(KeyError):
        s["nosuch"]


def test_set_variables_from_python_and_use_them():
    out = io.StringIO()
    s = Session(out=out)
    m = np.eye(4)
    m[:3, 3] = (1, 2, 3)
    s["G^"] = m
    s["speed"] = 2.5
    s["label"] = "wire"
    s["p"] = [1.0, 2.0, 3.0]
    s.run("WRITELN(G^.P, ' ', speed * 2, ' ', label, ' ', p)")
    assert out.getvalue() == "(1, 2, 3) 5 wire (1, 2, 3)\n"
    with pytest.raises(ValueError):
        s["G^"] = np.ones((4, 4))  # not a rigid transform
    with pytest.raises(TypeError):
        s["x"] = Frame.identity()  # only frame names hold frames
    with pytest.raises(TypeError):
        s["speed"] = "fast"
    s["speed"] = 3  # an INTEGER into a REAL variable
    assert s["speed"] == 3.0 and isinstance(s["speed"], float)
    for bad in ("1x", "x-y", "_x", "\u017fx", "a^b"):  # names as the grammar's NAME and FRAMENAME have them
        with pytest.raises(ValueError, match="not an RCL name"):
            s[bad] = 1


def test_register_a_python_function_as_a_typed_builtin():
    out = io.StringIO()
    s = Session(out=out)
    calls = []

    def clearance(a: float, b: float) -> float:
        """CLEARANCE(a, b): a - b."""
        calls.append((a, b))
        return a - b

    def lift(f: Frame, h: float) -> Frame:
        return Frame.trans(0, 0, h) * f

    def count_into(n: Var[int]) -> None:
        n.set(n.get() + 1)

    s.register(clearance)
    s.register(lift, name="LIFT^")
    s.register(count_into, name="BUMP")
    s.run("k := 1\nBUMP(k)\nWRITELN(CLEARANCE(5, 2), ' ', LIFT^(IDENT(), 7).P, ' ', k)")
    assert out.getvalue() == "3 (0, 0, 7) 2\n"
    assert calls == [(5.0, 2.0)] and all(isinstance(x, float) for x in calls[0])
    # the checker knows the signature
    with pytest.raises(RclStaticError) as e:
        s.run("x := CLEARANCE('a', 2)")
    assert "argument 1 of CLEARANCE must be a REAL, not a STRING" in str(e.value)
    # a session's built-ins are its own
    assert Session().check("x := CLEARANCE(1, 2)")


def test_two_sessions_share_nothing():
    a, _ = run("x := 1\nPROCEDURE P\nEND")
    b = Session()
    assert b.get("x") is None
    assert b.check("P") and "unknown routine P" in b.check("P")[0].message
    b.run("x := 'text'")  # a different type in the other session is fine
    assert a["x"] == 1 and b["x"] == "text"
    assert a.robot is not b.robot


def test_static_error_runs_nothing_and_leaves_the_session_unchanged():
    robot = RecordingArm()
    out = io.StringIO()
    s = Session(robot=robot, out=out)
    with pytest.raises(RclStaticError) as e:
        s.run("MOVE(TRANS(1, 2, 3))\nWRITELN('hi')\ny := 1\nz := W^ + 1\nq := nosuch")
    assert [d.span.line for d in e.value.diagnostics] == [4, 5]
    assert robot.log == [] and out.getvalue() == ""
    assert s.get("y") is None  # the rejected program declared nothing
    s.run("y := 'now a string'")


def test_runtime_error_halts_the_robot_and_reports_the_rcl_stack():
    robot = RecordingArm()
    s = Session(robot=robot, out=io.StringIO())
    src = "PROCEDURE P(n : INTEGER)\n  MOVE(TRANS(n, 0, 0))\n  x := 1 DIV (n - 2)\nEND\nP(1)\nP(2)\n"
    with pytest.raises(RclRuntimeError) as e:
        s.run(src, "task.rcl")
    err = e.value
    assert (err.filename, err.span.line, err.message) == ("task.rcl", 3, "division by zero")
    assert [(f.routine, f.span.line) for f in err.stack] == [("P", 6)]
    assert robot.log[-1] == ("halt",) and [k for k, *_ in robot.log].count("move") == 2
    text = err.render()
    assert text.startswith("task.rcl:3:") and "P, called at task.rcl:6:1" in text


def test_an_equals_sign_meant_as_assignment_is_answered_with_how_to_assign():
    s = Session(out=io.StringIO())
    with pytest.raises(RclStaticError) as e:
        s.evaluate("x = 5")  # the REPL reads a line that is no statement as an expression
    assert e.value.diagnostics[0].message == "unknown name x; to assign, write x := ..."
    s.run("x := 5")
    assert s.evaluate("x = 5") == (True, "BOOLEAN")  # a known x: a comparison, as written


def test_a_recursions_call_stack_is_folded():
    s = Session(out=io.StringIO())
    with pytest.raises(RclRuntimeError) as e:
        s.run("PROCEDURE P(n : INTEGER)\n  P(n + 1)\nEND\nP(1)\n", "rec.rcl")
    assert len(e.value.stack) == 1000
    assert e.value.render().splitlines()[3:] == [
        "RCL call stack (most recent call first):",
        "  P, called at rec.rcl:2:3",
        "  [the call above 998 more times]",
        "  P, called at rec.rcl:4:1",
    ]


@pytest.mark.parametrize("loop", ["WHILE TRUE DO x := 1 END",
                                  "x := 0\nFOR i := 1 TO 1000000000000 DO x := x + 1 END"])  # a tight loop
def test_cancel_from_another_thread_stops_a_loop_and_halts(loop):
    robot = RecordingArm()
    s = Session(robot=robot, out=io.StringIO())
    timer = threading.Timer(0.2, s.cancel)
    timer.start()
    t0 = time.monotonic()
    with pytest.raises(RclCancelled):
        s.run(loop)
    assert time.monotonic() - t0 < 5
    assert robot.halted
    s.run("x := 2")  # the session is usable afterwards
    assert s["x"] == 2


def test_step_budget_stops_runaway_programs_but_not_catchable():
    s = Session(out=io.StringIO(), step_budget=1000)
    with pytest.raises(RclCancelled) as e:
        s.run("TRY\n  WHILE TRUE DO END\nEXCEPT\n  WRITELN('caught')\nEND")
    assert "step budget of 1000" in str(e.value)
    s.run("FOR i := 1 TO 500 DO END")  # the budget is per run


@pytest.mark.parametrize("body", ["", "s := s + i", "s := s + i\n  s := s - 1", "x := x + i",
                                  "s := s + ROUND(0.4)"])  # a call: the limit read every turn
def test_step_budget_counts_every_turn_of_a_tight_loop_exactly(body):
    setup = "s := 0\nx := 0.0\n"
    loop = f"FOR i := 1 TO {{n}} DO\n  {body}\nEND\n"
    Session(out=io.StringIO(), step_budget=1000).run(setup + loop.format(n=600) + loop.format(n=400))
    with pytest.raises(RclCancelled, match="step budget of 1000"):
        Session(out=io.StringIO(), step_budget=1000).run(setup + loop.format(n=600) + loop.format(n=401))
    # the turns run before a runtime error that TRY caught still count
    caught = f"TRY\n  FOR i := 1 TO 600 DO\n    {body}\n    s := 10 DIV (i - 600)\n  END\nEXCEPT\nEND\n"
    Session(out=io.StringIO(), step_budget=1000).run(setup + caught + loop.format(n=400))
    with pytest.raises(RclCancelled, match="step budget of 1000"):
        Session(out=io.StringIO(), step_budget=1000).run(setup + caught + loop.format(n=401))


def test_cancel_stops_a_loop_calling_a_slow_builtin_at_its_next_turn():
    s = Session(out=io.StringIO())

    def nap(seconds: float) -> float:
        time.sleep(seconds)
        return seconds
    s.register(nap)
    timer = threading.Timer(0.2, s.cancel)
    timer.start()
    t0 = time.monotonic()
    with pytest.raises(RclCancelled):
        s.run("x := 0.0\nFOR i := 1 TO 1000 DO x := x + NAP(0.01) END")
    assert time.monotonic() - t0 < 1.5  # not after the 256 turns a loop of short turns may run unpolled
    assert 10 <= s["i"] < 100


def test_routines_persist_and_can_be_redefined_with_the_same_signature():
    out = io.StringIO()
    s = Session(out=out)
    s.run("FUNCTION F(x : INTEGER) : INTEGER\n  RETURN x + 1\nEND\nPROCEDURE SHOW\n  WRITELN(F(1))\nEND")
    s.run("SHOW")
    s.run("FUNCTION F(x : INTEGER) : INTEGER\n  RETURN x * 10\nEND")
    s.run("SHOW")
    assert out.getvalue() == "2\n10\n"
    with pytest.raises(RclStaticError):
        s.run("FUNCTION F(x : REAL) : REAL\n  RETURN x\nEND")


def test_imports_are_loaded_once_and_cycles_are_harmless(tmp_path):
    (tmp_path / "a.rcl").write_text("IMPORT 'b'\nWRITELN('a ran')\nA_DONE := TRUE\n")
    (tmp_path / "b.rcl").write_text("IMPORT 'a'\nWRITELN('b ran')\nFUNCTION TWICE(x : INTEGER) : INTEGER\n  RETURN 2 * x\nEND\n")
    (tmp_path / "main.rcl").write_text("IMPORT 'a'\nIMPORT 'b'\nIMPORT 'frames'\nWRITELN(TWICE(21), ' ', A_DONE)\n")
    out = io.StringIO()
    s = Session(out=out)
    s.run_file(tmp_path / "main.rcl")
    assert out.getvalue() == "b ran\na ran\n42 TRUE\n"
    s.run_file(tmp_path / "main.rcl")  # already loaded: the modules do not run again
    assert out.getvalue().count("a ran") == 1


def test_missing_import_is_a_static_error(tmp_path):
    (tmp_path / "main.rcl").write_text("WRITELN('x')\nIMPORT 'nowhere'\n")
    with pytest.raises(RclStaticError) as e:
        Session().run_file(tmp_path / "main.rcl")
    d = e.value.diagnostics[0]
    assert d.span.line == 2 and "cannot find module 'nowhere'" in d.message


def test_errors_in_an_imported_file_name_that_file(tmp_path):
    (tmp_path / "lib.rcl").write_text("PROCEDURE P\n  x := 1 +\nEND\n")
    (tmp_path / "main.rcl").write_text("IMPORT 'lib'\nP\n")
    with pytest.raises(RclStaticError) as e:
        Session().run_file(tmp_path / "main.rcl")
    assert e.value.diagnostics[0].filename.endswith("lib.rcl")


def test_motion_builtins_reach_the_robot_backend():
    robot = RecordingArm()
    s = Session(robot=robot, out=io.StringIO())
    s.run("SPEED(40)\nOPEN\nMOVE(TRANS(1, 2, 3))\nMOVES(TRANS(4, 5, 6))\nCLOSE\nDELAY(1.5)\n"
          "VAR q : ARRAY [1..5] OF REAL\nq[2] := 30\nJMOVE(q)\nJOINTS(q)\nH^ := HERE^()\nHOME")
    kinds = [entry[0] for entry in robot.log]
    assert kinds == ["speed", "open", "move", "moves", "close", "delay", "jmove", "home"]
    assert robot.log[-2] == ("jmove", (0.0, 30.0, 0.0, 0.0, 0.0))
    np.testing.assert_allclose(s["H^"].p, [4, 5, 6])
    assert s["q"] == [0.0, 30.0, 0.0, 0.0, 0.0]
    with pytest.raises(RclRuntimeError) as e:
        s.run("VAR r : ARRAY [1..3] OF REAL\nJOINTS(r)")
    assert "array of 5 REALs" in e.value.message


def test_vision_builtins_turn_pixels_into_wire_frames_through_the_camera_model():
    from rcl.camera import Calibration
    from rcl.vision import Sighting

    with pytest.raises(RclRuntimeError, match="no camera"):
        Session(out=io.StringIO()).run("IF GREYWIRE(W^, WG^) THEN WRITELN('seen') END")

    class Model(Calibration):  # a camera looking straight down: x = 100 + u / 2, y = 50 - v / 2 (v runs down)
        def warp(self, u, v):
            return 100 + u / 2, 50 - v / 2, 7.0

    class Camera:
        def grab(self):
            return np.zeros((10, 10))

    def finder(image, method):
        if method == "grey":
            return None
        # the end at (20, 40) px, the wire running to +u; the grasp 30 px along, tangent 90 degrees (down the image)
        return Sighting(end=(20.0, 40.0), end_angle=0.0, grasp=(50.0, 40.0), grasp_angle=90.0)

    out = io.StringIO()
    s = Session(out=out, camera=Camera(), camera_model=Model(), wire_finder=finder)
    s.run("WRITELN(GREYWIRE(W^, WG^), ' ', BINWIRE(W^, WG^))")
    assert out.getvalue() == "FALSE TRUE\n"
    w, wg = s["W^"].matrix, s["WG^"].matrix
    np.testing.assert_allclose(w[:3, 3], [110, 30, 7])  # the end on the tray
    np.testing.assert_allclose(w[:3, 2], [1, 0, 0], atol=1e-12)  # Z along the wire, away from the end
    np.testing.assert_allclose(w[:3, 0], [0, 0, 1], atol=1e-12)  # X up out of the tray
    g = w @ wg  # the gripper in the world
    np.testing.assert_allclose(g[:3, 3], [125, 30, 7])
    np.testing.assert_allclose(g[:3, 2], [0, 0, -1], atol=1e-12)  # approach straight down
    # the tangent at the grasp is image-down, world -y; the fingers (o) close across it, along world x
    np.testing.assert_allclose(abs(g[:3, 1] @ [1, 0, 0]), 1, atol=1e-12)
