"""Runs every tests/programs/*.rcl program and compares with the expectations in its comments.

    // expect: TEXT             one line of standard output, in order (`// expect:` alone: an empty line)
    // expect-exit: N           0 (default), 1 for a runtime error, 2 for static errors
    // expect-error: L TEXT     a diagnostic on line L whose message contains TEXT; L may be
                                `.` (this line) or `^` (the last line above with code);
                                for static errors, exactly the listed ones must be reported
"""
from __future__ import annotations

import io
import re
from pathlib import Path

import pytest

from rcl import RclRuntimeError, RclStaticError, Session
from rcl.robots import RecordingArm

CASES = sorted((Path(__file__).parent / "programs").glob("*.rcl"))
EXPECT = re.compile(r"// expect(?P<kind>-exit|-error)?:(?P<rest>.*)$")


def expectations(path: Path):
    out, exit_code, errors = [], 0, []
    code_line = 0
    for number, line in enumerate(path.read_text().splitlines(), start=1):
        m = EXPECT.search(line)
        if not line.lstrip().startswith("//"):
            here, code_line = number, number
        else:
            here = code_line
        if not m:
            continue
        rest = m["rest"][1:] if m["rest"].startswith(" ") else m["rest"]
        if m["kind"] is None:
            out.append(rest)
        elif m["kind"] == "-exit":
            exit_code = int(rest)
        else:
            where, _, text = rest.partition(" ")
            errors.append((number if where == "." else here if where == "^" else int(where), text))
    return out, exit_code, errors


@pytest.mark.parametrize("path", CASES, ids=lambda p: p.stem)
def test_program(path: Path):
    want_out, want_exit, want_errors = expectations(path)
    buf = io.StringIO()
    session = Session(out=buf, step_budget=1_000_000, robot=RecordingArm())  # the language, not kinematics
    exit_code, found = 0, []
    try:
        session.run_file(path)
    except RclStaticError as e:
        exit_code = 2
        found = [(d.span.line, d.message) for d in e.diagnostics]
        assert buf.getvalue() == "", "a program with static errors must print nothing"
        assert session.robot.log == [], "a program with static errors must move nothing"
    except RclRuntimeError as e:
        exit_code = 1
        found = [(e.span.line, e.message)]
        assert session.robot.halted, "the robot must be halted after a runtime error"
    assert exit_code == want_exit, f"exit {exit_code}, diagnostics: {found}"
    got_out = buf.getvalue().split("\n")
    assert got_out[-1] == "", "output must end with a newline"
    assert got_out[:-1] == want_out
    for line, text in want_errors:
        assert any(fl == line and text in msg for fl, msg in found), (
            f"no error on line {line} containing {text!r}; found {found}")
    if want_exit == 2:
        assert len(found) == len(want_errors), f"unexpected diagnostics: {found}"


def test_every_section_of_the_language_reference_has_cases_here():
    """docs/language.md is the whole language; each of its numbered sections is exercised by
    the project's own cases (tests/programs/*.rcl name theirs on their first line, 'Section N'),
    without ../shared. Section 11, the whole task, is run from the page by test_examples."""
    page = (Path(__file__).parent.parent / "docs" / "language.md").read_text(encoding="utf-8")
    sections = [int(n) for n in re.findall(r"^## (\d+)\. ", page, re.M)]
    assert sections == list(range(1, len(sections) + 1)) and len(sections) >= 11
    named = set()
    for case in CASES:
        first = case.read_text(encoding="utf-8").splitlines()[0]
        named.update(int(n) for n in re.findall(r"Section (\d+)", first))
    named.add(11)  # tests/test_examples.py::test_the_whole_task_in_the_language_reference_runs
    assert set(sections) <= named, f"sections with no case: {sorted(set(sections) - named)}"
