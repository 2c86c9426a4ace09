"""Hostile input: whatever the text, rcl answers with exit 0, 1 or 2 and a diagnostic,
never a Python traceback; a program with a static error prints nothing and moves nothing."""
from __future__ import annotations

import contextlib
import io
import os
import random
import re

import pytest
from conftest import ROOT, rcl
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rcl import RclCancelled, RclRuntimeError, RclStaticError, Session
from rcl.cli import main as cli_main
from rcl.session import RclInternalError

FUZZ = int(os.environ.get("RCL_FUZZ", "1"))  # benchmarks/fuzz.py runs these with many times the examples
DIAGNOSTIC = re.compile(r"^[^:\n]+:\d+:\d+: error: ", re.M)
TOKENS = ["IF", "THEN", "ELSE", "ELSIF", "END", "WHILE", "DO", "REPEAT", "UNTIL", "FOR", "TO", "DOWNTO",
          "BY", "RETURN", "TRY", "EXCEPT", "RAISE", "SOLVE", "IMPORT", "VAR", "CONST", "PROCEDURE",
          "FUNCTION", "ARRAY", "OF", "FRAME", "AND", "OR", "NOT", "DIV", "MOD", "TRUE", "FALSE",
          ":=", "=", "<>", "<", ">", "<=", ">=", "+", "-", "*", "/", "(", ")", "[", "]", ",", ";", ".",
          "..", ":", "^", "->", "x", "y", "W^", "T5^", "INV", "TRANS", "MOVE", "WRITELN", "HOME",
          "1", "0", "2.5", "1e400", "99999999999999999999999", "'s'", "'", "{", "}", "(*", "*)", "//",
          "\n", " ", "world -> base", "INTEGER", "REAL", "VEC", "DIST", "@", "\x00", "é"]
EXAMPLES = [p.read_text() for p in sorted((ROOT / "examples").glob("*.rcl"))] + \
           [p.read_text() for p in sorted((ROOT / "tests" / "programs").glob("*.rcl"))]


def outcome(source: str) -> tuple[int, str, list]:
    """Run source in a session: (exit status as the CLI would give it, output, robot log)."""
    out = io.StringIO()
    s = Session(out=out, step_budget=20_000)
    try:
        s.run(source, "soup.rcl")
    except RclStaticError as e:
        assert e.diagnostics, "a static error carries diagnostics"
        for d in e.diagnostics:
            assert DIAGNOSTIC.match(d.render()), d.render()
        assert out.getvalue() == "", "a program with a static error printed something"
        assert s.robot.log == [], "a program with a static error moved the robot"
        return 2, out.getvalue(), s.robot.log
    except (RclRuntimeError, RclCancelled) as e:
        assert s.robot.halted, "the robot was not halted after a runtime error"
        text = e.render()
        if isinstance(e, RclRuntimeError) and e.span is not None:
            assert DIAGNOSTIC.match(text), text
        return 1, out.getvalue(), s.robot.log
    except RclInternalError as e:  # a fault in RCL itself: never acceptable
        raise AssertionError(f"internal error for {source!r}") from e
    return 0, out.getvalue(), s.robot.log


@pytest.mark.slow
@settings(max_examples=400 * FUZZ, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.sampled_from(TOKENS), max_size=40).map(" ".join))
def test_token_soup(source):
    outcome(source)


@pytest.mark.slow
@settings(max_examples=300 * FUZZ, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(EXAMPLES), st.randoms(use_true_random=False), st.integers(1, 4))
def test_mutated_programs(source, rnd: random.Random, edits):
    words = re.split(r"(\s+)", source)
    for _ in range(edits):
        i = rnd.randrange(len(words))
        action = rnd.randrange(3)
        if action == 0:
            words[i] = ""
        elif action == 1:
            words[i] = rnd.choice(TOKENS)
        else:
            words.insert(i, rnd.choice(TOKENS))
    outcome("".join(words))


@pytest.mark.slow
@settings(max_examples=200 * FUZZ, deadline=None)
@given(st.text(max_size=200))
def test_arbitrary_text(source):
    outcome(source)


OPENERS = [("IF TRUE THEN\n", "END\n"), ("WHILE FALSE DO\n", "END\n"), ("REPEAT\n", "UNTIL TRUE\n"),
           ("FOR i := 1 TO 1 DO\n", "END\n"), ("TRY\n", "EXCEPT\nEND\n"), ("x := -(", ")\n")]


@settings(max_examples=40 * FUZZ, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.sampled_from(range(len(OPENERS) - 1)), min_size=1, max_size=8), st.integers(1, 2_200),
       st.integers(0, 3_000))
