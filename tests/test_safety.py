"""Safety: the files a program may touch (rcl.files), and the limits that keep hostile programs and files from crashing rcl."""
from __future__ import annotations

import io
import os
import subprocess
import sys

import pytest

from rcl import RclRuntimeError, RclStaticError, Session
from rcl.files import MAX_NAME, FileRefused, Files

FIT = "\n".join(f"CALPOINT({u}, {v}, {u / 4}, {v / 4})" for u in range(0, 500, 100) for v in range(0, 500, 100))


@pytest.fixture
def place(tmp_path):
    """tmp/prog (the program's folder, with a fitted model saved as m.json), tmp/outside (a file
    there), tmp/data; a symlink prog/out -> outside."""
    prog, outside, data = tmp_path / "prog", tmp_path / "outside", tmp_path / "data"
    for d in (prog, outside, data):
        d.mkdir()
    (outside / "secret.json").write_text("{}")
    (outside / "x.rcl").write_text("WRITELN('outside')\n")
    (prog / "out").symlink_to(outside)
    s = Session(out=io.StringIO())
    s.run(FIT + "\nr := FITWARP()\n")
    s.camera_model.save(prog / "m.json")
    return tmp_path


def run_program(folder, text, **session):
    """Run text as folder/p.rcl with a camera model fitted; the session."""
    (folder / "p.rcl").write_text(FIT + "\nr := FITWARP()\n" + text + "\n")
    s = Session(out=io.StringIO(), **session)
    s.run_file(folder / "p.rcl")
    return s


@pytest.mark.parametrize("name", ["ABS/outside/w.json", "../outside/w.json", "out/w.json", "out/../../outside/w.json"])
def test_savewarp_writes_nothing_outside_the_programs_folder(place, name):
    name = name.replace("ABS", str(place))
    with pytest.raises(RclRuntimeError, match="SAVEWARP: .* is outside the folders a program may write"):
        run_program(place / "prog", f"SAVEWARP('{name}')")
    assert sorted(p.name for p in (place / "outside").iterdir()) == ["secret.json", "x.rcl"]


@pytest.mark.parametrize("name", ["ABS/outside/secret.json", "../outside/secret.json", "out/secret.json",
                                  "/etc/passwd", "/dev/zero", "/dev/stdin", "missing/../../outside/secret.json"])
def test_loadwarp_reads_nothing_outside_and_does_not_say_whether_it_exists(place, name):
    name = name.replace("ABS", str(place))
    with pytest.raises(RclRuntimeError) as e:
        run_program(place / "prog", f"LOADWARP('{name}')")
    assert "is outside the folders a program may read" in str(e.value)
    assert "JSON" not in str(e.value) and "No such file" not in str(e.value)


def test_inside_the_folder_and_the_data_folders_files_are_read_and_written(place):
    prog, data = place / "prog", place / "data"
    run_program(prog, "SAVEWARP('sub_w.json')\nLOADWARP('m.json')\nLOADWARP('./sub_w.json')")
    assert (prog / "sub_w.json").is_file()
    # a data folder: relative names start there; the program's own folder stays readable by full path
    run_program(prog, f"SAVEWARP('w.json')\nLOADWARP('w.json')\nLOADWARP('{prog}/m.json')", data=[data])
    assert (data / "w.json").is_file() and not (prog / "w.json").exists()
    # widened by the embedding API
    run_program(prog, f"SAVEWARP('{place}/outside/w.json')", any_file=True)
    assert (place / "outside" / "w.json").is_file()


def test_filepath_names_where_a_file_name_leads_and_refuses_the_same_names(place):
    prog, data = place / "prog", place / "data"
    assert run_program(prog, "a := FILEPATH('m.json')")["a"] == str(prog / "m.json")
    assert run_program(prog, "a := FILEPATH('w.json')", data=[data])["a"] == str(data / "w.json")  # data first
    for name in ("out/secret.json", "/etc/passwd"):  # a symlink out, an absolute path
        s = run_program(prog, f"TRY\n  a := FILEPATH('{name}')\nEXCEPT\n  a := ERRMSG()\nEND")
        assert s["a"] == (f"FILEPATH: '{name}' is outside the folders a program may read: the program's folder "
                          f"and the standard library")


