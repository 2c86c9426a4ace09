"""Cameras that deliver images: for now, image files on disk."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .images import ImageError, read_image

IMAGE_SUFFIXES = {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp", ".pgm", ".ppm", ".pnm", ".gif", ".webp"}


class ImageFiles:
    """A camera reading files: one image file (the same picture every time) or a folder
    (its images in name order, the next one at every grab)."""

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        if self.path.is_dir():
            self.files = sorted(p for p in self.path.iterdir() if p.suffix.lower() in IMAGE_SUFFIXES)
            if not self.files:
                raise ImageError(f"{self.path} holds no image files")
        elif self.path.is_file():
            self.files = [self.path]
        else:
            raise ImageError(f"{self.path}: no such file or folder")
        self.taken = 0

    def grab(self) -> np.ndarray:
        if self.path.is_dir():
            if self.taken >= len(self.files):
                raise ImageError(f"no more images in {self.path} (all {len(self.files)} were used)")
            path = self.files[self.taken]
        else:
            path = self.path
        self.taken += 1
        return read_image(path)
