"""The machine a benchmark ran on, for the first line of its table: figures reproduce only with it."""
from __future__ import annotations

import os
import platform
import subprocess
from pathlib import Path


def describe() -> str:
    """'machine: x86_64, 2 cores, Linux, Python 3.11.7, numpy 2.4.6; rcl at commit abc1234'."""
    import numpy as np

    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], check=False, capture_output=True, text=True, timeout=10,
                                cwd=Path(__file__).resolve().parent).stdout.strip() or "unknown"
    except (OSError, subprocess.SubprocessError):
        commit = "unknown"
    return (f"machine: {platform.machine()}, {os.cpu_count()} cores, {platform.system()}, Python "
            f"{platform.python_version()}, numpy {np.__version__}; rcl at commit {commit}")


def one_core_pool(workers: int):
    """A process pool whose workers each compute on one core: started afresh (not forked from this
    process, whose BLAS has its threads already) with one BLAS thread each. Two workers on a
    2-core machine, each with a BLAS thread per core, spin against each other: the ridge finder's
    contrast stage took 21 ms a 512 x 512 image so, against 3.8 ms with one thread each."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    one_thread()
    return ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn"))


def one_thread() -> None:
    """One BLAS (and OpenMP) thread for numpy in this process, if it has not been imported yet,
    and in every process started from it."""
    for name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(name, "1")


def cached_env(**extra: str) -> dict:
    """The environment for timing fresh `rcl` processes as an installed rcl starts: with Python's
    compiled-bytecode cache written and used (pip compiles a wheel's modules when it installs
    them; a checkout writes its __pycache__ on the first run), even where the shell sets
    PYTHONDONTWRITEBYTECODE, which would make every start compile rcl's sources anew."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env.update(extra)
    return env


def interval(k: int, n: int) -> tuple[float, float]:
    """The Wilson score interval, 95 %, for a share measured as k of n, as fractions (scipy's):
    the range of true shares the count does not rule out. On 2,000 trays a 93 % share is known to
    about +-1.1 %; on 3 photographs a 33 % share to anywhere between 6 and 79 %."""
    if n <= 0:
        return 0.0, 1.0
    from scipy.stats import binomtest

    ci = binomtest(k, n).proportion_ci(0.95, method="wilson")
    return float(ci.low), float(ci.high)
