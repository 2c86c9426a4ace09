"""Interpreter speed against plain Python + numpy. Run by hand: python benchmarks/interp.py

Prints one table:
  - 100,000 evaluations of the paper's equation T5^ := INV(Z^)*W^*WG^*INV(E^) in RCL, against the
    same loop in Python with numpy.linalg.inv (the obvious way), with a closed-form rigid inverse,
    and with the two inverses computed once before the loop (as RCL does: a Frame keeps its inverse
    once asked for, and Z^ and E^ are the same frames in every turn);
  - a 1,000,000-step scalar loop in RCL and in Python;
  - parse + check of a generated 2,000-line program;
  - with --large: parse and check apart for 100,000-line programs of four shapes (issue 13, point 8),
    per line and per token, to state the bound docs/language.md gives;
  - `rcl run` start-up for a one-line script (a fresh process, median of several).
The loops' times are medians of runs interleaved with their references, and each ratio the median
of the ratios within a round (see `paired`).
"""
from __future__ import annotations

import io
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from rcl import Session
from rcl.checker import Checker
from rcl.parser import parse

N_FRAMES = 100_000
N_SCALAR = 1_000_000

SETUP = """Z^ := TRANS(0, 0, 100) * ROTZ(30)
E^ := TRANS(0, 0, 50) * ROTX(10)
W^ := TRANS(300, 20, 0) * ROTY(180) * ROTZ(20)
WG^ := TRANS(0, 0, -15) * ROTZ(90)
"""



def best(f, repeat=3) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return min(times)


def timed(f) -> float:
    t = time.perf_counter()
    f()
    return time.perf_counter() - t


def paired(subject, references: dict, pairs: int = 7) -> tuple[float, dict]:
    """(median seconds of subject(), {name: (median seconds, median ratio subject / reference)}).

    The runs are interleaved, subject then each reference, and each ratio is taken within one
    round: a shared machine's speed drifts by half from one second to the next, which the best of
    separate runs would put into the ratio."""
    ts: list[float] = []
    rs: dict = {k: ([], []) for k in references}
    for _ in range(pairs):
        t = timed(subject)
        ts.append(t)
        for k, f in references.items():
            r = timed(f)
            rs[k][0].append(r)
            rs[k][1].append(t / r)
    return statistics.median(ts), {k: (statistics.median(a), statistics.median(b)) for k, (a, b) in rs.items()}


def rcl_loop(setup: str, loop: str):
    s = Session(out=io.StringIO())
    s.run(setup)
    return lambda: s.run(loop)


def frames_numpy(closed_form: bool, hoisted: bool = False):
    def rz(d):
        t = np.radians(d)
        m = np.eye(4)
        m[:2, :2] = [[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]]
        return m
    Z = rz(30)
    Z[2, 3] = 100
    E = np.eye(4)
    E[2, 3] = 50
    W = rz(20)
    W[:3, 3] = (300, 20, 0)
    WG = rz(90)
    WG[2, 3] = -15

    def rigid_inv(m):
        out = m.T.copy()
        out[:3, 3] = -(out[:3, :3] @ m[:3, 3])
        out[3, :3] = 0.0
        return out
    inv = rigid_inv if closed_form else np.linalg.inv

    def loop():
        for _ in range(N_FRAMES):
            inv(Z) @ W @ WG @ inv(E)

    def loop_hoisted():
        iz, ie = rigid_inv(Z), rigid_inv(E)
        for _ in range(N_FRAMES):
            iz @ W @ WG @ ie
    return loop_hoisted if hoisted else loop


def scalar_python() -> None:
    s = 0
    for i in range(1, N_SCALAR + 1):
        s = s + i