def test_devices_pipes_folders_and_huge_files_are_not_read(place):
    prog = place / "prog"
    os.mkfifo(prog / "pipe.json")  # opening it to read would block for ever
    (prog / "folder.json").mkdir()
    with open(prog / "big.json", "wb") as f:
        f.truncate(2 * 1024 * 1024)
    for name, why in (("pipe.json", "not a regular file"), ("folder.json", "Is a directory"),
                      ("big.json", "larger than 1024 kB"), ("/dev/zero", "not a regular file")):
        with pytest.raises(RclRuntimeError, match=f"LOADWARP: .*{why}"):
            run_program(prog, f"LOADWARP('{name}')", any_file=True)
    with pytest.raises(RclRuntimeError, match="SAVEWARP: 'folder.json' is not a regular file"):
        run_program(prog, "SAVEWARP('folder.json')")


def test_names_that_are_no_names_are_refused(place):
    files = Files()
    for name, why in (("a\0b", "NUL"), ("x" * (MAX_NAME + 1), "characters"), ("", "empty")):
        with pytest.raises(FileRefused, match=why):
            files.resolve(name)
    with pytest.raises(RclRuntimeError, match="LOADWARP: a file name of 2000 characters"):
        run_program(place / "prog", f"LOADWARP('{'y' * 2000}')")
    # a name too long for the file system is only not found
    with pytest.raises(RclRuntimeError, match="LOADWARP: cannot read"):
        run_program(place / "prog", f"LOADWARP('{'y' * 300}.json')")


@pytest.mark.parametrize("name", ["../outside/x", "ABS/outside/x", "out/x"])
def test_import_finds_nothing_outside_the_allowed_folders_and_nothing_runs(place, name):
    name = name.replace("ABS", str(place))
    out = io.StringIO()
    (place / "prog" / "p.rcl").write_text(f"IMPORT '{name}'\nWRITELN('ran')\n")
    with pytest.raises(RclStaticError, match=r"p\.rcl:1:1: error: IMPORT .* outside the folders a program may read"):
        Session(out=out).run_file(place / "prog" / "p.rcl")
    assert out.getvalue() == ""


def test_import_of_a_long_name_and_from_a_declared_folder(place):
    prog = place / "prog"
    (prog / "p.rcl").write_text(f"IMPORT '{'z' * 300}'\n")
    with pytest.raises(RclStaticError, match="cannot find module"):
        Session(out=io.StringIO()).run_file(prog / "p.rcl")
    (prog / "q.rcl").write_text("IMPORT 'x'\n")
    out = io.StringIO()
    Session(out=out, search_path=[place / "outside"]).run_file(prog / "q.rcl")
    assert out.getvalue() == "outside\n"


