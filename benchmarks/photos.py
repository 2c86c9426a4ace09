"""First picks on public photographs of wires, judged against their labels. Run by hand:

    python benchmarks/photos.py PATH [--methods ridge,grey,binary] [--part held-out|tune|all]
                                [--diameter-mm 2.5] [--limit N] [--show DIR] [--failures]

PATH is a folder holding one or more of these public sets, fetched as docs/vision.md says
(none of their files is in this repository: no licence to redistribute, or GPL):

- ForNe-tech/CVF-DLO, DATASETS/BWH: photographs of wire harnesses on a green mat, a label
  image per wire route (routes of one harness share their trunk);
- StructuresComp/mBEST, dataset/S1-S3: single-colour wires on a black board, an instance
  label per wire (a wire passing under another is cut in two there);
- pablomalvido/cables_segmentation, real_images: cables in front of real workshop scenes,
  one binary mask per image (wires that touch are one region); and synthetic_images: 180 of
  its images rendered in Blender (another renderer than ours: cables on stone, wood, grass,
  concrete and fabric textures, or in front of workshop scenes, six kinds of 30), masks alike.

The labels become centre lines and wire ends: each instance is closed over 2 px (a ragged
edge thins to rings and prongs) and thinned, the thinning's whiskers (a branch that meets the
rest within a wire's width of its end: a bump on the label's edge, the prongs of a blunt end)
pruned, and every end left traced into the wire and carried out to the label's edge; an end
at the frame border, or one where the label stops against another wire (it runs under it),
is no wire end. A wire end is graspable by the same rules as the generated trays' ground
truth (synth.py): its first 20 mm inside the frame and clear of other wires by 0.5 mm, no
other wire (nor the same wire further on) within 4 mm of the grasp point 15 mm along it. The
photographs have no scale: px/mm is the labels' median wire width over --diameter-mm.

The first pick is judged as on the trays (Tray.judge): correct if it is a graspable end,
within 1.5 mm, the direction within 20 degrees, the grasp point on that wire 11-19 mm along
with the tangent within 15 degrees, or no pick where nothing is graspable; foul any other
pick; miss no pick where something was graspable. Every third image (by sorted name) is the
tuning part, the rest are held out; the table is printed for the chosen part, split into
images with a graspable end inside the frame and images without one. --failures lists, under
each table, every image whose first pick was not correct: method, verdict, the end's error (mm)
and direction error (degrees) where there was a pick, and for a foul its cause (Tray.foul_cause).
"""
from __future__ import annotations

import argparse
import collections
import sys
import time
from pathlib import Path

import numpy as np

from rcl.vision import find_wires, load
from rcl.vision.common import principal_direction
from rcl.vision.synth import FINGER_CLEARANCE_MM, GRASP_MM, TOUCH_MM, End, Tray, Wire

SPAN_MM = GRASP_MM + 5.0
BORDER_MM = 3.0



def sets(root: Path):
    """(set name, [(image path, loader of its instance masks)]) for each set found under root."""
    from PIL import Image

    def png_masks(paths):
        return lambda: [np.asarray(Image.open(p).convert("L")) > 0 for p in paths]

    for bwh in sorted(root.rglob("DATASETS/BWH")):
        items = []
        for img in sorted((bwh / "imgs").glob("*.jpg")):
            labels = sorted((bwh / "labels").glob(img.stem + "_*.png"))
            if labels:
                items.append((img, png_masks(labels)))
        yield "CVF-DLO BWH", items
    for base in sorted(root.rglob("dataset/S1")):
        for s in ("S1", "S2", "S3"):
            d = base.parent / s
            items = []
            for img in sorted((d / "images").glob("*.jpg")):
                npy = d / "gt_labels" / (img.stem + ".npy")
                if npy.exists():
                    items.append((img, _instances(npy)))
            yield f"mBEST {s}", items
    for real in sorted(root.rglob("real_images")):
        if not (real / "masks").is_dir():
            continue
        items = []
        for img in sorted((real / "images").glob("*.jp*g")):
            m = real / "masks" / img.name
            if m.exists():
                items.append((img, _components(m)))
        yield "cables_segmentation real", items
    for synth in sorted(root.rglob("synthetic_images")):
        items = []
        for kind in sorted(d for d in synth.iterdir() if (d / "masks").is_dir()):
            for img in sorted((kind / "images").glob("*.png")):
                m = kind / "masks" / img.name
                if m.exists():
                    items.append((img, _components(m)))
        yield "cables_segmentation synthetic", items


def _instances(npy: Path):
    def load_():
        lab = np.load(npy)
        return [lab == k for k in np.unique(lab) if k != 0]
    return load_


