"""Pictures of what a wire finder saw: the image, its skeleton or boundaries, every
candidate, and the chosen end and grasp with the W and WG axes (Pillow)."""
from __future__ import annotations

import math

import numpy as np

from ..camera.images import as_grey

SKELETON = (255, 60, 60)
CONTOUR = (255, 60, 60)
CANDIDATE = (255, 200, 0)
W_Z = (0, 120, 255)  # W^'s Z: from the end along the wire
W_Y = (0, 200, 0)
GRIP = (255, 0, 255)  # WG^: the fingers close across the wire at the grasp point


def draw(image: np.ndarray, result, arrow_px: float | None = None, legend: bool = True):
    """A Pillow RGB image of `image` with the result of find_wires drawn on it, and below it
    (unless legend is False) a strip that says what each colour is."""
    from PIL import Image, ImageDraw

    grey = as_grey(image)
    lo, hi = float(grey.min()), float(grey.max())
    if lo >= 0.0 and hi <= 1.0:  # fixed levels: an empty tray looks like a tray, not a camera fault
        base = grey * 255.0
    else:  # numbers in units of their own: shown from their least to their most
        base = (grey - lo) / (hi - lo) * 255.0
    picture = Image.fromarray(base.astype(np.uint8)).convert("RGB")
    pen = ImageDraw.Draw(picture)
    h, w = grey.shape
    arrow = arrow_px or max(12.0, min(h, w) / 20.0)
    skeleton = getattr(result, "skeleton", None)
    if skeleton is not None:
        k = result.scale
        rows, cols = np.nonzero(skeleton)
        for r, c in zip(rows.tolist(), cols.tolist()):
            pen.rectangle([c * k, r * k, c * k + k - 1, r * k + k - 1], fill=SKELETON)
    for contour in getattr(result, "contours", []):
        if len(contour) > 1:
            pen.line([tuple(p) for p in contour.tolist()], fill=CONTOUR, width=1)
    for s in result.candidates[1:]:
        _ring(pen, s.end, 4, CANDIDATE)
        _ring(pen, s.grasp, 3, CANDIDATE)
    if result.candidates:
        s = result.candidates[0]
        a = math.radians(s.end_angle)
        z = (math.cos(a), math.sin(a))
        _arrow(pen, s.end, z, arrow, W_Z)
        _arrow(pen, s.end, (-z[1], z[0]), arrow * 0.6, W_Y)
        _ring(pen, s.end, 6, W_Z)
        t = math.radians(s.grasp_angle)
        across = (-math.sin(t), math.cos(t))
        gu, gv = s.grasp
        half = arrow * 0.5
        pen.line([(gu - across[0] * half, gv - across[1] * half), (gu + across[0] * half, gv + across[1] * half)],
                 fill=GRIP, width=3)
        pen.line([(gu - math.cos(t) * half * 0.5, gv - math.sin(t) * half * 0.5),
                  (gu + math.cos(t) * half * 0.5, gv + math.sin(t) * half * 0.5)], fill=GRIP, width=1)
        _ring(pen, s.grasp, 5, GRIP)
    return _with_legend(picture, result) if legend else picture


def legend_items(result) -> list[tuple[tuple, str]]:
    """(colour, words) for each thing an overlay of this result draws."""
    from .binary import BinaryResult
    from .grey import GreyResult

    seen = ("skeleton" if isinstance(result, BinaryResult) else "traced boundaries"
            if isinstance(result, GreyResult) else "centre lines")
    return [(SKELETON, seen), (CANDIDATE, "other free ends and grasps"),
            (W_Z, "chosen end: W's Z, along the wire"), (W_Y, "W's Y"),
            (GRIP, "grasp: the fingers close across")]


def _with_legend(picture, result):
    """The picture with a dark strip below it naming each colour (wrapped to its width)."""
    from PIL import Image, ImageDraw, ImageFont

    font = ImageFont.load_default(size=11)
    w, h = picture.size
    measure = ImageDraw.Draw(picture)
    rows, x = [[]], 4
    for colour, words in legend_items(result):
        width = 18 + int(measure.textlength(words, font=font)) + 12
        if x + width > w and rows[-1]:
            rows.append([])
            x = 4
        rows[-1].append((x, colour, words))
        x += width
    out = Image.new("RGB", (w, h + 16 * len(rows) + 4), (24, 24, 24))
    out.paste(picture, (0, 0))
    pen = ImageDraw.Draw(out)
    for i, row in enumerate(rows):
        y = h + 3 + 16 * i
        for x, colour, words in row:
            pen.line([(x, y + 7), (x + 14, y + 7)], fill=colour, width=3)
            pen.text((x + 18, y), words, fill=(235, 235, 235), font=font)
    return out


def _ring(pen, at, r: float, colour) -> None:
    u, v = at
    pen.ellipse([u - r, v - r, u + r, v + r], outline=colour, width=2)


def _arrow(pen, start, direction, length: float, colour) -> None:
    u, v = start
    du, dv = direction
    tip = (u + du * length, v + dv * length)
    pen.line([start, tip], fill=colour, width=2)
    for turn in (2.6, -2.6):  # the head
        c, s = math.cos(turn), math.sin(turn)
        hu, hv = du * c - dv * s, du * s + dv * c
        pen.line([tip, (tip[0] + hu * length * 0.25, tip[1] + hv * length * 0.25)], fill=colour, width=2)