@pytest.mark.slow
def test_the_cli_refuses_a_path_out_with_a_located_error_and_takes_data_folders(place):
    prog = place / "prog"
    (prog / "p.rcl").write_text(f"{FIT}\nr := FITWARP()\nSAVEWARP('{place}/outside/w.json')\n")
    r = subprocess.run(check=False, args=[sys.executable, "-m", "rcl", "run", str(prog / "p.rcl")], capture_output=True,
                       text=True, timeout=120, cwd=place)  # the working folder is not the program's
    assert r.returncode == 1 and "Traceback" not in r.stderr
    assert f"p.rcl:{FIT.count(chr(10)) + 3}:1: error: SAVEWARP:" in r.stderr, r.stderr
    assert not (place / "outside" / "w.json").exists()
    (prog / "p.rcl").write_text(f"{FIT}\nr := FITWARP()\nSAVEWARP('w.json')\n")
    r = subprocess.run(check=False, args=[sys.executable, "-m", "rcl", "run", str(prog / "p.rcl"), "--data", str(place / "data")],
                       capture_output=True, text=True, timeout=120, cwd=place)
    assert r.returncode == 0, r.stderr
    assert (place / "data" / "w.json").is_file()
    r = subprocess.run(check=False, args=[sys.executable, "-m", "rcl", "run", str(prog / "p.rcl"), "--data", str(place / "nope")],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and "--data:" in r.stderr and "not a folder" in r.stderr


# Deep programs and files: one limit, at check time; never a crash --------------------------------

def nested(opener: str, closer: str, n: int, inner: str = "WRITELN(1)") -> str:
    return opener * n + inner + "\n" + closer * n


@pytest.mark.parametrize("text", [
    nested("IF TRUE THEN\n", "END\n", 10_000),
    nested("WHILE FALSE DO\n", "END\n", 50_000),
    nested("REPEAT\n", "UNTIL TRUE\n", 50_000),
    nested("FOR i := 1 TO 1 DO\n", "END\n", 50_000),
    nested("TRY\n", "EXCEPT\nEND\n", 50_000),
    "x := " + "-" * 50_000 + "1\n",
    "x := 1" + " + 1" * 100_000 + "\n",
])
@pytest.mark.slow
def test_a_program_nested_too_deep_is_refused_before_it_runs(text):
    from rcl.parser import MAX_NESTING

    s = Session(out=io.StringIO())
    diagnostics = s.check(text, "deep.rcl")
    assert len(diagnostics) == 1 and f"nests too deeply: more than {MAX_NESTING} levels" in diagnostics[0].message
    with pytest.raises(RclStaticError):
        s.run(text, "deep.rcl")


@pytest.mark.slow
def test_nesting_just_within_the_limit_runs_and_the_cli_never_crashes(tmp_path):
    out = io.StringIO()
    Session(out=out).run(nested("IF TRUE THEN\n", "END\n", 1_900) + "x := " + "-" * 3_001 + "1\nWRITELN(x)\n")
    assert out.getvalue() == "1\n-1\n"
    (tmp_path / "deep.rcl").write_text(nested("IF TRUE THEN\n", "END\n", 10_000))
    r = subprocess.run(check=False, args=[sys.executable, "-m", "rcl", "run", str(tmp_path / "deep.rcl")], capture_output=True,
                       text=True, timeout=120)
    assert r.returncode == 2 and "deep.rcl:2001:1: error: the program nests too deeply" in r.stderr


@pytest.mark.slow
def test_recursion_through_deeply_nested_blocks_is_an_error_try_catches():
    """Each call within 1,900 nested IFs takes thousands of Python frames: Python's stack is spent
    long before the 1,000-call limit. That is an RCL error at the call, not a crash, and TRY catches it."""
    body = nested("IF TRUE THEN\n", "END\n", 1_900, inner="IF d < 1000 THEN x := F(d + 1) END")
    program = ("FUNCTION F(d : INTEGER) : INTEGER\n" + body + "RETURN d\nEND\n"
               "TRY\n  WRITELN(F(1))\nEXCEPT\n  WRITELN('caught: ', ERRMSG())\nEND\n")
    out = io.StringIO()
    Session(out=out).run(program, "deep.rcl")
    assert out.getvalue() == "caught: the program nests too deeply to run: calls within deeply nested blocks\n"


def test_a_camera_model_file_nested_deep_is_refused_not_a_crash(tmp_path):
    (tmp_path / "deep.json").write_text('{"format": "rcl-camera-model", "fit": ' + "[" * 70_000 + "]" * 70_000 + "}")
    with pytest.raises(RclRuntimeError, match="nested 70001 deep: not a camera-model file"):
        Session(out=io.StringIO(), data=[tmp_path]).run("LOADWARP('deep.json')", "x.rcl")
    r = subprocess.run(check=False, args=[sys.executable, "-m", "rcl", "calib", "apply", str(tmp_path / "deep.json"),
                        str(tmp_path / "q.csv")], capture_output=True, text=True, timeout=120)
    assert r.returncode != 0 and "nested 70001 deep" in r.stderr and "Traceback" not in r.stderr


# Numbers and strings out of range: RCL errors that TRY catches, never "internal error" -----------

@pytest.mark.parametrize("text, message", [
    ("x := COS(1e308 * 10)", "COS of inf degrees: the angle must be a finite number"),
    ("x := SIN(1e308 * 10)", "SIN of inf degrees"),
    ("x := TAN(1e308 * 10 - 1e308 * 10)", "TAN of nan degrees"),
    ("x := 1e308 * 10 - 1e308 * 10\ni := ROUND(x)", "ROUND of nan is not a 64-bit INTEGER"),
    ("F^ := TRANS(1e308, 0, 0) * TRANS(1e308, 0, 0)\nG^ := INV(F^)\nMOVE(G^)",
     "MOVE: the frame holds a number that is not finite"),
    ("F^ := TRANS(1e308, 0, 0) * TRANS(1e308, 0, 0)\nMOVES(F^)", "MOVES: the frame holds a number that is not"),
    ("s := 'ab'\nWHILE TRUE DO s := s + s END", "string too long: 33,554,432 characters"),
])
def test_numbers_and_strings_out_of_range_are_rcl_errors_try_catches(text, message):
    s = Session(out=io.StringIO())
    with pytest.raises(RclRuntimeError, match=message) as e:
        s.run(text, "t.rcl")
    assert e.value.render().startswith("t.rcl:") and s.robot.trajectory == []  # the arm never moved
    out = io.StringIO()
    body = text.replace("\n", "\n  ")
    Session(out=out).run(f"TRY\n  {body}\nEXCEPT\n  WRITELN('caught: ', ERRMSG())\nEND\n", "t.rcl")
    assert out.getvalue().startswith("caught: ") and message.split(":")[0] in out.getvalue()


@pytest.mark.slow
def test_ctrl_c_while_checking_or_seeing_ends_with_130_and_a_message(tmp_path):
    import signal
    import time

    (tmp_path / "big.rcl").write_text("x := 1\n" * 300_000)  # ~8 s of checking: Ctrl-C comes well before its end
    for args in (["check", str(tmp_path / "big.rcl")], ["run", str(tmp_path / "big.rcl")]):
        # as from a terminal: a job started in the background inherits SIGINT ignored, and rcl keeps it so
        proc = subprocess.Popen([sys.executable, "-m", "rcl", *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                text=True, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
        time.sleep(3.0)  # (past start-up's imports, which take over 1.5 s on a busy machine)
        proc.send_signal(signal.SIGINT)
        _out, err = proc.communicate(timeout=60)
        assert proc.returncode == 130 and "interrupted" in err and "Traceback" not in err, (args, err[-500:])


@pytest.mark.parametrize("fit, message", [
    ('"abc"', '"fit" must be an object, not str'),
    ('[1, "x"]', '"fit" must be an object, not list'),
    ('{"a": 1}', '"rms_mm" must be a finite number'),
    ('{"points": "many", "rms_mm": 1, "max_mm": 1}', '"points" must be a whole number'),
    ('{"rms_mm": 1' + '0' * 4000 + ', "max_mm": 1}', '"rms_mm" must be a finite number'),
    ('{"rms_mm": 1' + '0' * 5000 + ', "max_mm": 1}', "not a camera-model file"),
    ('{"rms_mm": 1, "max_mm": 1, "residuals_mm": [[1, "x"]]}', '"residuals_mm" must be a list'),
])
@pytest.mark.slow
def test_a_camera_model_with_a_bad_fit_is_a_clear_error(place, fit, message):
    import json

    doc = json.loads((place / "prog" / "m.json").read_text())
    doc.pop("fit")
    text = json.dumps(doc)[:-1] + ', "fit": ' + fit + "}"
    (place / "bad.json").write_text(text)
    (place / "q.csv").write_text("u,v\n10,20\n")
    r = subprocess.run(check=False, args=[sys.executable, "-m", "rcl", "calib", "apply", str(place / "bad.json"),
                                          str(place / "q.csv")],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and message in r.stderr and "Traceback" not in r.stderr, r.stderr[-300:]


@pytest.mark.slow
def test_rcl_vision_refuses_a_scale_no_camera_has(tmp_path):
    from PIL import Image

    Image.new("L", (64, 64), 128).save(tmp_path / "grey.png")
    for scale in ("inf", "1e-9", "1e6", "nan", "0"):
        r = subprocess.run(check=False, args=[sys.executable, "-m", "rcl", "vision", str(tmp_path / "grey.png"),
                                              "--px-per-mm", scale],
                           capture_output=True, text=True, timeout=60)
        assert r.returncode == 2 and "the scale must be 0.5 to 100 px per mm" in r.stderr, r.stderr[-300:]


@pytest.mark.parametrize("change, message", [
    (("us_per_degree = [10.0, 10.0, 10.0, 10.0, 10.0]", "us_per_degree = [0.0, 10.0, 10.0, 10.0, 10.0]"),
     "us_per_degree must not be 0"),
    (("channels = [0, 1, 2, 3, 4]", 'channels = ["a", 1, 2, 3, 4]'), "channels must be a list of whole numbers"),
    (("channels = [0, 1, 2, 3, 4]", "channels = [0, 0, 2, 3, 4]"), "distinct channels"),
    (("direction = [1, -1, 1, 1, 1]", "direction = [0, -1, 1, 1, 1]"), "direction must hold 1 or -1"),
    (("baud = 115200", 'baud = "fast"'), "baud must be a whole number"),
    (("linear_speed = 100.0", "linear_speed = 0.0"), "linear_speed must be above zero"),
    (("linear_speed = 100.0", "linear_speed = nan"), "linear_speed must be a finite number"),
])
@pytest.mark.slow
def test_an_arm_model_with_a_bad_number_is_refused_when_loaded(tmp_path, change, message):
    from rcl.robots import RobotError
    from rcl.robots.kinematics import MODELS_DIR, load_model

    text = (MODELS_DIR / "al5d.toml").read_text()
    old, new = change
    assert old in text, old
    (tmp_path / "arm.toml").write_text(text.replace(old, new))
    with pytest.raises(RobotError, match=message):
        load_model(tmp_path / "arm.toml")
    r = subprocess.run(check=False, args=[sys.executable, "-m", "rcl", "run", "nothing.rcl", "--model",
                                      str(tmp_path / "arm.toml")],
                       capture_output=True, text=True, timeout=60, cwd=tmp_path)
    assert r.returncode == 2 and message in r.stderr and "Traceback" not in r.stderr, r.stderr[-300:]


def test_the_pulse_sent_to_a_servo_says_the_angle_asked_for():
    import dataclasses

    from rcl.robots import RobotError
    from rcl.robots.kinematics import load_model
    from rcl.robots.ssc32 import SSC32

    model = load_model("al5d")
    driver = SSC32(None, model)
    assert driver.pulse(0, 30.0) == 1800 and driver.pulse(1, 30.0) == 1200  # 10 us a degree; joint 1 reversed
    tiny = dataclasses.replace(model, ssc32={**model.ssc32, "us_per_degree": [0.001] * 5})
    with pytest.raises(RobotError, match="the pulse 1500 us means 0.0 degrees, not the 30.0 asked for"):
        SSC32(None, tiny).pulse(0, 30.0)


@pytest.mark.parametrize("text, message", [
    ("[camera]\nnoise = -5\n", "camera.noise must be 0 to 1, not -5"),
    ("[robot]\nseed = -1\n", "robot.seed must be 0 to"),
    ("[tray]\nlayers = 99999999999999999999\n", "tray.layers must be 1 to 10"),
    ("[tray]\nwires = " + "[" * 5000 + "]" * 5000 + "\n", "nested too deep for a cell file"),
    ("[camera]\npx_per_mm = 1e300\n", "camera.px_per_mm must be 0 (from the width and fov) or 0.5 to 100"),
    ("[bath]\nseconds = -1\n", "bath.seconds must be 0 to 3600"),
    ("[camera]\nwidth = 4096\n", "camera.width must be 64 to 2048, not 4096"),  # 2 GB a look
])
@pytest.mark.slow
def test_a_cell_file_with_a_number_out_of_range_is_refused_when_loaded(tmp_path, text, message):
    from rcl.cell import CellConfigError, load_config

    (tmp_path / "cell.toml").write_text(text)
    with pytest.raises(CellConfigError, match=message.replace("(", r"\(").replace(")", r"\)")):
        load_config(tmp_path / "cell.toml")
    (tmp_path / "one.rcl").write_text("WRITELN(1)\n")
    r = subprocess.run(check=False, args=[sys.executable, "-m", "rcl", "run", str(tmp_path / "one.rcl"), "--cell",
                        str(tmp_path / "cell.toml")], capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and message in r.stderr and "Traceback" not in r.stderr and r.stdout == ""


@pytest.mark.parametrize("text, where, shown", [
    ("x := 1\ry := \n", "1:13", "x := 1 y := "),
    ("x := 1\fy := 2\nz := q\n", "2:6", "z := q"),
    ("x := 1\u2028y := 2\n", "1:7", "x := 1 y := 2"),
    ("x := 1\r\ny := 1 / 0\r\n", "2:8", "y := 1 / 0"),
    ("x := 1\x0by := 2\n", "1:7", "x := 1 y := 2"),
])
def test_errors_name_the_line_and_column_the_parser_counted(text, where, shown):
    # one definition of a line everywhere: ended by LF (CRLF counts once); CR, FF, VT, U+2028 end none
    with pytest.raises((RclStaticError, RclRuntimeError)) as e:
        Session(out=io.StringIO()).run(text, "f.rcl")
    lines = e.value.render().split("\n") if isinstance(e.value, RclRuntimeError) else \
        e.value.diagnostics[0].render().split("\n")
    assert lines[0].startswith(f"f.rcl:{where}: error:"), lines
    assert lines[1] == shown, lines
    assert "^" in lines[2] and lines[2].index("^") == int(where.split(":")[1]) - 1


@pytest.mark.slow
def test_an_image_too_large_for_any_camera_is_refused_before_it_is_decoded(tmp_path):
    import warnings

    from PIL import Image

    from rcl.camera import ImageError
    from rcl.camera.images import read_image

    Image.new("L", (13_377, 13_377), 0).save(tmp_path / "huge.png")  # 2.3 MB on disk, 179 M pixels
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # and no DecompressionBombWarning leaks out
        with pytest.raises(ImageError, match="13377 x 13377 px, more than the 40,000,000 pixels"):
            read_image(tmp_path / "huge.png")
    r = subprocess.run(check=False, args=[sys.executable, "-m", "rcl", "vision", str(tmp_path / "huge.png")], capture_output=True,
                       text=True, timeout=60)
    assert r.returncode != 0 and "more than the 40,000,000 pixels" in r.stderr and "Warning" not in r.stderr


@pytest.mark.slow
def test_a_time_limit_stops_a_program_that_runs_on(tmp_path):
    import time

    from rcl import RclCancelled

    s = Session(out=io.StringIO(), time_limit=0.5)
    t0 = time.monotonic()
    with pytest.raises(RclCancelled, match="the time limit of 0.5 s is spent"):
        s.run("WHILE TRUE DO\n  x := 1\nEND\n", "loop.rcl")
    assert time.monotonic() - t0 < 3
    s.run("WRITELN('again')")  # the next run has its own time
    (tmp_path / "loop.rcl").write_text("WHILE TRUE DO\n  x := COS(1)\nEND\n")
    r = subprocess.run(check=False, args=[sys.executable, "-m", "rcl", "run", str(tmp_path / "loop.rcl"), "--time-limit", "1"],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 1 and "the time limit of 1 s is spent" in r.stderr and "halted" in r.stderr
    with pytest.raises(ValueError):
        Session(time_limit=0)


@pytest.mark.slow
def test_recursion_with_large_local_arrays_stops_at_a_memory_bound():
    from rcl.interpreter import MAX_LIVE_ELEMENTS

    program = ("PROCEDURE P(n : INTEGER)\n  VAR a : ARRAY[1..10000000] OF REAL\n  a[n + 1] := n\n"
               "  IF n > 0 THEN P(n - 1) END\nEND\nP(1000)\n")
    with pytest.raises(RclRuntimeError, match=f"too much array memory: .* 30,000,000 elements .at most "
                                              f"{MAX_LIVE_ELEMENTS:,}"):
        Session(out=io.StringIO()).run(program, "arr.rcl")
    out = io.StringIO()  # P(1) holds 20,000,000 at its deepest: within the bound, and given back as it returns
    Session(out=out).run(program.replace("P(1000)", "P(1)\nP(1)\nP(1)\nWRITELN('done')"), "arr.rcl")
    assert out.getvalue() == "done\n"


def test_only_the_first_unknown_names_get_a_suggestion():
    # each suggestion compares with every name: a file with thousands of unknown names must not
    # cost quadratic time (10,000 CONSTs naming the next one took over 120 s to check)
    from rcl.checker import MAX_SUGGESTIONS

    source = "\n".join(f"CONST value{i} = value{i + 1} + 1" for i in range(300)) + "\nCONST value300 = 0\n"
    diagnostics = Session().check(source, "c.rcl")
    unknown = [d for d in diagnostics if d.message.startswith("unknown name")]
    assert len(unknown) == 300
    assert any("did you mean" in d.message for d in unknown[:MAX_SUGGESTIONS])
    assert not any("did you mean" in d.message for d in unknown[MAX_SUGGESTIONS:])
    assert [d.span.line for d in unknown] == list(range(1, 301))  # every line shown is its own
    assert all(d.source_line.startswith(f"CONST value{d.span.line - 1} ") for d in unknown)


def test_ctrl_c_while_the_command_starts_ends_with_130_and_a_message(monkeypatch, capsys):
    """A Ctrl-C while `rcl` imports its parts (numpy, the parser: the first few tenths of a
    second) is reported as one later is, not as a traceback."""
    import types

    from rcl import launch

    class Starting(types.ModuleType):
        def __getattr__(self, name):
            raise KeyboardInterrupt

    monkeypatch.setitem(sys.modules, "rcl.cli", Starting("rcl.cli"))
    with pytest.raises(SystemExit) as stop:
        launch.main()
    assert stop.value.code == 130 and "interrupted" in capsys.readouterr().err


def test_importing_rcl_is_light():
    """`import rcl` loads neither numpy nor the parser (they come with Session or Frame), so the
    command can take a Ctrl-C from its first moments."""
    code = "import sys, rcl; print('numpy' in sys.modules, 'lark' in sys.modules); rcl.Session; print('numpy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert out == ["False", "False", "True"]