def _components(path: Path):
    def load_():
        from PIL import Image
        from scipy import ndimage

        m = np.asarray(Image.open(path).convert("L")) > 127  # the masks are JPEG: threshold them
        m = ndimage.binary_opening(m, np.ones((3, 3)))
        lab, n = ndimage.label(m, np.ones((3, 3)))
        sizes = ndimage.sum_labels(m, lab, np.arange(1, n + 1))
        return [lab == k + 1 for k in range(n) if sizes[k] >= 200]
    return load_


def median_width(masks) -> float:
    from scipy import ndimage

    from rcl.vision.binary import thin

    widths = []
    for m in masks:
        sk = thin(m)
        if sk.any():
            widths.append(2.0 * np.median(ndimage.distance_transform_edt(m)[sk]))
    return float(np.median(widths)) if widths else 8.0


class Truth:
    """Wire ends and graspability from instance masks (pixels), at ppm px/mm."""

    def __init__(self, masks: list[np.ndarray], ppm: float) -> None:
        from scipy import ndimage

        self.ppm = ppm
        self.h, self.w = masks[0].shape
        self.masks = masks
        self.union = np.zeros_like(masks[0])
        for m in masks:
            self.union |= m
        self.edt = ndimage.distance_transform_edt(self.union)

    def tray(self, image: np.ndarray) -> Tray:
        wires, ends = [], []
        for k, m in enumerate(self.masks):
            for path, why_not_end in self._ends(k, m):
                if why_not_end:
                    continue
                p0 = path[0]
                if any(np.linalg.norm(e.point * self.ppm - p0[::-1]) < 3.0 for e in ends):
                    continue  # routes of a harness share ends
                ok, why = self._graspable(k, path)
                width = 2.0 * float(np.median(self.edt[tuple(np.round(path[: max(len(path) // 2, 1)]).astype(int).T)]))
                wire = Wire(path[:, ::-1] / self.ppm, max(width, 1.0) / self.ppm, 0, (0.0,))
                wires.append(wire)
                d = _inward(path, 5.0 * self.ppm)[::-1]  # (x, y): the labels' rounded ends need a baseline
                ends.append(End(len(wires) - 1, 0, path[0][::-1] / self.ppm, d, ok, why))
        return Tray(image, self.ppm, wires, ends, kind="photo")

    def _ends(self, k: int, m: np.ndarray):
        """(path from the end inward, (row, col) px, the end carried out to the label's edge;
        why it is no wire end, or '') for each end of instance k's label, thinned once closed and
        without its whiskers."""
        from scipy import ndimage

        from rcl.vision.binary import thin

        spur = max(int(self.edt[thin(m)].max() if m.any() else 2), 3) * 2
        # a ragged label (pixels left out at its edge) thins to rings and prongs: it is closed
        # first, over 2 px (and no further: not out to the frame's edge)
        label, square = m, np.ones((3, 3), bool)
        m = ndimage.binary_closing(m, square, iterations=2, border_value=1) \
            & ndimage.binary_dilation(m, square, iterations=2)
        sk = thin(m)
        pad = _pruned(np.pad(sk, 1), spur)
        sk = pad[1:-1, 1:-1]
        count = ndimage.convolve(pad.astype(np.uint8), np.ones((3, 3), np.uint8), mode="constant") - 1
        ends = np.argwhere(pad & (count == 1)) - 1
        pixels = set(map(tuple, np.argwhere(sk).tolist()))
        for r, c in ends.tolist():
            path = _trace(pixels, (r, c), int((SPAN_MM + FINGER_CLEARANCE_MM + 12) * self.ppm))
            if len(path) < spur:
                continue  # a whisker of the thinning
            pts = np.array(path, float)
            d = -_inward(pts, 5.0 * self.ppm)
            tip = pts[0].copy()
            while True:  # out to the label's edge
                q = tip + d * 0.5
                qi = np.round(q).astype(int)
                if not (0 <= qi[0] < self.h and 0 <= qi[1] < self.w) or not m[qi[0], qi[1]]:
                    break
                tip = q
            full = np.vstack([tip, pts])
            border = BORDER_MM * self.ppm
            if tip[0] < border or tip[1] < border or tip[0] > self.h - 1 - border or tip[1] > self.w - 1 - border:
                yield full, ""  # a wire cut by the frame: an end nobody may pick, kept as a foul trap
                continue
            # beyond the edge: another wire's label right there means this one runs under it
            ahead = tip + d * np.arange(1.0, 4.0)[:, None]
            ai = np.round(ahead).astype(int)
            okq = (ai[:, 0] >= 0) & (ai[:, 0] < self.h) & (ai[:, 1] >= 0) & (ai[:, 1] < self.w)
            others = self.union & ~label
            if okq.any() and others[ai[okq, 0], ai[okq, 1]].any():
                yield full, "it runs under another wire"
                continue
            yield full, ""

    def _graspable(self, k: int, path: np.ndarray) -> tuple[bool, str]:
        from scipy import ndimage

        ppm = self.ppm
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(path, axis=0), axis=1))]) / ppm
        border = BORDER_MM * ppm
        if arc[-1] < SPAN_MM:
            return False, "less than 20 mm of it before a crossing or its other end"
        span = path[arc <= SPAN_MM]
        if (span[:, 0] < border).any() or (span[:, 1] < border).any() or (span[:, 0] > self.h - 1 - border).any() \
                or (span[:, 1] > self.w - 1 - border).any():
            return False, "off the image or cut by its border"
        width = 2.0 * float(np.median(self.edt[tuple(np.round(span).astype(int).T)]))
        own = np.zeros_like(self.union)
        near = path[arc <= SPAN_MM + FINGER_CLEARANCE_MM + 2 * width / ppm]
        idx = np.round(near).astype(int)
        own[idx[:, 0].clip(0, self.h - 1), idx[:, 1].clip(0, self.w - 1)] = True
        tube = ndimage.distance_transform_edt(~own) <= width / 2 + 0.75 * ppm
        rest = self.union & ~(tube & self.masks[k])  # everything but this wire near its end
        if not rest.any():
            return True, ""
        dist = ndimage.distance_transform_edt(~rest)
        si = np.round(span).astype(int)
        gap = dist[si[:, 0], si[:, 1]].min() / ppm - width / 2 / ppm
        if gap < TOUCH_MM:
            return False, "it crosses or touches another wire near its end"
        g = np.array([np.interp(GRASP_MM, arc, path[:, 0]), np.interp(GRASP_MM, arc, path[:, 1])])
        if dist[round(g[0]), round(g[1])] / ppm < FINGER_CLEARANCE_MM:
            return False, "no room for the fingers at the grasp point"
        return True, ""


def _pruned(sk: np.ndarray, spur: int) -> np.ndarray:
    """The thinning (padded by a pixel of False) without its whiskers: branches from an end
    that reach a fork in fewer than `spur` pixels (a bump on the label's edge; the two prongs a
    blunt end thins to, whose fork is then the end), pruned until none is left. An end within
    `spur` of the frame's edge stays: a wire cut there (frayed into prongs by the label) is not
    pruned into an end inside the frame."""
    from scipy import ndimage

    sk = sk.copy()
    kernel = np.ones((3, 3), np.uint8)
    h, w = sk.shape
    for _ in range(4):
        count = ndimage.convolve(sk.astype(np.uint8), kernel, mode="constant") - 1
        forks = sk & (count >= 3)
        cut = []
        for r, c in np.argwhere(sk & (count == 1)).tolist():
            if min(r, c, h - 1 - r, w - 1 - c) <= spur:
                continue  # at the frame's edge (the padding is one of these pixels)
            branch, (pr, pc) = [(r, c)], (r, c)
            while len(branch) < spur:
                nxt = [(pr + dr, pc + dc) for dr in (-1, 0, 1) for dc in (-1, 0, 1)
                       if (dr or dc) and sk[pr + dr, pc + dc] and (pr + dr, pc + dc) not in branch]
                if not nxt or any(forks[q] for q in nxt):
                    break
                pr, pc = nxt[0]
                branch.append((pr, pc))
            else:
                continue  # a branch as long as spur: a wire's end
            if nxt:  # (it stopped at a fork, not at a line's other end)
                cut += branch
        if not cut:
            return sk
        sk[tuple(np.array(cut).T)] = False
    return sk


def _inward(path: np.ndarray, reach: float) -> np.ndarray:
    """The unit direction (row, col) from a path's first point into it, fitted over `reach` px."""
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(path, axis=0), axis=1))])
    pts = path[arc <= reach]
    if len(pts) < 3:
        d = path[-1] - path[0]
    else:
        d = principal_direction(pts)
        if d @ (pts[-1] - pts[0]) < 0:
            d = -d
    return d / max(float(np.linalg.norm(d)), 1e-9)


