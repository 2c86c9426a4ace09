"""The interactive prompt, driven through prompt_toolkit's pipe input and one real terminal (pexpect)."""
from __future__ import annotations

import io
import os
import signal
import sys
import threading

import pytest
from conftest import ROOT
from prompt_toolkit.input import create_pipe_input
from prompt_toolkit.output import DummyOutput

from rcl import Session
from rcl.repl import Repl, banner
from rcl.robots import RecordingArm


@pytest.fixture(autouse=True)
def private_history(tmp_path, monkeypatch):
    monkeypatch.setenv("RCL_HISTORY", str(tmp_path / "history"))


def drive(text: str, during=None) -> str:
    """Type text into a REPL (\\r is Enter), then Ctrl-D; what the REPL printed."""
    out = io.StringIO()
    repl = Repl(lambda: Session(out=out, robot=RecordingArm()), out=out)
    with create_pipe_input() as pipe:
        pipe.send_text(text + "\x04")
        if during:
            during()
        assert repl.loop(input=pipe, output=DummyOutput()) == 0
    first, _, rest = out.getvalue().partition("\n")
    assert first == banner()  # every session starts by saying how to get help and how to leave
    return rest


def test_statements_and_bare_expressions():
    out = drive("x := 41\rx + 1\rW^ := TRANS(10, 20, 30) * ROTZ(90)\rW^\rWRITELN('hi')\r'a' + 'b'\r")
    lines = out.splitlines()
    assert lines[0] == "42"
    assert lines[1].startswith("  [    0.0000     -1.0000      0.0000     10.0000 ]")
    assert "position (10, 20, 30) mm, RPY (0, 0, 90) degrees" in out
    assert "hi" in lines and "ab" in lines


def test_multi_line_blocks_continue_until_closed():
    out = drive("IF TRUE THEN\r  WRITELN('yes')\rEND\rPROCEDURE P(n : INTEGER)\rWRITELN(n * 2)\rEND\rP(21)\r"
                "x := (1 +\r 2)\rx\r")
    assert out.splitlines() == ["yes", "42", "3"]


def test_diagnostics_do_not_end_the_session():
    out = drive("y := nosuch + 1\rz := 1 DIV 0\rq := (\r)\rWRITELN('still here')\r")
    assert "<stdin>:1:6: error: unknown name nosuch" in out
    assert "error: division by zero" in out
    assert out.strip().endswith("still here")


def test_commands(tmp_path):
    lib = tmp_path / "lib.rcl"
    lib.write_text("FUNCTION TWICE(n : INTEGER) : INTEGER\n  RETURN 2 * n\nEND\nloaded := TRUE\n")
    out = drive(f":help WRITELN\r:help\r:type TRANS(1, 2, 3) * VEC(1, 0, 0)\r:type HOME\r:load {lib}\r"
                f"TWICE(21)\r:help TWICE\r:vars\r:reset\r:vars\r:bogus\r:help IF\r")
    assert "WRITELN(...: any value)\nWRITELN(args...): write the arguments, then a newline." in out
    assert ":type EXPR     the static type of an expression" in out
    assert "VECTOR\n" in out and "no value: a procedure call" in out
    assert "\n42\n" in out
    assert "FUNCTION TWICE(n : INTEGER) : INTEGER" in out
    assert "loaded : BOOLEAN = TRUE" in out
    assert "a new session" in out and "no variables yet" in out
    assert "unknown command :bogus" in out and "docs/language.md, 5. Statements:\n    IF c THEN ... ELSIF" in out


def test_completion_of_keywords_builtins_and_variables():
    out = io.StringIO()
    repl = Repl(lambda: Session(out=out, robot=RecordingArm()), out=out)
    repl.handle("Counter := 1\rGrasp^ := IDENT()")
    repl.handle("Counter := 1")
    repl.handle("Grasp^ := IDENT()")
    assert repl.completions("wri") == ["WRITE", "WRITELN"]
    assert "Counter" in repl.completions("co") and "COS" in repl.completions("co")
    assert repl.completions("gras") == ["Grasp^"]
    assert "WHILE" in repl.completions("wh")


@pytest.mark.slow
def test_ctrl_c_stops_a_running_loop_and_returns_to_the_prompt():
    def interrupt_soon():
        threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
    out = drive("WHILE TRUE DO x := 1 END\rWRITELN('after')\r", during=interrupt_soon)
    assert "stopped: interrupted (Ctrl-C)" in out and "the robot was halted" in out
    assert out.strip().endswith("after")