@pytest.mark.slow
def test_deep_nesting_up_to_and_past_the_limit(kinds, depth, operators):
    # blocks of mixed kinds nested `depth` deep around an expression of `operators` chained minus
    # signs: it runs, or it is refused as nested too deeply; nothing else
    from rcl.parser import MAX_NESTING

    layers = [OPENERS[kinds[i % len(kinds)]] for i in range(depth)]
    body = "y := " + "-" * operators + "1\n"
    source = "".join(o for o, _ in layers) + body + "".join(c for _, c in reversed(layers))
    code, _out, _log = outcome(source)
    levels = 2 * depth + operators  # a block and its body are two levels; each minus sign one
    if levels < MAX_NESTING - 10:
        assert code == 0, (depth, operators)
    elif levels > MAX_NESTING + 10:
        assert code == 2 and f"more than {MAX_NESTING} levels" in Session().check(source)[0].message


@pytest.mark.slow
def test_deep_nesting_of_parentheses_and_ifs():
    assert outcome("x := " + "(" * 1000 + "1" + ")" * 1000 + "\nWRITELN(x)")[:2] == (0, "1\n")
    nested_if = "x := 0\n" + "IF TRUE THEN\n" * 1000 + "x := 1\n" + "END\n" * 1000 + "WRITELN(x)"
    assert outcome(nested_if)[:2] == (0, "1\n")
    assert outcome("x := " + "-" * 1000 + "1\nWRITELN(x)")[:2] == (0, "1\n")
    assert outcome("x := " + "(" * 1000 + "1")[0] == 2
    loops = "n := 0\n" + "FOR i := 1 TO 1 DO\n" * 500 + "n := n + 1\n" + "END\n" * 500 + "WRITELN(n)"
    assert outcome(loops)[:2] == (0, "1\n")


def test_unterminated_comments_fail_fast_with_a_clear_message():
    for opener in ("(* ", "{ "):
        with pytest.raises(RclStaticError) as e:
            Session().run("x := 1\n" + opener + "text\n" * 20000)
        assert "unterminated comment" in e.value.diagnostics[0].message
        assert e.value.diagnostics[0].span.line == 2


def test_huge_literals_and_values():
    assert outcome("x := " + "9" * 5000)[0] == 2
    assert outcome("x := 1" + "0" * 400 + ".0")[0] == 2
    assert outcome("x := 1e308 * 10\nWRITELN(x, ' ', -x, ' ', x - x)")[:2] == (0, "inf -inf nan\n")
    assert outcome("WRITELN(LOW(0))")[0] == 2
    assert outcome("VAR a : ARRAY [1..9223372036854775807] OF REAL")[0] == 2
    assert outcome("x := 9223372036854775807\nx := x + 1")[0] == 1
    assert outcome("WRITELN(ROUND(1e300))")[0] == 1
    assert outcome("F^ := TRANS(1e308 * 10, 0, 0)")[0] == 1
    assert outcome("F^ := ROTZ(1e308 * 10)")[0] == 1


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                               HealthCheck.function_scoped_fixture])
@pytest.mark.slow
@given(st.lists(st.sampled_from(TOKENS), max_size=30).map(" ".join))
def test_cli_exit_codes_for_token_soup(tmp_path, source):
    path = tmp_path / "soup.rcl"
    path.write_text(source, encoding="utf-8")
    err, out = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
        code = cli_main(["run", str(path), "--step-budget", "5000"])
    assert code in (0, 1, 2)
    assert "Traceback" not in err.getvalue()
    if code == 2:
        assert out.getvalue() == "" and DIAGNOSTIC.search(err.getvalue())
    elif code == 1:
        assert DIAGNOSTIC.search(err.getvalue()), err.getvalue()


def test_cli_in_process_never_shows_a_traceback(tmp_path):
    soups = ["IF", "x := ", "END END", "(* open", "'open", "x := 1 DIV 0", "MOVE(5)", "\x00", "W ^ := 1",
             "FUNCTION F^ : INTEGER\nEND", "SOLVE A^ = B^ FOR C^", "IMPORT 'nothing'", "RETURN RETURN"]
    for i, text in enumerate(soups):
        path = tmp_path / f"case{i}.rcl"
        path.write_text(text)
        err = io.StringIO()
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            code = cli_main(["run", str(path)])
        assert code in (0, 1, 2), (text, code)
        assert "Traceback" not in err.getvalue()
        if code:
            assert DIAGNOSTIC.search(err.getvalue()), (text, err.getvalue())


@pytest.mark.slow
@pytest.mark.parametrize("text", ["x := (((", "WHILE TRUE DO x := 1 END", "IF 1 THEN END", "\xff"])
def test_cli_subprocess_exits_cleanly(tmp_path, text):
    path = tmp_path / "p.rcl"
    path.write_text(text, encoding="latin-1")
    r = rcl("run", str(path), "--step-budget", "1000")
    assert r.returncode in (1, 2) and "Traceback" not in r.stderr and r.stderr.strip()
