"""What a wire finder reports about one graspable wire end."""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Sighting:
    """A wire end and where to grasp the wire, in pixels (u = column, v = row).

    end_angle: degrees, atan2(dv, du) of the direction from the end into the wire.
    grasp_angle: degrees in [0, 180), the direction of the wire's tangent at the grasp point.
    """

    end: tuple[float, float]
    end_angle: float
    grasp: tuple[float, float]
    grasp_angle: float
    score: float = 1.0
