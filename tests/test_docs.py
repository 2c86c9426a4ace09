"""The README and the tutorial, walked top to bottom: every REPL transcript replays with the
output it shows, every program fragment runs (or fails as the text says), every `rcl` command
runs with the output quoted after it, and the README's Python example works. Docs that drift
from the code fail here."""
from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys

import pytest
from conftest import ROOT, benchmark, rcl

TUTORIAL = ROOT / "docs" / "tutorial.md"
README = ROOT / "README.md"


def code_blocks(path) -> list[tuple[str, list[str]]]:
    """(the heading it lies under, its lines) for each code block of a Markdown file: fenced
    (```) or indented by four spaces after a blank line."""
    blocks, heading, fence, current = [], "", None, None
    lines = path.read_text(encoding="utf-8").splitlines()
    for i, line in enumerate(lines):
        if fence is not None:
            if line.startswith("```"):
                blocks.append((heading, fence))
                fence = None
            else:
                fence.append(line)
            continue
        if line.startswith("```"):
            fence = []
            continue
        if line.startswith("#"):
            heading = line.lstrip("#").strip()
        indented = line.startswith("    ") or (current is not None and not line.strip())
        if current is not None and indented:
            current.append(line[4:])
        elif current is not None:
            while current and not current[-1].strip():
                current.pop()
            blocks.append((heading, current))
            current = None
        if current is None and line.startswith("    ") and (i == 0 or not lines[i - 1].strip()):
            current = [line[4:]]
    if current:
        blocks.append((heading, current))
    return blocks


def section(heading_start: str) -> list[list[str]]:
    return [b for h, b in code_blocks(TUTORIAL) if h.startswith(heading_start)]


def expect_in_order(output: str, expected: list[str]) -> None:
    """Each expected line appears in output, in order; a line ending in '...' is a prefix."""
    got = [line.rstrip() for line in output.splitlines()]
    at = 0
    for want in expected:
        want = want.rstrip()
        prefix = want.endswith("...")
        stem = want[:-3].rstrip() if prefix else want
        for j in range(at, len(got)):
            if (got[j].startswith(stem) if prefix else got[j] == stem):
                at = j + 1
                break
        else:
            pytest.fail(f"{want!r} is not in the output (after line {at}):\n{output}")


@pytest.mark.slow
def test_the_tutorials_repl_transcripts_replay_as_shown():
    inputs, expected = [], []
    for _, block in code_blocks(TUTORIAL):
        if not block or not block[0].startswith("rcl> "):
            continue
        for line in block:
            if line.startswith("rcl> "):
                inputs.append(line[5:])
            elif line.strip():
                expected.append(line)
    assert len(inputs) >= 8, "the tutorial's transcripts were not found"
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    out = subprocess.run([sys.executable, "-m", "rcl"], input="\n".join(inputs) + "\n", capture_output=False,
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60, env=env)
    expect_in_order(out.stdout, expected)
    assert out.returncode == 2  # the transcripts show static errors: the worst exit status


def run_program(tmp_path, text: str, *args: str) -> subprocess.CompletedProcess:
    path = tmp_path / "walk.rcl"
    path.write_text(text + "\n", encoding="utf-8")
    return rcl(*args, str(path)) if args and args[0] == "check" else rcl("run", str(path))


@pytest.mark.slow
def test_the_tutorials_cell_equation_and_pick_run_as_written(tmp_path):
    (declare_and_solve,) = [b for b in section("2.") if b[0].startswith("VAR")]
    solve = [b for b in section("2.") if b[0].startswith("SOLVE")][0]
    program = "\n".join(declare_and_solve + solve)
    done = run_program(tmp_path, program)
    assert done.returncode == 0, done.stderr
    # the mistake the text describes, and the checker's answer it quotes
    forgot = program.replace("SOLVE Z^ * T5^ * E^ = W^ * WG^ FOR T5^", "SOLVE Z^ * T5^ = W^ * WG^ FOR T5^")
    text = TUTORIAL.read_text(encoding="utf-8")
    quoted = " ".join(re.search(r"the checker answers \"([^\"]+)\"", text).group(1).split())
    wrong = run_program(tmp_path, forgot, "check")
    assert wrong.returncode == 2 and quoted in wrong.stderr, wrong.stderr
    # section 3: approach, grasp and retreat after the same declarations
    (pick,) = section("3.")[:1]
    done = run_program(tmp_path, "\n".join(declare_and_solve + pick))
    assert done.returncode == 0, done.stderr
    # section 4: the library's PICKUP on the same frames
    (library,) = section("4.")
    assert library[0].startswith("IMPORT") and any(line.startswith("PICKUP") for line in library)
    done = run_program(tmp_path, "\n".join(library[:1] + declare_and_solve + library[1:]))
    assert done.returncode == 0, done.stderr


