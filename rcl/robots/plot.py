"""A PNG of a path of points, drawn with Pillow: a top view and a side view."""
from __future__ import annotations

from typing import Sequence

import numpy as np

SIZE = 360
MARGIN = 30


def plot_path(points: Sequence[np.ndarray], path: str, title: str) -> None:
    from PIL import Image, ImageDraw

    img = Image.new("RGB", (2 * SIZE, SIZE + 20), "white")
    draw = ImageDraw.Draw(img)
    draw.text((8, 4), title, fill="black")
    pts = np.array(points, dtype=float).reshape(-1, 3)
    for panel, (i, j, label) in enumerate(((0, 1, "top view: x right, y up"), (0, 2, "side view: x right, z up"))):
        x0 = panel * SIZE
        draw.rectangle([x0 + MARGIN, 20 + MARGIN, x0 + SIZE - MARGIN, 20 + SIZE - MARGIN], outline="grey")
        draw.text((x0 + MARGIN, 20 + SIZE - MARGIN + 6), label, fill="black")
        if len(pts) == 0:
            continue
        a, b = pts[:, i], pts[:, j]
        lo = min(a.min(), b.min())
        hi = max(a.max(), b.max())
        scale = (SIZE - 2 * MARGIN) / max(hi - lo, 1.0)
        xy = [(x0 + MARGIN + (p - lo) * scale, 20 + SIZE - MARGIN - (q - lo) * scale) for p, q in zip(a, b)]
        if len(xy) > 1:
            draw.line(xy, fill="blue", width=1)
        draw.ellipse([xy[0][0] - 3, xy[0][1] - 3, xy[0][0] + 3, xy[0][1] + 3], outline="green")
        draw.ellipse([xy[-1][0] - 3, xy[-1][1] - 3, xy[-1][0] + 3, xy[-1][1] + 3], outline="red")
        draw.text((x0 + SIZE - MARGIN - 80, 20 + 4 + MARGIN), f"{lo:.0f}..{hi:.0f} mm", fill="grey")
    img.save(path)
