"""Inverse kinematics speed per pose and model. Run by hand: python benchmarks/kinematics.py

Poses are FK of random joint angles within the limits; each IK starts from the
model's home. Reports microseconds per pose for the analytic solver (all
branches, then the nearest within limits) and, for comparison, the numerical
fallback on the same poses, and the worst FK -> IK -> FK error.
"""
from __future__ import annotations

import time

import numpy as np

from rcl.robots.kinematics import fk, load_model, solve

N = 10_000
N_NUMERICAL = 50



def poses(model, n, rng):
    lo = np.array([j.min for j in model.joints])
    hi = np.array([j.max for j in model.joints])
    return [fk(model, q) for q in rng.uniform(lo, hi, size=(n, model.axes))]


def main() -> None:
    # benchmarks/machine.py, imported here as tests load some of these files as modules
    from machine import describe

    print(describe())
    print(f"{'model':<10} {'axes':>4} {'analytic us/pose':>17} {'worst error mm':>15} "
          f"{'numerical us/pose':>18}  target")
    for name in ("smartarms", "al5d", "puma560"):
        model = load_model(name)
        rng = np.random.default_rng(0)
        targets = poses(model, N, rng)
        t0 = time.perf_counter()
        answers = [solve(model, t, model.home) for t in targets]
        analytic = (time.perf_counter() - t0) / N * 1e6
        worst = max(float(np.abs(fk(model, q) - t).max()) for q, t in zip(answers, targets))
        model.solver = "numerical"
        t0 = time.perf_counter()
        for t in targets[:N_NUMERICAL]:
            solve(model, t, model.home)
        numerical = (time.perf_counter() - t0) / N_NUMERICAL * 1e6
        print(f"{name:<10} {model.axes:>4} {analytic:>17.1f} {worst:>15.1e} {numerical:>18.0f}  <= 50 us analytic")


if __name__ == "__main__":
    main()