@pytest.mark.slow
def test_the_tutorials_commands_print_what_it_quotes(tmp_path):
    """`rcl run examples/...` as the tutorial says, in a folder of one's own, with the output it
    quotes in the block after the command."""
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    blocks = [b for _, b in code_blocks(TUTORIAL)]
    commands = [(i, b[0]) for i, b in enumerate(blocks) if b and b[0].startswith("rcl run ")]
    assert len(commands) >= 2
    for i, command in commands:
        args = command.split()[1:]
        done = rcl(*args, cwd=tmp_path, timeout=300)
        assert done.returncode == 0, f"{command}: {done.stderr}"
        after = blocks[i + 1] if i + 1 < len(blocks) else []
        if after and not after[0].startswith(("rcl", "WHILE", "SOLVE", "IMPORT", "VAR")):
            expect_in_order(done.stdout, after)
        for arg, value in zip(args, args[1:]):
            if arg == "--plot":
                assert (tmp_path / value).stat().st_size > 1000
            if arg == "--pictures":
                assert any((tmp_path / value).glob("*.png"))


def test_the_readmes_python_example_runs():
    (example,) = [b for _, b in code_blocks(README) if any("from rcl import Session" in line for line in b)]
    code = "\n".join(example) + "\nprint(s['W^'].matrix[0, 3])\n"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["3", "300.0"]


def test_the_readmes_quick_start_is_two_commands_that_install_and_run():
    blocks = [b for h, b in code_blocks(README) if h == "Quick start"]
    assert [len(b) for b in blocks] == [1, 1]
    (main_job,), (tests,) = blocks
    assert "pip install ." in main_job and main_job.endswith("rcl run examples/crimp.rcl")
    assert "pip install '.[test]'" in tests and tests.endswith("pytest")
    # the command the CI runs is the README's
    assert "pytest" in (ROOT / ".ci" / "run").read_text(encoding="utf-8")


def test_every_benchmark_that_prints_figures_says_which_machine_it_ran_on():
    # README figures come from benchmarks/*.py; each table starts with the machine and commit
    line = benchmark("machine").describe()
    assert re.match(r"machine: \S+, \d+ cores, \S+, Python [\d.]+, numpy [\d.]+; rcl at commit \S+$", line), line
    for script in sorted((ROOT / "benchmarks").glob("*.py")):
        if script.name in ("machine.py", "fuzz.py"):  # fuzz.py prints pytest's verdict, no figures
            continue
        assert "print(describe())" in script.read_text(), f"{script.name} does not print the machine it ran on"


def test_the_benchmarks_intervals_are_wilsons():
    # the share's 95 % interval printed beside the tables' figures: the textbook Wilson interval
    # for 1 of 3 (0.0615-0.7923), and the closed forms n / (n + z^2) at none and all of n
    interval = benchmark("machine").interval
    lo, hi = interval(1, 3)
    assert abs(lo - 0.0615) < 5e-4 and abs(hi - 0.7923) < 5e-4
    for n in (7, 60, 2000):
        edge = n / (n + 1.959963984540054 ** 2)
        assert interval(0, n)[0] == 0.0 and abs(interval(0, n)[1] - (1 - edge)) < 1e-9
        assert abs(interval(n, n)[0] - edge) < 1e-9 and interval(n, n)[1] == 1.0
    lo, hi = interval(1866, 2000)
    assert lo < 0.933 < hi and 0.02 < hi - lo < 0.023  # about +-1.1 points on 2,000 trays
    assert interval(0, 0) == (0.0, 1.0)


