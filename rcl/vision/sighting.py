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

    def __post_init__(self) -> None:  # plain floats, whatever numpy scalars a finder computed with
        object.__setattr__(self, "end", (float(self.end[0]), float(self.end[1])))
        object.__setattr__(self, "grasp", (float(self.grasp[0]), float(self.grasp[1])))
        for name in ("end_angle", "grasp_angle", "score"):
            object.__setattr__(self, name, float(getattr(self, name)))
