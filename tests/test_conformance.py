"""The public conformance cases of ../shared/conformance, when that folder exists."""
from __future__ import annotations

import subprocess
import sys

import pytest
from conftest import ROOT

RUNNER = ROOT.parent / "shared" / "conformance" / "run.py"


@pytest.mark.slow
@pytest.mark.skipif(not RUNNER.exists(), reason="../shared/conformance is not beside this checkout")
def test_public_conformance_cases():
    r = subprocess.run([sys.executable, str(RUNNER), "--rcl", f"{sys.executable} -m rcl"],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stdout.strip().endswith("0 failed")