def _trace(pixels: set, start, limit: int) -> list:
    path = [start]
    seen = {start}
    r, c = start
    for _ in range(limit):
        nxt = [(r + dr, c + dc) for dr in (-1, 0, 1) for dc in (-1, 0, 1)
               if (dr or dc) and (r + dr, c + dc) in pixels and (r + dr, c + dc) not in seen]
        if not nxt:
            break
        if len(nxt) > 1:
            edge = [p for p in nxt if abs(p[0] - r) + abs(p[1] - c) == 1]
            if len(nxt) == 2 and len(edge) == 1:
                nxt = edge
            else:
                break  # a crossing or a branch
        r, c = nxt[0]
        path.append((r, c))
        seen.add((r, c))
    return path


def main() -> None:
    # benchmarks/machine.py, imported here as tests load some of these files as modules
    from machine import describe, interval

    print(describe())
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("path", type=Path)
    ap.add_argument("--methods", default="ridge,grey,binary")
    ap.add_argument("--part", choices=("held-out", "tune", "all"), default="held-out")
    ap.add_argument("--diameter-mm", type=float, default=2.5)
    ap.add_argument("--limit", type=int, default=0)
    ap.add_argument("--show", type=Path, help="write an overlay per image (the first method) here")
    ap.add_argument("--failures", action="store_true", help="list every image whose first pick was not correct")
    args = ap.parse_args()
    from rcl.camera import read_image

    methods = args.methods.split(",")
    for m in methods:
        load(m)
    print(f"first picks on public photographs ({args.part} part); px/mm from a {args.diameter_mm} mm wire; "
          "judged as the generated trays are")
    found_any = False
    for name, items in sets(args.path):
        if not items:
            continue
        found_any = True
        chosen = [it for i, it in enumerate(items) if args.part == "all" or ((i % 3 == 0) == (args.part == "tune"))]
        if args.limit:
            chosen = chosen[:args.limit]
        counts = {m: collections.Counter() for m in methods}
        times = {m: [] for m in methods}
        ppms = []
        failures = []
        for path, masks_of in chosen:
            masks = masks_of()
            if not masks:
                continue
            image = read_image(path)  # (the right way up, as its labels were drawn)
            if masks[0].shape != image.shape[:2]:
                print(f"{path}: its labels are {masks[0].shape[1]} x {masks[0].shape[0]} px, the image "
                      f"{image.shape[1]} x {image.shape[0]}: left out", file=sys.stderr)
                continue
            ppm = median_width(masks) / args.diameter_mm
            ppms.append(ppm)
            tray = Truth(masks, ppm).tray(image)
            inside = "with a graspable end" if any(e.graspable for e in tray.ends) else "without one"
            for m in methods:
                t = time.perf_counter()
                res = find_wires(image, m, ppm)
                times[m].append((time.perf_counter() - t) * 1000)
                pick = res.candidates[0] if res.candidates else None
                verdict, err, ang = tray.judge(pick)
                counts[m][(inside, verdict)] += 1
                if verdict != "correct":
                    how = f"end {err:.1f} mm, direction {ang:.0f} deg off" if err is not None else "no pick"
                    if verdict == "foul":
                        how += f": {tray.foul_cause(pick)}"
                    failures.append(f"  {m:<7} {verdict:<5} {Path(path).name}: {how}")
                if args.show and m == methods[0]:
                    _show(args.show, name, path, image, res, tray, verdict)
        print(f"\n{name}: {len(ppms)} images, px/mm {np.median(ppms):.1f} median")
        print(f"  {'method':<7} {'images':<22} {'n':>4} {'correct':>8} {'foul':>6} {'miss':>6} {'ms':>6}"
              f"  {'correct, 95 % interval':>22}")
        for m in methods:
            for inside in ("with a graspable end", "without one"):
                c = counts[m]
                n = sum(v for (i, _), v in c.items() if i == inside)
                if not n:
                    continue
                pc = [f"{100 * c[(inside, v)] / n:.0f}%" for v in ("correct", "foul", "miss")]
                lo, hi = interval(c[(inside, "correct")], n)
                print(f"  {m:<7} {inside:<22} {n:>4} {pc[0]:>8} {pc[1]:>6} {pc[2]:>6} "
                      f"{np.median(times[m]):6.1f}  {f'{100 * lo:.0f}-{100 * hi:.0f}%':>22}")
        if args.failures and failures:
            print("  not correct:")
            print("\n".join(failures))
    if not found_any:
        print(f"no known set under {args.path} (see docs/vision.md)", file=sys.stderr)
        sys.exit(1)


def _show(folder: Path, name: str, path: Path, image, res, tray: Tray, verdict: str) -> None:
    from PIL import ImageDraw

    from rcl.vision.overlay import draw

    folder.mkdir(parents=True, exist_ok=True)
    pic = draw(image, res)
    pen = ImageDraw.Draw(pic)
    for e in tray.ends:
        u, v = e.point * tray.px_per_mm
        col = (0, 255, 0) if e.graspable else (255, 140, 0)
        pen.ellipse([u - 5, v - 5, u + 5, v + 5], outline=col, width=2)
    pen.text((4, 4), verdict, fill=(255, 255, 0))
    pic.save(folder / f"{name.replace(' ', '_')}_{path.stem}.png")


if __name__ == "__main__":
    main()
