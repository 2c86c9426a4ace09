"""Randomized trays: every look drawn afresh from what real trays vary, with ground truth.

(About 560 lines, over the ~500 we hold modules to: the draw (Scene, draw_scene, random_wire,
wire_look) and the painting that uses each drawn choice (board, finish, _paint_wire) are
read together; the painting could move to a module of its own, as the cell's renderer would
then import it alone.)

random_tray(seed, slice=None) draws a Scene (how the tray looks) and its wires
from the seed, renders it and computes the same ground truth as synth.make_tray:
each wire's centre line in mm (end 0 to end 1, conductor tips included) and
which ends a gripper could take. Image coordinates: u = column, v = row,
px = mm * px_per_mm.

What is drawn per tray:
- image size 320 x 240 to 2048 x 2048, scale 2.5-8 px/mm (the tray at least 55 mm across);
- 1-25 wires in up to 4 layers; each near-straight, gently bent, an S-bend, a tight
  curl or a loop that crosses itself; 0.8-3 mm thick; some running off the frame;
- insulation black, white, grey, red, blue, green/yellow striped or translucent
  (with the copper core showing through);
- each end flat-cut, rounded, crimped into a ferrule, stripped to copper, or tinned;
- a round wire's shading (darker flanks, a specular line) and its soft shadow;
- a board that is plain, paper, wood grain, speckled, a cutting mat with a grid,
  or a printed two-tone pattern, in any colour; a tray rim or clutter at the frame
  edge;
- uneven light and vignetting, defocus and motion blur, sensor noise, JPEG
  compression, colour or grey.

Slices are named constraints on the draw (SLICES): today's synth kinds (sparse,
crossing, low_contrast, bright_on_dark, stripped, colour, edge) and more
(textured, curly, thin, dense, photographic, plain_dark, plain_bright). A tray
drawn with no slice is drawn from everything; `tags(scene)` says which slices a
drawn scene falls in, so a benchmark can report per slice on fully random trays.
"""
from __future__ import annotations

import io
import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from .synth import Thing, Tray, Wire, ground_truth, keep_apart, resample

SLICES = ("sparse", "crossing", "low_contrast", "bright_on_dark", "stripped", "colour", "edge",
          "textured", "curly", "thin", "dense", "photographic", "plain_dark", "plain_bright")
SIZES = ((320, 240), (512, 512), (640, 480), (800, 600), (1024, 768), (1280, 960), (2048, 2048))
SIZE_WEIGHTS = (0.12, 0.35, 0.25, 0.12, 0.08, 0.05, 0.03)
SHAPES = ("straight", "gentle", "s_bend", "curl", "loop")
SHAPE_WEIGHTS = (0.2, 0.35, 0.2, 0.15, 0.1)
ENDS = ("flat", "rounded", "ferrule", "copper", "tinned")
INSULATION = ("black", "white", "grey", "red", "blue", "striped", "translucent")
BOARDS = ("plain", "paper", "wood", "speckled", "mat", "printed")
MIN_EXTENT_MM = 55.0  # the smaller side of the field of view: room for a wire's free 20 mm and more
MIN_CONTRAST = 0.18  # least RGB distance between a wire and its board: a person could see it

COLOURS = {
    "black": (0.08, 0.08, 0.09), "white": (0.92, 0.92, 0.9), "grey": (0.5, 0.5, 0.52),
    "red": (0.78, 0.12, 0.1), "blue": (0.12, 0.25, 0.72), "striped": (0.1, 0.55, 0.2),
    "translucent": (0.85, 0.85, 0.8),
}
STRIPE = (0.9, 0.8, 0.1)  # the yellow of green/yellow earth wire
METAL = {"ferrule": (0.8, 0.8, 0.83), "copper": (0.86, 0.52, 0.3), "tinned": (0.74, 0.74, 0.77)}


@dataclass
class WireLook:
    insulation: str
    colour: tuple
    ends: tuple  # end kind at end 0 and end 1
    tip_mm: tuple  # conductor or ferrule length at each end (0 for flat/rounded)
    gloss: float