def test_the_vision_benchmark_lists_the_trays_whose_verdict_changed():
    vision = benchmark("vision")
    before = {"ridge": {"7": ["correct", ""], "12": ["foul", "past the end, on from its wire"], "30": ["miss", ""]},
              "grey": {"7": ["miss", ""]}}
    after = {"ridge": {"7": ["correct", "", 2.0], "12": ["correct", "", 0.3], "30": ["foul", "at no wire end", None],
                       "31": ["foul", "at no wire end", None]},  # (now with each verdict's nearness)
             "binary": {"7": ["foul", "at no wire end"]}}
    # only what both runs hold, in seed order (as numbers: "12" before "30"), a foul with its cause
    assert vision.changed(before, after) == [("ridge", 12, "foul past the end, on from its wire", "correct"),
                                             ("ridge", 30, "miss", "foul at no wire end")]
    assert vision.changed(after, after) == []


def test_the_vision_benchmark_counts_each_verdict_by_how_near_the_rule_it_lies(capsys):
    vision = benchmark("vision")
    results = [{"ridge": (v, 0, 0, 0, {}, "", near)} for v, near in
               [("correct", 2.0), ("correct", 0.1), ("foul", 0.3), ("foul", 0.25), ("foul", None), ("miss", 1.5),
                ("miss", 0.6)]]
    vision.near_table(results, "ridge")
    rows = {line.split()[0]: [int(x) for x in line.split()[1:]] for line in capsys.readouterr().out.splitlines()[2:]}
    # bins: <= 0.25, 0.25-0.5, 0.5-1, > 1 mm, not in mm
    assert rows == {"correct": [1, 0, 0, 1, 0], "foul": [1, 1, 0, 0, 1], "miss": [0, 0, 1, 1, 0]}


def test_the_vision_benchmark_counts_the_fouls_no_camera_could_see_by_cause(capsys):
    vision = benchmark("vision")
    room, top = "an end not graspable: no room for the fingers at the grasp point", "at no wire end"
    results = [{"ridge": (v, 0, 0, 0, {}, why, near, unseen)} for v, why, near, unseen in
               [("foul", room, 0.3, 1.0), ("foul", room, 2.0, 0.95), ("foul", room, 2.0, 0.5), ("foul", top, None, None),
                ("correct", "", 2.0, None), ("miss", "", 0.6, None)]]
    vision.cause_table(results, "ridge")
    rows = capsys.readouterr().out.splitlines()[1:]
    # room: 3 fouls, 1 near, 2 gross, 2 hidden 90 % or more; the other: 1, gross (in degrees), none hidden
    assert [r.split()[:9] for r in rows] == [["50.00%", "3", "(", "1", "near,", "2", "gross,", "2", "unseen)"],
                                             ["16.67%", "1", "(", "0", "near,", "1", "gross,", "0", "unseen)"]]
    vision.cause_table([{"ridge": ("correct", 0, 0, 0, {}, "", 2.0, None)}], "ridge")
    assert capsys.readouterr().out == ""


def test_the_vision_benchmark_groups_trays_by_what_they_are_drawn_with():
    import numpy as np

    from rcl.vision.scenes import draw_scene

    vision = benchmark("vision")
    scene = draw_scene(np.random.default_rng(5))
    groups = vision.drawn_with(scene)
    assert groups[0] == f"board {scene.board}" and groups[3] == ("colour" if scene.colour else "grey")
    scene.width, scene.height, scene.count = 320, 240, 20
    assert vision.drawn_with(scene)[1:3] == ["small image", "20+ wires"]
    scene.width, scene.height, scene.count = 1024, 768, 4
    assert vision.drawn_with(scene)[1:3] == ["large image", "1-4 wires"]
    scene.width, scene.height, scene.count = 640, 480, 10
    assert vision.drawn_with(scene)[1:3] == ["medium image", "10-19 wires"]
