"""REPL start-up: time from launching `rcl` on a terminal to its first prompt.
Run by hand: python benchmarks/repl.py   (needs pexpect, from the test extra)"""
from __future__ import annotations

import os
import statistics
import sys
import tempfile
import time

import pexpect


def main() -> None:
    # benchmarks/machine.py, imported here as tests load some of these files as modules
    from machine import cached_env, describe

    print(describe())
    with tempfile.TemporaryDirectory() as d:
        env = cached_env(RCL_HISTORY=os.path.join(d, "history"), PROMPT_TOOLKIT_NO_CPR="1")
        times = []
        for _ in range(10):
            t = time.perf_counter()
            child = pexpect.spawn(sys.executable, ["-m", "rcl"], env=env, timeout=20, encoding="utf-8")
            child.expect_exact("rcl>")
            times.append(time.perf_counter() - t)  # the first (writing the caches) is dropped below
            child.sendcontrol("d")
            child.expect(pexpect.EOF)
            child.close()
    times = times[1:]
    print(f"REPL start to first prompt: median {statistics.median(times):.3f} s, "
          f"max {max(times):.3f} s (target < 0.5 s)")


if __name__ == "__main__":
    main()