@dataclass
class Scene:
    """How one tray looks: everything random_tray draws before it renders."""

    width: int
    height: int
    px_per_mm: float
    colour: bool
    count: int
    layers: int
    shapes: tuple
    thickness: tuple  # mm, the least and most wire diameter
    insulation: tuple  # the insulation kinds to draw from
    end_kinds: tuple
    board: str
    board_colour: tuple
    board_contrast: float  # amplitude of the board's texture
    light: tuple  # (gradient strength, gradient angle rad, vignetting)
    light_dir: tuple  # unit vector (x, y, z): where the lamp is, for shading and shadows
    shadow: float  # 0: none; else the shadow's darkness
    blur_px: float
    motion_px: float
    noise: float
    jpeg: int  # quality, 0: none
    rim: bool
    clutter: int
    off_frame: float  # share of wires placed to run off the frame
    apart: bool  # wires kept clear of each other (sparse)
    slice: str = ""
    looks: list = field(default_factory=list)
    things: list = field(default_factory=list)  # synth.Thing: the rim and clutter as drawn


def draw_scene(rng: np.random.Generator, slice: str | None = None) -> Scene:
    """A scene drawn at random; a slice constrains the draw."""
    if slice is not None and slice not in SLICES:
        raise ValueError(f"unknown slice {slice!r} (one of {', '.join(SLICES)})")
    s = slice or ""
    w, h = SIZES[int(rng.choice(len(SIZES), p=SIZE_WEIGHTS))]
    if rng.random() < 0.5:
        w, h = (h, w) if rng.random() < 0.3 else (w, h)
    ppm = float(rng.uniform(2.5, 8.0))
    ppm = min(ppm, min(w, h) / MIN_EXTENT_MM)
    if s in ("sparse", "crossing", "low_contrast", "bright_on_dark", "stripped", "colour", "edge",
             "plain_dark", "plain_bright"):
        ppm = float(rng.uniform(2.5, min(6.0, min(w, h) / MIN_EXTENT_MM)))
    area = (w / ppm) * (h / ppm)
    most = float(np.clip(area / 500.0, 3, 25))  # at most a wire per 500 mm2 of tray
    count = round(math.exp(rng.uniform(0.0, math.log(most))))
    layers = int(rng.integers(1, 5))
    shapes: tuple[str, ...] = SHAPES
    thickness = (0.8, 3.0)
    insulation: tuple[str, ...] = INSULATION
    end_kinds: tuple[str, ...] = ENDS
    board = str(rng.choice(BOARDS, p=(0.3, 0.15, 0.15, 0.15, 0.1, 0.15)))
    board_colour = _board_colour(rng)
    board_contrast = float(rng.uniform(0.02, 0.12))
    light = (float(rng.uniform(0.0, 0.45)), float(rng.uniform(0, 2 * math.pi)), float(rng.uniform(0.0, 0.35)))
    a = rng.uniform(0, 2 * math.pi)
    elev = rng.uniform(math.radians(35), math.radians(85))
    light_dir = (math.cos(a) * math.cos(elev), math.sin(a) * math.cos(elev), math.sin(elev))
    shadow = float(rng.uniform(0.0, 0.35)) if rng.random() < 0.7 else 0.0
    blur = float(rng.uniform(0.0, 1.4)) if rng.random() < 0.6 else 0.0
    motion = float(rng.uniform(0.0, 3.0)) if rng.random() < 0.15 else 0.0
    noise = float(rng.uniform(0.003, 0.035))
    jpeg = int(rng.integers(40, 96)) if rng.random() < 0.5 else 0
    colour = bool(rng.random() < 0.7)
    rim = bool(rng.random() < 0.25)
    clutter = int(rng.integers(1, 5)) if rng.random() < 0.25 else 0
    off_frame = float(rng.uniform(0.0, 0.4))
    apart = False
    # the slices: constraints on the draw
    if s == "sparse":
        count, layers, apart, shapes = int(rng.integers(2, 6)), 1, True, ("straight", "gentle", "s_bend")
        board, board_contrast, off_frame = "plain", 0.02, 0.0
    elif s == "crossing":
        count, layers = int(rng.integers(6, 13)), int(rng.integers(2, 5))
    elif s == "low_contrast":
        light = (float(rng.uniform(0.3, 0.5)), light[1], float(rng.uniform(0.15, 0.35)))
    elif s == "bright_on_dark":
        board_colour = tuple(float(x) for x in rng.uniform(0.05, 0.2) * np.ones(3))
        insulation = ("white", "translucent", "grey")
        board = str(rng.choice(("plain", "paper", "mat")))
    elif s == "stripped":
        end_kinds = ("ferrule", "copper", "tinned")
    elif s == "colour":
        colour, insulation = True, ("red", "blue", "striped", "black", "white")
        board_colour = tuple(float(x) for x in rng.uniform(0.2, 0.8, 3))
    elif s == "edge":
        off_frame = float(rng.uniform(0.6, 1.0))
    elif s == "textured":
        board = str(rng.choice(("paper", "wood", "speckled", "mat", "printed")))
        board_contrast = float(rng.uniform(0.06, 0.15))
    elif s == "curly":
        shapes = ("curl", "loop", "s_bend")
    elif s == "thin":
        thickness = (0.8, 1.2)
    elif s == "dense":
        count, layers = int(rng.integers(15, 26)), int(rng.integers(2, 5))
    elif s == "photographic":
        blur, motion = float(rng.uniform(0.6, 1.6)), float(rng.uniform(0.0, 2.5))
        jpeg, noise = int(rng.integers(35, 80)), float(rng.uniform(0.015, 0.04))
        light = (float(rng.uniform(0.2, 0.5)), light[1], float(rng.uniform(0.2, 0.4)))
    elif s in ("plain_dark", "plain_bright"):  # what the paper's systems were made for
        board, board_contrast, clutter, rim = "plain", 0.02, 0, False
        grey = rng.uniform(0.65, 0.9) if s == "plain_dark" else rng.uniform(0.08, 0.25)
        board_colour = (float(grey),) * 3
        insulation = ("black",) if s == "plain_dark" else ("white",)
        end_kinds = ("flat", "rounded")
        count, layers = int(rng.integers(1, 8)), int(rng.integers(1, 3))
        blur, motion, jpeg = min(blur, 0.8), 0.0, 0
    return Scene(w, h, ppm, colour, count, layers, tuple(shapes), thickness, tuple(insulation), tuple(end_kinds),
                 board, board_colour, board_contrast, light, light_dir, shadow, blur, motion, noise, jpeg,
                 rim, clutter, off_frame, apart, s)


