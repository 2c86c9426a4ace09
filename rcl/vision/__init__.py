"""Vision: finding a graspable wire end in an image. Plain numpy; nothing here knows RCL.

find_wires(image, method, px_per_mm) runs one of the paper's systems; Sighting is
what every finder reports, in pixels of the input image (u = column, v = row).
"""
from __future__ import annotations

from .sighting import Sighting

METHODS = ("ridge", "grey", "binary")
DEFAULT_METHOD = "ridge"
MIDDLE = "middle"  # not an end finder: where to take a wire by its middle (ridge.find_middle)


class VisionError(ValueError):
    """A method that cannot be used, or an image it cannot work on."""


def load(method: str):
    """The finder for a method (imported, its tables built)."""
    if method == "binary":
        from .binary import deletion_tables, find_wires_binary

        deletion_tables()
        return find_wires_binary
    if method == "ridge":
        from .ridge import find_wires_ridge

        return find_wires_ridge
    if method == "grey":
        from .grey import find_wires_grey

        return find_wires_grey
    if method == MIDDLE:
        from .ridge import find_middle

        return find_middle
    raise VisionError(f"unknown method {method!r} (one of {', '.join(METHODS)})")


MIN_PX_PER_MM, MAX_PX_PER_MM = 0.5, 100.0  # a 1 mm wire a pixel wide at least; a 10 mm field at most at 1000 px


def find_wires(image, method: str = DEFAULT_METHOD, px_per_mm: float = 4.0):
    """Candidates best-first (with .candidates and .timings in ms) for one image."""
    if not MIN_PX_PER_MM <= px_per_mm <= MAX_PX_PER_MM:
        raise VisionError(f"the scale must be {MIN_PX_PER_MM:g} to {MAX_PX_PER_MM:g} px per mm, not {px_per_mm}")
    return load(method)(image, px_per_mm)


__all__ = ["DEFAULT_METHOD", "METHODS", "MIDDLE", "Sighting", "VisionError", "find_wires", "load"]