@pytest.mark.slow
def test_a_real_terminal_session_with_pexpect(tmp_path):
    pexpect = pytest.importorskip("pexpect")
    # pexpect's pty answers no cursor-position requests; without this prompt_toolkit waits for them
    env = dict(os.environ, RCL_HISTORY=str(tmp_path / "history"), TERM="xterm", PROMPT_TOOLKIT_NO_CPR="1")
    child = pexpect.spawn(sys.executable, ["-m", "rcl"], env=env, cwd=str(ROOT), timeout=20, encoding="utf-8")
    try:
        child.expect_exact("rcl>")
        child.sendline("x := 41")
        child.expect_exact("rcl>")
        child.sendline("x + 1")
        child.expect_exact("42")
        child.expect_exact("rcl>")
        child.sendline("WRITELN('run', 'ning') WHILE TRUE DO x := 1 END")
        child.expect_exact("running")  # output, not the echo: the statement runs, the prompt let go
        child.sendintr()
        child.expect_exact("stopped: interrupted (Ctrl-C)")
        child.expect_exact("rcl>")
        child.sendline("WRITELN('alive ', x)")
        child.expect_exact("alive 1")
        child.expect_exact("rcl>")
        child.sendcontrol("d")
        child.expect(pexpect.EOF)
    finally:
        child.close()
    assert child.exitstatus == 0
    assert "x + 1" in (tmp_path / "history").read_text()


@pytest.mark.slow
def test_piped_input_is_taken_as_typed_at_the_prompt():
    from conftest import rcl
    r = rcl(input="x := 20\nWRITELN(x * 2 + 2)\n")
    assert (r.returncode, r.stdout) == (0, "42\n")
    r = rcl(input="x := 20\nx * 2 + 2\n:vars\nIF x > 1 THEN\n  WRITELN('big')\nEND\nz := 1 DIV 0\n:vars\nquit\nx\n")
    assert r.stdout == "42\nx : INTEGER = 20\nbig\nx : INTEGER = 20\n"  # a transcript replays
    assert r.returncode == 1 and "division by zero" in r.stderr
    r = rcl(input="x := \n")
    assert r.returncode == 2 and "unexpected end of file" in r.stderr
    r = rcl("repl", input="WRITELN(1 DIV 0)\n")
    assert r.returncode == 1 and "<stdin>:1:" in r.stderr


def test_help_exit_and_quit_do_what_a_newcomer_expects():
    out = drive("help\rx := 1\rquit\rWRITELN('not reached')\r")
    assert out.startswith("Type RCL statements or an expression") and "not reached" not in out
    for word in ("exit", "quit()", "EXIT()"):
        assert drive(f"{word}\rWRITELN('not reached')\r") == ""
    # a name of the user's own spelt so is theirs
    assert drive("quit := 7\rquit\rhelp\r").splitlines()[0] == "7"


def test_help_on_a_keyword_quotes_the_reference_and_on_a_routine_its_doc_comment():
    out = drive(":help SOLVE\rIMPORT 'frames'\r:help approach^\r")
    assert "docs/language.md, 7. Transform equations:" in out and "The unknown must\noccur exactly once" in out
    assert "FUNCTION APPROACH^(F^ : FRAME; d : REAL) : FRAME  (defined in " in out  # the installed file's path
    assert ("frames.rcl)\nF^ moved d mm back along its own approach (Z) axis: where the tool waits before "
            "going in.") in out


def test_a_failed_input_declares_nothing():
    out = drive("x := 1\ry := 10 / 0\r:vars\ry := 'text'\ry\rx := 5; z := 1 DIV 0\rx\r")
    lines = out.splitlines()
    assert "error: division by zero" in lines[0]
    assert lines[3] == "x : INTEGER = 1"  # y, whose assignment failed, is not there
    assert lines[4] == "text"  # so y may be a STRING now
    assert lines[-1] == "5"  # what a failed input did to a variable it did not declare stays


def test_every_built_in_is_highlighted_as_one():
    """The lexer takes its built-ins from the table the checker uses: the cell's (CRIMP,
    GRIPPED, WIRENO) were missing when it kept a list of its own."""
    from pygments.token import Name

    from rcl.builtins import default_builtins
    from rcl.highlight import RclLexer
    from rcl.keywords import keywords
    from rcl.types import NAMED

    lexer = RclLexer()
    reserved = {k.upper() for k in keywords()} | {n.upper() for n in NAMED}  # FRAME(...) shows as the type
    for b in default_builtins().values():
        if b.name.upper() in reserved:
            continue
        for spelling in (b.name, b.name.lower()):
            tokens = [(t, v) for t, v in lexer.get_tokens(f"x := {spelling}") if v.strip()]
            assert tokens[-1] == (Name.Builtin, spelling), (spelling, tokens)
    assert [t for t, v in lexer.get_tokens("W^ := x") if v.strip()][0] == Name.Variable.Instance
