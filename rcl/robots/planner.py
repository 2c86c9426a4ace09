"""Planning a motion whole before it starts: the joint path, checked, and its duration.

Every backend plans with this, so a move that the simulator refuses is refused
on real hardware too: IK at every point, joint limits, the table plane for
every link frame along the path, and (for straight lines) no configuration
flip on the way.
"""
from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from .base import RobotError
from .kinematics import ArmModel, fk, frames, solve

JOINT_STEP_DEG = 2.0  # path sampling for the checks
LINE_STEP_MM = 2.0
LINE_STEP_DEG = 2.0
MAX_JUMP_DEG = 15.0  # a bigger joint change between neighbouring samples of a straight line is a flip


class Planner:
    def __init__(self, model: ArmModel) -> None:
        self.model = model

    def joint_path(self, start: Sequence[float], target: Sequence[float]) -> list[list[float]]:
        """Joint interpolation from start to target, checked against the table plane."""
        self.model.check_limits(target)
        span = max(abs(a - b) for a, b in zip(start, target))
        n = max(1, math.ceil(span / JOINT_STEP_DEG))
        path = [[a + (b - a) * k / n for a, b in zip(start, target)] for k in range(n + 1)]
        self.check_table(path)
        return path

    def line_path(self, start: Sequence[float], t5: np.ndarray) -> list[list[float]]:
        """A straight line of T5 (position linear, orientation by slerp) from the pose at start to t5."""
        from scipy.spatial.transform import Rotation, Slerp

        here = fk(self.model, start)
        p0, p1 = here[:3, 3], t5[:3, 3]
        rots = Rotation.from_matrix(np.stack([here[:3, :3], t5[:3, :3]]))
        turn = math.degrees(float((rots[0].inv() * rots[1]).magnitude()))
        n = max(1, math.ceil(max(float(np.linalg.norm(p1 - p0)) / LINE_STEP_MM, turn / LINE_STEP_DEG)))
        slerp = Slerp([0.0, 1.0], rots)
        path = [list(start)]
        for k in range(1, n + 1):
            s = k / n
            t = np.eye(4)
            t[:3, :3] = slerp([s]).as_matrix()[0] if k < n else t5[:3, :3]
            t[:3, 3] = p0 + (p1 - p0) * s
            try:
                q = solve(self.model, t, path[-1])
            except RobotError as e:
                raise RobotError(f"the straight line leaves the arm's reach {100 * s:.0f}% of the way "
                                 f"(at {_point(t)}): {e}") from None
            jump = max(abs(a - b) for a, b in zip(q, path[-1]))
            if jump > MAX_JUMP_DEG:
                raise RobotError(f"the straight line passes a singularity or a change of arm configuration "
                                 f"{100 * s:.0f}% of the way (at {_point(t)}): a joint would jump {jump:.0f} "
                                 f"degrees; use MOVE, or a line that avoids it")
            path.append(q)
        self.check_table(path)
        return path

    def check_table(self, path: list[list[float]]) -> None:
        limit = self.model.table_z
        for q in path:
            for j, f in zip(self.model.joints, frames(self.model, q)):
                if f[2, 3] < limit - 1e-9:
                    raise RobotError(f"the move would take the {j.name} link to z = {f[2, 3]:.1f} mm, below "
                                     f"the table plane z = {limit:g} mm")

    def joint_seconds(self, path: list[list[float]], percent: float) -> float:
        """At percent of full speed: as long as the slowest joint needs."""
        full = max(sum(abs(b[i] - a[i]) for a, b in zip(path, path[1:])) / j.speed
                   for i, j in enumerate(self.model.joints))
        return full / (percent / 100.0)

    def line_seconds(self, path: list[list[float]], percent: float) -> float:
        length = float(np.linalg.norm(fk(self.model, path[-1])[:3, 3] - fk(self.model, path[0])[:3, 3]))
        return max(length / self.model.linear_speed, self.joint_seconds(path, 100.0)) / (percent / 100.0)


def _point(t: np.ndarray) -> str:
    return "(" + ", ".join(f"{c:.1f}" for c in t[:3, 3]) + ")"
