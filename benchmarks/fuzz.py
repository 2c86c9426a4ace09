"""The hostile-input property tests with many times the examples CI runs.

    python benchmarks/fuzz.py [TIMES]      (default 50: up to about 47,000 generated programs, 5 min)

Runs tests/test_properties.py (token soups, mutated examples, arbitrary text, nesting up to
and past the limit) with RCL_FUZZ=TIMES and prints pytest's summary; any exception that is not
an RCL error, any traceback from the CLI, fails it.
"""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

if __name__ == "__main__":
    times = sys.argv[1] if len(sys.argv) > 1 else "50"
    env = {**os.environ, "RCL_FUZZ": times}
    sys.exit(subprocess.call([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                              str(ROOT / "tests" / "test_properties.py")], env=env, cwd=ROOT))
