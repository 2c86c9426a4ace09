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