def program(lines: int) -> str:
    """A realistic program: routines, loops, frames, arrays, SOLVE; about `lines` lines."""
    chunk = """PROCEDURE PICK{k}(W^, WG^; depth : REAL)
  VAR T5^ : FRAME
  SOLVE Z^ * T5^ * E^ = W^ * WG^ * TRANS(0, 0, -depth) FOR T5^
  MOVE(T5^)
END
FUNCTION AREA{k}(a, b : REAL) : REAL
  RETURN a * b
END
total{k} := 0
FOR i := 1 TO 3 DO
  IF i MOD 2 = 0 THEN total{k} := total{k} + i ELSE total{k} := total{k} - 1 END
END
F{k}^ := TRANS(total{k}, AREA{k}(2, 3), 0) * ROTZ(45)
PICK{k}(F{k}^, IDENT(), 10)
VAR arr{k} : ARRAY [1..4] OF REAL
arr{k}[2] := DIST(F{k}^, IDENT())
WHILE total{k} < 10 DO total{k} := total{k} + 3 END
WRITELN('chunk {k}: ', total{k}, ' ', arr{k}[2])
"""
    head = "Z^ := TRANS(0, 0, 100)\nE^ := TRANS(0, 0, 50)\n"
    per = chunk.count("\n")
    return head + "".join(chunk.format(k=k) for k in range(lines // per + 1))


def parse_check(source: str) -> float:
    def once():
        modules = [parse(source, "big.rcl")]
        s = Session()
        diagnostics = Checker(s._scope.fork()).check(modules)
        assert not diagnostics, diagnostics[:3]
    return best(once)


def large_programs() -> None:
    """Parse and check time of big programs, once each (they take seconds)."""
    import gc

    from rcl.parser import _parser

    shapes = [
        ("realistic (routines, loops, SOLVE)", program(100_000), False),
        ("x := x + 1", "x := 0\n" + "x := x + 1\n" * 100_000, False),
        ("ELSIF arms", "x := 0\nIF x = 0 THEN x := 1\n"
         + "".join(f"ELSIF x = {i} THEN x := {i + 1}\n" for i in range(1, 100_000)) + "END\n", False),
        ("CONSTs each naming the next (10,000)",  # every one an error: a CONST is used before it is made
         "".join(f"CONST C{i} = C{i + 1} + 1\n" for i in range(10_000)) + "CONST C10000 = 1\n", True),
    ]
    print(f"\n{'program':<38} {'lines':>8} {'tokens':>9} {'parse':>8} {'check':>8} {'us/line':>8} {'us/token':>9}")
    for name, source, errors_expected in shapes:
        lines = source.count("\n")
        tokens = sum(1 for _ in _parser().lex(source))
        gc.disable()  # as Session does while parsing and checking
        try:
            t0 = time.perf_counter()
            modules = [parse(source, "big.rcl")]
            t1 = time.perf_counter()
            diagnostics = Checker(Session()._scope.fork()).check(modules)
            t2 = time.perf_counter()
        finally:
            gc.enable()
        assert bool(diagnostics) == errors_expected, diagnostics[:3]
        total = t2 - t0
        print(f"{name:<38} {lines:>8,} {tokens:>9,} {t1 - t0:>7.2f}s {t2 - t1:>7.2f}s {1e6 * total / lines:>8.0f} "
              f"{1e6 * total / tokens:>9.1f}")


def startup() -> tuple[float, float]:
    """(median seconds of `rcl run` on a one-line script, of `python -c "import numpy"`: the floor
    of any start that does arithmetic on frames), each over 7 fresh processes."""
    from machine import cached_env

    env = cached_env()
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / "one.rcl"
        p.write_text("WRITELN('ok')\n")
        subprocess.run([sys.executable, "-m", "rcl", "run", str(p)], capture_output=True, env=env)  # warm caches
        times, floor = [], []
        for _ in range(7):
            t = time.perf_counter()
            r = subprocess.run([sys.executable, "-m", "rcl", "run", str(p)], capture_output=True, text=True, env=env)
            times.append(time.perf_counter() - t)
            assert r.stdout == "ok\n", r.stderr
            t = time.perf_counter()
            subprocess.run([sys.executable, "-c", "import numpy"], check=True, env=env)
            floor.append(time.perf_counter() - t)
        return statistics.median(times), statistics.median(floor)


def main() -> None:
    # benchmarks/machine.py, imported here as tests load some of these files as modules
    from machine import describe

    print(describe())
    rows = []
    loop = f"FOR i := 1 TO {N_FRAMES} DO\n  T5^ := INV(Z^)*W^*WG^*INV(E^)\nEND\n"
    t_rcl, ref = paired(rcl_loop(SETUP, loop), {
        "numpy.linalg.inv": frames_numpy(closed_form=False), "closed-form numpy": frames_numpy(closed_form=True),
        "inverses hoisted": frames_numpy(closed_form=True, hoisted=True)}, pairs=5)
    rows.append((f"{N_FRAMES:,} x T5^ := INV(Z^)*W^*WG^*INV(E^)", t_rcl,
                 "; ".join(f"{k} {t:.3f} s ({r:.2f}x)" for k, (t, r) in ref.items()), "<= 0.8x linalg.inv"))
    t_rcl, ref = paired(rcl_loop("s := 0\n", f"s := 0\nFOR i := 1 TO {N_SCALAR} DO s := s + i END\n"),
                        {"Python": scalar_python}, pairs=9)
    t_py, ratio = ref["Python"]
    rows.append((f"{N_SCALAR:,}-step scalar loop s := s + i", t_rcl, f"Python {t_py:.3f} s ({ratio:.1f}x)",
                 "<= 5x Python"))
    source = program(2000)
    n_lines = source.count("\n")
    rows.append((f"parse + check, {n_lines:,}-line program", parse_check(source), "", "< 0.5 s"))
    t_run, t_numpy = startup()
    rows.append(("`rcl run` start-up, one-line script", t_run,
                 f"median of 7 fresh processes; python -c 'import numpy' {t_numpy:.3f} s", "< 0.3 s"))
    width = max(len(r[0]) for r in rows)
    print(f"{'benchmark':<{width}}  {'RCL':>8}  {'target':>8}  reference")
    print("-" * (width + 70))
    for name, t, ref, target in rows:
        print(f"{name:<{width}}  {t:>7.3f}s  {target:>8}  {ref}")
    if "--large" in sys.argv[1:]:
        large_programs()


if __name__ == "__main__":
    main()
