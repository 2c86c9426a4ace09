"""The rcl command as a user meets it: exit codes, diagnostics, Ctrl-C."""
from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time

import pytest
from conftest import ROOT, rcl

DIAGNOSTIC = re.compile(r"^(?P<file>[^:\n]+):(?P<line>\d+):(?P<col>\d+): error: (?P<msg>.*)$", re.M)


def test_run_ok(write):
    p = write("ok.rcl", "WRITELN('hello ', 6 * 7)\n")
    r = rcl("run", str(p))
    assert (r.returncode, r.stdout, r.stderr) == (0, "hello 42\n", "")


def test_static_errors_exit_2_with_every_diagnostic_source_line_and_caret(write):
    p = write("bad.rcl", "WRITELN('start')\nx := 1\nx := 'a'\ny := nosuch + 1\n")
    r = rcl("run", str(p))
    assert r.returncode == 2 and r.stdout == ""
    found = DIAGNOSTIC.findall(r.stderr)
    assert [(int(line), int(col)) for _, line, col, _ in found] == [(3, 6), (4, 6)]
    assert all(f.endswith("bad.rcl") for f, *_ in found)
    lines = r.stderr.splitlines()
    i = lines.index(next(s for s in lines if s.endswith("it cannot hold a STRING")))
    assert lines[i + 1] == "x := 'a'" and lines[i + 2] == "     ^~~"
    assert "Traceback" not in r.stderr


def test_runtime_error_exit_1_with_rcl_call_stack(write):
    p = write("rt.rcl", "PROCEDURE P(n : INTEGER)\n  WRITELN(10 DIV n)\nEND\nWRITELN('before')\nP(0)\n")
    r = rcl("run", str(p))
    assert r.returncode == 1 and r.stdout == "before\n"
    first = DIAGNOSTIC.search(r.stderr)
    assert first and first["line"] == "2" and first["msg"] == "division by zero"
    assert "RCL call stack" in r.stderr and "P, called at" in r.stderr and ":5:1" in r.stderr


@pytest.mark.slow
def test_check_exit_codes(write):
    good = write("good.rcl", "x := 1\n")
    bad = write("bad.rcl", "x := \n")
    r = rcl("check", str(good))
    assert r.returncode == 0 and r.stdout == f"{good}: no errors (1 line and their imports: syntax, names, types, " \
                                             "frame rules and references checked)\n"
    r = rcl("check", str(good), str(bad))
    assert r.returncode == 2 and "bad.rcl:" in r.stderr and "bad.rcl: no errors" not in r.stdout
    assert rcl("check", *map(str, sorted((ROOT / "examples").glob("*.rcl"))),
               *map(str, sorted((ROOT / "stdlib").glob("*.rcl")))).returncode == 0


@pytest.mark.slow
def test_unreadable_files_get_a_clear_message(tmp_path):
    r = rcl("run", str(tmp_path / "missing.rcl"))
    assert r.returncode == 2 and "rcl: error: cannot read" in r.stderr and "Traceback" not in r.stderr
    binary = tmp_path / "binary.rcl"
    binary.write_bytes(b"x := 1\n\xff\xfe\n")
    r = rcl("run", str(binary))
    assert r.returncode == 2 and "not UTF-8" in r.stderr
    r = rcl("run", str(tmp_path))
    assert r.returncode == 2 and "folder" in r.stderr


@pytest.mark.slow
def test_usage_errors():
    r = rcl("run")
    assert r.returncode == 2 and "usage" in r.stderr.lower()
    r = rcl("run", "x.rcl", "--step-budget", "-3")
    assert r.returncode == 2


def test_step_budget_option(write):
    p = write("loop.rcl", "WHILE TRUE DO END\n")
    r = rcl("run", str(p), "--step-budget", "100")
    assert r.returncode == 1 and "step budget" in r.stderr


@pytest.mark.slow
def test_ctrl_c_stops_a_run_cleanly_with_exit_130(write):
    p = write("forever.rcl", "WRITELN('looping')\nWHILE TRUE DO x := 1 END\n")
    env = dict(os.environ, PYTHONFAULTHANDLER="1")  # if it ever hangs, SIGABRT shows where
    # as from a terminal: a job started in the background (CI under nohup ... &) inherits SIGINT
    # ignored, and then Python never turns Ctrl-C into KeyboardInterrupt
    proc = subprocess.Popen([sys.executable, "-m", "rcl", "run", str(p)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, stdin=subprocess.DEVNULL, env=env,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    assert proc.stdout.readline() == "looping\n"
    time.sleep(0.3)
    proc.send_signal(signal.SIGINT)
    try:
        out, err = proc.communicate(timeout=20)
    except subprocess.TimeoutExpired:
        proc.send_signal(signal.SIGABRT)
        out, err = proc.communicate(timeout=20)
        raise AssertionError("rcl run did not stop on Ctrl-C; where it was:\n" + err) from None
    assert proc.returncode == 130
    assert "interrupted" in err and "robot was halted" in err and "Traceback" not in err
    assert f"{p}:2:" in err and "error: stopped: interrupted (Ctrl-C)" in err  # where the program was


@pytest.mark.slow
def test_console_script_and_module_are_the_same_command(write):
    import shutil
    exe = shutil.which("rcl", path=os.path.dirname(sys.executable)) or shutil.which("rcl")
    assert exe, "the rcl console script is not installed"
    p = write("one.rcl", "WRITELN(1)\n")
    r = subprocess.run([exe, "run", str(p)], capture_output=True, text=True, timeout=60)
    assert (r.returncode, r.stdout) == (0, "1\n")
    assert "rcl " in subprocess.run([exe, "--version"], capture_output=True, text=True).stdout


@pytest.mark.slow
def test_the_sample_trays_give_rcl_vision_something_to_find(tmp_path):
    """examples/trays: images to try `rcl vision` on before a camera is connected; each shows
    graspable ends (the overlays are written too)."""
    import json

    images = sorted((ROOT / "examples" / "trays").glob("*.jpg"))
    assert len(images) >= 3
    done = rcl("vision", *map(str, images), "--json", "--overlay", str(tmp_path))
    assert done.returncode == 0, done.stderr
    lines = [json.loads(line) for line in done.stdout.splitlines()]
    assert len(lines) == len(images)
    assert all(line["wires"] for line in lines), lines
    assert len(list(tmp_path.glob("*.png"))) == len(images)