def tags(scene: Scene) -> set[str]:
    """The slices a drawn scene falls in (one tray may be in several)."""
    t = set()
    if scene.slice:
        t.add(scene.slice)
    if scene.board != "plain" and scene.board_contrast >= 0.06:
        t.add("textured")
    if scene.count >= 15:
        t.add("dense")
    if scene.layers >= 2 and scene.count >= 6:
        t.add("crossing")
    if scene.blur_px >= 0.6 and 0 < scene.jpeg <= 80:
        t.add("photographic")
    if scene.off_frame >= 0.6:
        t.add("edge")
    if scene.looks and all(lk.insulation in ("black", "white") for lk in scene.looks) and scene.board == "plain":
        lum = float(np.mean(scene.board_colour))
        if all(lk.insulation == "black" for lk in scene.looks) and lum > 0.55:
            t.add("plain_dark")
        if all(lk.insulation == "white" for lk in scene.looks) and lum < 0.35:
            t.add("plain_bright")
    if scene.looks and any(k in ("ferrule", "copper", "tinned") for lk in scene.looks for k in lk.ends):
        t.add("stripped")
    return t


def random_tray(seed: int, slice: str | None = None) -> Tray:
    """A randomized tray; the same seed and slice give the same tray."""
    rng = np.random.default_rng([seed, 1 + (SLICES.index(slice) if slice else len(SLICES))])
    scene = draw_scene(rng, slice)
    extent = np.array([scene.width, scene.height]) / scene.px_per_mm
    wires = [random_wire(rng, scene, extent, i) for i in range(scene.count)]
    if scene.apart:
        wires = keep_apart(wires)
    scene.looks = [wire_look(rng, scene) for _ in wires]
    for w, look in zip(wires, scene.looks):
        w.level = look.colour
        w.tip = max(look.tip_mm)
    image = render(scene, wires, rng)
    tray = Tray(image, scene.px_per_mm, wires, kind=slice or "random", things=list(scene.things))
    tray.ends = ground_truth(wires, extent, scene.things)
    tray.scene = scene  # type: ignore[attr-defined]
    return tray


