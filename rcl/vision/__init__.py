"""Vision: finding a graspable wire end in an image. Plain numpy; nothing here knows RCL.

Sighting is the result every wire finder gives, in pixels of the input image.
"""
from .sighting import Sighting

__all__ = ["Sighting"]
