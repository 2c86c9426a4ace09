"""Vision: finding a graspable wire end in an image. Plain numpy; nothing here knows RCL.

find_wires(image, method, px_per_mm) runs one of the paper's systems; Sighting is
what every finder reports, in pixels of the input image (u = column, v = row).
"""
from __future__ import annotations

from .sighting import Sighting

METHODS = ("binary", "grey")


class VisionError(ValueError):
    """A method that cannot be used, or an image it cannot work on."""


def find_wires(image, method: str = "binary", px_per_mm: float = 4.0):
    """Candidates best-first (with .candidates and .timings in ms) for one image."""
    if not px_per_mm > 0:
        raise VisionError(f"the scale must be a positive number of px per mm, not {px_per_mm}")
    if method == "binary":
        from .binary import find_wires_binary

        return find_wires_binary(image, px_per_mm)
    if method == "grey":
        from .grey import find_wires_grey

        return find_wires_grey(image, px_per_mm)
    raise VisionError(f"unknown method {method!r} (binary or grey)")


__all__ = ["Sighting", "find_wires", "VisionError", "METHODS"]