def tray_scene(rng: np.random.Generator, width: int, height: int, px_per_mm: float, count: int, layers: int,
               slice: str | None = None) -> Scene:
    """A scene for a tray of known size and scale (a work cell's): drawn as random_tray draws its
    scene, but the frame is the tray itself, so every wire lies wholly on it and there is no rim
    or clutter drawn at the frame's edge (the tray's own edge is its rim)."""
    scene = draw_scene(rng, slice)
    return replace(scene, width=int(width), height=int(height), px_per_mm=float(px_per_mm), count=int(count),
                   layers=max(int(layers), 1), rim=False, clutter=0, off_frame=0.0, apart=False, looks=[], things=[])


# Wires -------------------------------------------------------------------------------


def random_wire(rng, scene: Scene, extent: np.ndarray, index: int) -> Wire:
    """A wire's centre line (mm) of a shape drawn from the scene's, placed on the tray."""
    weights = np.array([SHAPE_WEIGHTS[SHAPES.index(k)] for k in scene.shapes])
    shape = str(rng.choice(scene.shapes, p=weights / weights.sum()))
    diameter = float(rng.uniform(*scene.thickness))
    span = float(min(extent))
    length = float(rng.uniform(0.45, 1.1) * span)
    length = max(min(length, 160.0), 35.0)
    step = 0.5
    n = int(length / step)
    s = np.arange(n) * step
    if shape == "straight":
        curv = np.full(n, rng.normal(0, 0.002))
    elif shape == "gentle":
        curv = rng.normal(0, 0.012) + np.cumsum(rng.normal(0, 0.0015, n)) * 0.1
    elif shape == "s_bend":
        amp = rng.uniform(0.03, 0.07) * rng.choice((-1, 1))
        curv = amp * np.sin(2 * math.pi * s / length * rng.uniform(1.0, 2.0) + rng.uniform(0, math.pi))
    else:  # a curl (part of a turn) or a loop (a full turn: the wire crosses itself)
        radius = max(rng.uniform(4.0, 12.0), 2.5 * diameter)
        turn = rng.uniform(0.6, 0.9) if shape == "curl" else rng.uniform(1.05, 1.3)
        arc = 2 * math.pi * radius * turn
        if arc > 0.7 * length:
            length = arc / 0.7
            n = int(length / step)
            s = np.arange(n) * step
        start = rng.uniform(0.15, 0.85) * (length - arc)
        curv = np.where((s >= start) & (s < start + arc), rng.choice((-1, 1)) / radius, 0.0)
        curv = curv + rng.normal(0, 0.004)
    heading = rng.uniform(0, 2 * math.pi) + np.cumsum(curv * step)
    pts = np.cumsum(np.column_stack([np.cos(heading), np.sin(heading)]) * step, axis=0)
    pts = pts - pts.mean(axis=0)
    if rng.random() < scene.off_frame:  # a wire that runs off the frame
        centre = pts + rng.uniform(-0.1, 1.1, 2) * extent
    else:
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        room = extent - (hi - lo) - 8.0
        offset = np.where(room > 0, 4.0 + rng.uniform(0, 1, 2) * np.maximum(room, 0), (extent - (hi - lo)) / 2)
        centre = pts - lo + offset
    layer = int(rng.integers(scene.layers)) if not scene.apart else index
    return Wire(centre, diameter, layer, (0.1,), 0.0)


