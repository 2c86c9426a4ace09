"""A PNG of the arm's path, drawn with Pillow: a top view and a side view at one scale, with
axes in millimetres (ticks, a grid, their names), each motion numbered at its end and
coloured by kind, and a legend."""
from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

SIZE = 420  # px, each panel
MARGIN = 44  # px, room for the tick labels
TOP = 22  # px, the title's line
LEGEND = 34  # px, the legend's lines at the bottom
COLOURS = {"move": (30, 90, 200), "moves": (200, 60, 30), "jmove": (120, 60, 170), "home": (110, 110, 110)}
WORDS = {"move": "MOVE (joints interpolated)", "moves": "MOVES (straight line)", "jmove": "JMOVE",
         "home": "HOME"}


def nice_step(span: float, ticks: int = 5) -> float:
    """A round tick step (1, 2 or 5 times a power of ten) giving about `ticks` ticks over span."""
    raw = max(span, 1e-9) / ticks
    power = 10.0 ** math.floor(math.log10(raw))
    return next(m * power for m in (1, 2, 5, 10) if m * power >= raw)


def plot_path(motions: Sequence[tuple[str, np.ndarray]], path: str, title: str) -> None:
    """motions: (kind, (N, 3) points in mm, base coordinates) in the order they ran; a kind
    ending in ' (halted)' was stopped part way."""
    from PIL import Image, ImageDraw, ImageFont

    img = Image.new("RGB", (2 * SIZE, TOP + SIZE + LEGEND), "white")
    draw = ImageDraw.Draw(img)
    draw.font = ImageFont.load_default(size=12)  # Pillow's own scalable font: its spaces show
    draw.text((8, 5), title, fill="black")
    pts = np.vstack([np.asarray(p, float).reshape(-1, 3) for _, p in motions]) if motions else np.zeros((0, 3))
    for panel, (i, j, names) in enumerate(((0, 1, ("x", "y", "top view")), (0, 2, ("x", "z", "side view")))):
        x0 = panel * SIZE
        left, right, top, bottom = x0 + MARGIN, x0 + SIZE - 12, TOP + 12, TOP + SIZE - MARGIN
        draw.rectangle([left, top, right, bottom], outline=(150, 150, 150))
        draw.text((left, TOP), f"{names[2]} (mm)", fill="black")
        draw.text(((left + right) // 2, bottom + 24), f"{names[0]} (mm)", fill="black")
        draw.text((x0 + 4, (top + bottom) // 2), names[1], fill="black")
        if not len(pts):
            continue
        a, b = pts[:, i], pts[:, j]
        # one scale for both axes (a circle stays round), centred on the path
        span = max(float(a.max() - a.min()), float(b.max() - b.min()), 10.0) * 1.1
        ca, cb = (a.max() + a.min()) / 2, (b.max() + b.min()) / 2
        scale = min(right - left, bottom - top) / span

        mid_x, mid_y = (left + right) / 2, (top + bottom) / 2

        def at(p: float, q: float, mid_x=mid_x, mid_y=mid_y, ca=ca, cb=cb, scale=scale) -> tuple[float, float]:
            return (mid_x + (p - ca) * scale, mid_y - (q - cb) * scale)

        step = nice_step(span)
        lo_a, hi_a = ca - (right - left) / 2 / scale, ca + (right - left) / 2 / scale
        lo_b, hi_b = cb - (bottom - top) / 2 / scale, cb + (bottom - top) / 2 / scale
        for v in np.arange(math.ceil(lo_a / step) * step, hi_a, step):
            x, _ = at(v, cb)
            draw.line([(x, top), (x, bottom)], fill=(228, 228, 228))
            draw.line([(x, bottom), (x, bottom + 4)], fill="black")
            draw.text((x - 12, bottom + 7), f"{v:g}", fill="black")
        for v in np.arange(math.ceil(lo_b / step) * step, hi_b, step):
            _, y = at(ca, v)
            draw.line([(left, y), (right, y)], fill=(228, 228, 228))
            draw.line([(left - 4, y), (left, y)], fill="black")
            draw.text((left - 40, y - 6), f"{v:>6g}", fill="black")
        labels: dict[tuple[int, int], list[str]] = {}  # motions ending at one spot share a label
        for n, (kind, p) in enumerate(motions, start=1):
            p = np.asarray(p, float).reshape(-1, 3)
            colour = COLOURS.get(kind.split()[0], (0, 0, 0))
            xy = [at(q[i], q[j]) for q in p]
            if len(xy) > 1:
                draw.line(xy, fill=colour, width=2)
            ex, ey = xy[-1]
            draw.ellipse([ex - 2, ey - 2, ex + 2, ey + 2], fill=colour)
            labels.setdefault((round(ex / 6), round(ey / 6)), []).append(str(n))
        if len(motions) <= 60:  # numbers on a long run would only cover the path
            for (gx, gy), ns in labels.items():
                draw.text((gx * 6 + 4, gy * 6 - 13), ", ".join(ns), fill="black")
        sx, sy = at(pts[0, i], pts[0, j])
        draw.ellipse([sx - 4, sy - 4, sx + 4, sy + 4], outline=(0, 150, 0), width=2)
    # the legend
    y = TOP + SIZE + 4
    x = 8
    kinds = [k for k in COLOURS if any(m.split()[0] == k for m, _ in motions)] or list(COLOURS)
    items = [(COLOURS[k], WORDS[k]) for k in kinds] + [((0, 150, 0), "start (ring)")]
    for colour, words in items:
        draw.line([(x, y + 7), (x + 18, y + 7)], fill=colour, width=3)
        draw.text((x + 22, y + 1), words, fill="black")
        x += 30 + int(draw.textlength(words))
    draw.text((8, y + 16), "motions are numbered at their ends, in the order they ran", fill="black")
    img.save(path)