def _board_colour(rng) -> tuple:
    palette = ((0.85, 0.85, 0.83), (0.62, 0.62, 0.6), (0.82, 0.74, 0.6), (0.6, 0.42, 0.25),
               (0.2, 0.45, 0.3), (0.25, 0.3, 0.55), (0.2, 0.2, 0.21), (0.08, 0.08, 0.08), (0.93, 0.93, 0.95))
    base = np.array(palette[int(rng.integers(len(palette)))])
    return tuple(float(x) for x in np.clip(base + rng.normal(0, 0.04, 3), 0.02, 0.98))


def wire_look(rng: np.random.Generator, scene: Scene) -> WireLook:
    """A wire's insulation, ends and gloss, drawn so that it can be seen on the scene's board."""
    board = np.array(scene.board_colour)
    for _ in range(30):
        kind = str(rng.choice(scene.insulation))
        colour = np.clip(np.array(COLOURS[kind]) + rng.normal(0, 0.04, 3), 0.02, 0.98)
        seen = 0.8 * colour  # as the wire's shading shows it, on average
        if kind == "translucent":
            seen = 0.5 * seen + 0.5 * board
        if not scene.colour:
            if abs(float(seen @ [0.299, 0.587, 0.114]) - float(board @ [0.299, 0.587, 0.114])) >= MIN_CONTRAST:
                break
        elif np.linalg.norm(seen - board) >= MIN_CONTRAST * math.sqrt(3):
            break
    ends = tuple(str(rng.choice(scene.end_kinds)) for _ in range(2))
    tips = tuple(float(rng.uniform(3.0, 8.0)) if e in METAL else 0.0 for e in ends)
    return WireLook(kind, tuple(float(x) for x in colour), ends, tips, float(rng.uniform(0.1, 0.6)))


# Rendering ---------------------------------------------------------------------------


def render(scene: Scene, wires: list[Wire], rng) -> np.ndarray:
    """The tray's image, float in [0, 1]: (h, w) grey or (h, w, 3) colour."""
    return finish(scene, paint(scene, wires, scene.looks, backdrop(scene, rng)), rng)


def backdrop(scene: Scene, rng) -> np.ndarray:
    """The board with its rim and clutter, (h, w, 3) float32: what lies under the wires."""
    img = board(scene, rng)
    if scene.rim:
        _rim(img, scene, rng)
    for _ in range(scene.clutter):
        _clutter(img, scene, rng)
    return img


def paint(scene: Scene, wires: list[Wire], looks: list[WireLook], under: np.ndarray) -> np.ndarray:
    """The wires drawn (lowest layer first, each with its shadow) over a copy of `under`."""
    img = under.copy()
    for i in sorted(range(len(wires)), key=lambda i: wires[i].layer):
        _paint_wire(img, wires[i], looks[i], scene)
    return img


def finish(scene: Scene, img: np.ndarray, rng) -> np.ndarray:
    """What the camera makes of the lit tray: uneven light and vignetting, blur, noise, grey or
    colour, JPEG."""
    from scipy import ndimage

    h, w = img.shape[:2]
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
    g, ang, vig = scene.light
    ramp = ((xx / w - 0.5) * math.cos(ang) + (yy / h - 0.5) * math.sin(ang))
    r2 = ((xx / w - 0.5) ** 2 + (yy / h - 0.5) ** 2) * 2.0
    img = img * ((1.0 + g * ramp) * (1.0 - vig * r2))[..., None]
    if scene.blur_px > 0:
        img = ndimage.gaussian_filter(img, (scene.blur_px, scene.blur_px, 0))
    if scene.motion_px > 0:  # a smear motion_px + 1 px long, centred (no shift of the picture)
        span = scene.motion_px + 1.0
        n = math.ceil(span) | 1
        kernel = np.clip(span / 2 + 0.5 - np.abs(np.arange(n) - n // 2), 0.0, 1.0).astype(np.float32)
        img = ndimage.convolve1d(img, kernel / kernel.sum(), axis=int(rng.integers(2)))
    if scene.noise > 0:
        img = img + rng.normal(0.0, scene.noise, img.shape).astype(np.float32)
    img = np.clip(img, 0.0, 1.0)
    if not scene.colour:
        img = img @ np.array([0.299, 0.587, 0.114], np.float32)
    if scene.jpeg:
        img = _jpeg(img, scene.jpeg)
    return img.astype(np.float64)


def board(scene: Scene, rng) -> np.ndarray:
    """The bare board (h, w, 3) float32, its texture in mm so it scales with the picture."""
    from scipy import ndimage

    h, w, ppm = scene.height, scene.width, scene.px_per_mm
    base = np.array(scene.board_colour, np.float32)
    img = np.broadcast_to(base, (h, w, 3)).copy()
    amp = scene.board_contrast

    def smooth_noise(sigma_mm: float) -> np.ndarray:
        """Unit-variance noise smoothed over sigma_mm (drawn coarse, then enlarged: cheap)."""
        k = max(int(sigma_mm * ppm / 3.0), 1)
        coarse = ndimage.gaussian_filter(rng.normal(0, 1, (h // k + 2, w // k + 2)).astype(np.float32),
                                         sigma_mm * ppm / k)
        n = ndimage.zoom(coarse, k, order=1)[:h, :w]
        return n / max(float(n.std()), 1e-6)

    mottle = smooth_noise(15.0) * 0.015
    if scene.board == "paper":
        tex = ndimage.gaussian_filter(rng.normal(0, 1, (h, w)).astype(np.float32), 0.6)
        tex = tex / max(float(tex.std()), 1e-6) * amp * 0.5
    elif scene.board == "wood":
        a = rng.uniform(0, math.pi)
        yy, xx = np.mgrid[0:h, 0:w].astype(np.float32) / ppm
        along = xx * math.cos(a) + yy * math.sin(a)
        across = -xx * math.sin(a) + yy * math.cos(a)
        warp = smooth_noise(8.0) * rng.uniform(1.0, 4.0)
        period = rng.uniform(1.5, 5.0)
        grain = np.sin(2 * math.pi * (across + warp + 0.02 * along) / period) ** 2
        strength = 0.5 + 0.5 * np.clip(smooth_noise(6.0), -1, 1)  # grain fades in and out
        tex = (grain - 0.5) * strength * amp * 0.8 + smooth_noise(0.3) * amp * 0.15
    elif scene.board == "speckled":
        dots = (rng.random((h, w)) < rng.uniform(0.002, 0.02) / max(ppm * ppm / 16, 0.25)).astype(np.float32)
        dots = ndimage.gaussian_filter(dots, rng.uniform(0.15, 0.4) * ppm)
        dots = dots / max(float(dots.max()), 1e-6)
        tex = dots * amp * rng.choice((-3.0, 3.0))
    elif scene.board == "mat":
        pitch = 10.0 * ppm  # a cutting mat's 10 mm grid of thin lines
        yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
        dx = (xx + rng.uniform(0, pitch)) % pitch
        dy = (yy + rng.uniform(0, pitch)) % pitch
        d = np.minimum(np.minimum(dx, pitch - dx), np.minimum(dy, pitch - dy))
        tex = np.clip(0.1 * ppm - d + 0.5, 0, 1) * amp * 2.5
    elif scene.board == "printed":
        patches = smooth_noise(rng.uniform(2.0, 6.0)) > rng.uniform(-0.5, 0.8)
        tex = ndimage.gaussian_filter(patches.astype(np.float32), 0.5) * amp * rng.choice((-1.5, 1.5))
    else:
        tex = np.zeros((h, w), np.float32)
    tint = np.ones(3, np.float32) if scene.board != "printed" else rng.uniform(0.5, 1.5, 3).astype(np.float32)
    img += (tex + mottle)[..., None] * tint
    return np.clip(img, 0.0, 1.0)


def _rim(img: np.ndarray, scene: Scene, rng) -> None:
    h, w = img.shape[:2]
    level = np.array(_board_colour(rng), np.float32)
    for side in rng.choice(4, size=int(rng.integers(1, 3)), replace=False):
        k = int(rng.uniform(0.03, 0.08) * (h if side < 2 else w))
        sl: Any = {0: np.s_[:k], 1: np.s_[h - k:], 2: np.s_[:, :k], 3: np.s_[:, w - k:]}[int(side)]
        img[sl] = level
        x0, y0, x1, y1 = {0: (0, 0, w, k), 1: (0, h - k, w, h), 2: (0, 0, k, h), 3: (w - k, 0, w, h)}[int(side)]
        ppm = scene.px_per_mm
        scene.things.append(Thing("the tray's rim", lo=np.array([x0, y0]) / ppm, hi=np.array([x1, y1]) / ppm))


def _clutter(img: np.ndarray, scene: Scene, rng) -> None:
    """A screw, a blob of glue or a scrap near the frame's edge."""
    h, w = img.shape[:2]
    ppm = scene.px_per_mm
    r = rng.uniform(1.5, 5.0) * ppm
    edge = int(rng.integers(4))
    t = rng.uniform(0, 1)
    depth = rng.uniform(0, 0.1)
    cu, cv = {0: (t * w, depth * h), 1: (t * w, (1 - depth) * h), 2: (depth * w, t * h), 3: ((1 - depth) * w, t * h)}[edge]
    r0, r1 = int(max(cv - r - 2, 0)), int(min(cv + r + 3, h))
    c0, c1 = int(max(cu - r - 2, 0)), int(min(cu + r + 3, w))
    if r0 >= r1 or c0 >= c1:
        return
    yy, xx = np.mgrid[r0:r1, c0:c1]
    cover = np.clip(r - np.hypot(xx - cu, yy - cv) + 0.5, 0, 1)[..., None]
    level = np.array(_board_colour(rng), np.float32)
    img[r0:r1, c0:c1] = img[r0:r1, c0:c1] * (1 - cover) + level * cover
    scene.things.append(Thing("something else on the tray", centre=np.array([cu, cv]) / ppm, radius=r / ppm))


def _paint_wire(img: np.ndarray, wire: Wire, look: WireLook, scene: Scene) -> None:
    """Draw one wire (its shadow first) over what is already in img."""
    from scipy import ndimage
    from scipy.spatial import cKDTree

    h, w = img.shape[:2]
    ppm = scene.px_per_mm
    r = wire.width * ppm / 2
    pts = wire.centre * ppm
    lx, ly, lz = scene.light_dir
    shift = np.array([-lx, -ly]) / max(lz, 0.3) * r * 0.8  # the shadow falls away from the lamp
    soft = 0.4 * r + 0.6
    pad = r + np.abs(shift).max() + 3 * soft + 2
    lo = np.floor(pts.min(axis=0) - pad).astype(int)
    hi = np.ceil(pts.max(axis=0) + pad).astype(int)
    c0, r0 = max(lo[0], 0), max(lo[1], 0)
    c1, r1 = min(hi[0], w), min(hi[1], h)
    if c0 >= c1 or r0 >= r1:
        return
    dense = resample(pts, 0.25)
    seg = np.linalg.norm(np.diff(dense, axis=0), axis=1)
    arc = np.concatenate([[0.0], np.cumsum(seg)]) / ppm  # mm from end 0
    tangent = np.gradient(dense, axis=0)
    tangent /= np.maximum(np.linalg.norm(tangent, axis=1, keepdims=True), 1e-9)
    length = arc[-1]
    # a rough distance on the pixel grid picks the pixels near the wire; the exact one is then
    # measured to the densely sampled centre line
    grid = np.ones((r1 - r0, c1 - c0), bool)
    iu = np.clip(np.round(dense[:, 0] - c0).astype(int), 0, c1 - c0 - 1)
    iv = np.clip(np.round(dense[:, 1] - r0).astype(int), 0, r1 - r0 - 1)
    inside = (dense[:, 0] >= c0) & (dense[:, 0] < c1) & (dense[:, 1] >= r0) & (dense[:, 1] < r1)
    grid[iv[inside], iu[inside]] = False
    if grid.all():
        return
    rough = ndimage.distance_transform_edt(grid)
    region = img[r0:r1, c0:c1]
    if scene.shadow > 0:
        sr, sc = round(shift[1]), round(shift[0])
        shadow = np.clip((r + soft - np.roll(rough, (sr, sc), axis=(0, 1))) / (2 * soft), 0, 1)
        shadow = ndimage.gaussian_filter(shadow, soft * 0.5)
        region *= (1.0 - scene.shadow * shadow)[..., None]
    near = rough < r + 2.0
    rows, cols = np.nonzero(near)
    p = np.column_stack([cols + c0, rows + r0]).astype(float)  # pixel centres at whole px
    dist, idx = cKDTree(dense).query(p)
    t = tangent[idx]
    v = p - dense[idx]
    along = np.einsum("ij,ij->i", v, t)
    lateral = v[:, 0] * -t[:, 1] + v[:, 1] * t[:, 0]
    s = arc[idx]
    # the radius along the wire: conductor or ferrule near a metal end
    radius = np.full(len(p), r)
    metal = np.zeros(len(p), bool)
    for end, kind, tip in ((0, look.ends[0], look.tip_mm[0]), (1, look.ends[1], look.tip_mm[1])):
        from_end = s if end == 0 else length - s
        if kind in METAL and tip > 0:
            zone = from_end < tip
            radius[zone] = r * (0.75 if kind == "ferrule" else 0.5)
            metal |= zone
    cover = np.clip(radius - dist + 0.5, 0, 1)
    for end, kind in ((0, look.ends[0]), (1, look.ends[1])):
        at_end = idx == (0 if end == 0 else len(dense) - 1)
        out = -along if end == 0 else along  # px past the end face
        if kind == "rounded":  # a cap whose far point is the end itself
            e = dense[0 if end == 0 else -1]
            inward = tangent[0] if end == 0 else -tangent[-1]
            centre = e + inward * radius[:, None]
            from_face = (p - e) @ inward
            cap = np.clip(radius - np.linalg.norm(p - centre, axis=1) + 0.5, 0, 1)
            cover = np.where((from_face < radius) & (np.linalg.norm(p - e, axis=1) < 2 * radius + 1), np.minimum(cover, cap),
                             cover)
        else:  # cut square
            cover = np.where(at_end, np.clip(0.5 - out, 0, 1) * np.clip(radius - np.abs(lateral) + 0.5, 0, 1), cover)
    if look.insulation == "translucent":
        alpha = np.where(metal, 1.0, 0.55)
        core = ~metal & (np.abs(lateral) < 0.3 * r)
        alpha = np.where(core, 1.0, alpha)
    else:
        alpha = np.ones(len(p))
        core = np.zeros(len(p), bool)
    colour = np.broadcast_to(np.array(look.colour, np.float32), (len(p), 3)).copy()
    if look.insulation == "striped":
        phase = (s * ppm / max(3.0 * r, 2.0) + lateral / max(2 * r, 1e-6)) % 1.0
        colour[phase < 0.45] = STRIPE
    colour[core] = METAL["copper"]
    for end, kind, tip in ((0, look.ends[0], look.tip_mm[0]), (1, look.ends[1], look.tip_mm[1])):
        if kind in METAL and tip > 0:
            zone = (s if end == 0 else length - s) < tip
            colour[zone] = METAL[kind]
    # shading of a round wire lit from light_dir
    x = np.clip(lateral / np.maximum(radius, 1e-6), -1.0, 1.0)
    nz = np.sqrt(1.0 - x * x)
    side = lx * -t[:, 1] + ly * t[:, 0]  # the lamp's direction across the wire
    diffuse = np.clip(x * side + nz * lz, 0.0, 1.0)
    gloss = np.where(metal, 0.8, look.gloss)
    spec = gloss * np.exp(-((x - side / (1.0 + lz)) / 0.2) ** 2)
    shade = colour * (0.45 + 0.55 * diffuse)[:, None] + spec[:, None]
    a = (cover * alpha)[:, None]
    region[rows, cols] = region[rows, cols] * (1 - a) + np.clip(shade, 0, 1) * a


def _jpeg(img: np.ndarray, quality: int) -> np.ndarray:
    from PIL import Image

    data = np.clip(img * 255.0 + 0.5, 0, 255).astype(np.uint8)
    buf = io.BytesIO()
    Image.fromarray(data).save(buf, format="JPEG", quality=quality)
    buf.seek(0)
    with Image.open(buf) as im:
        return np.asarray(im, np.float32) / 255.0
