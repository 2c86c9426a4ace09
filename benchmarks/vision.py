"""Vision accuracy and speed on generated trays. Run by hand: python benchmarks/vision.py [TRAYS]

For each scene kind and method, on TRAYS seeded trays (default 100), the first pick is:
- correct: its end within 1.5 mm of a graspable true end, its direction into the wire within
  20 degrees, its grasp point on that wire 11-19 mm from the end and its tangent within 15 degrees;
- foul: any other pick (a wrong end, or a right end picked wrongly);
- miss: no pick although the tray has a graspable end (no pick on a tray without one is correct).
Also the median end and angle errors of the correct picks, the median time per image per stage,
and, when the bench extra is installed, scikit-image's and OpenCV's thinning on the same masks.
"""
from __future__ import annotations

import sys
import time

import numpy as np

from rcl.vision import find_wires, load
from rcl.vision.binary import thin
from rcl.vision.synth import KINDS, make_tray


def other_thinning(masks):
    rows = []
    try:
        from skimage.morphology import skeletonize
        t = time.perf_counter()
        for m in masks:
            skeletonize(m)
        rows.append(("scikit-image skeletonize", (time.perf_counter() - t) / len(masks) * 1000))
    except ImportError:
        rows.append(("scikit-image skeletonize", None))
    try:
        import cv2
        t = time.perf_counter()
        for m in masks:
            cv2.ximgproc.thinning(m.astype(np.uint8) * 255)
        rows.append(("OpenCV ximgproc.thinning", (time.perf_counter() - t) / len(masks) * 1000))
    except (ImportError, AttributeError):
        rows.append(("OpenCV ximgproc.thinning", None))
    return rows


def run_method(method: str, n: int, masks: list) -> dict:
    """Print one method's table; return its totals and stage times."""
    print(f"\n{method} system")
    print(f"{'kind':<15} {'correct':>8} {'foul':>6} {'miss':>6} {'end err':>8} {'angle':>7} {'ms/image':>9}")
    totals = {"correct": 0, "foul": 0, "miss": 0}
    stages: dict[str, list] = {}
    for kind in KINDS:
        counts = {"correct": 0, "foul": 0, "miss": 0}
        errs, angs, times = [], [], []
        for seed in range(n):
            tray = make_tray(kind, 1000 + seed)
            res = find_wires(tray.image, method, tray.px_per_mm)
            times.append(res.timings.get("total", 0.0))
            for k, v in res.timings.items():
                stages.setdefault(k, []).append(v)
            if getattr(res, "mask", None) is not None and len(masks) < 200:
                masks.append(res.mask)
            verdict, err, ang = tray.judge(res.candidates[0] if res.candidates else None)
            counts[verdict] += 1
            if verdict == "correct" and err is not None:
                errs.append(err)
                angs.append(ang)
        for k in totals:
            totals[k] += counts[k]
        med = lambda a: f"{np.median(a):.2f}" if a else "-"  # noqa: E731
        print(f"{kind:<15} {100 * counts['correct'] / n:7.0f}% {100 * counts['foul'] / n:5.0f}% "
              f"{100 * counts['miss'] / n:5.0f}% {med(errs):>8} {med(angs):>7} {np.median(times):9.1f}")
    all_n = n * len(KINDS)
    print(f"{'all':<15} {100 * totals['correct'] / all_n:7.1f}% {100 * totals['foul'] / all_n:5.1f}% "
          f"{100 * totals['miss'] / all_n:5.1f}% {'':>8} {'':>7} {np.median(stages['total']):9.1f}")
    return {"totals": totals, "stages": stages}


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 100
    for method in ("binary", "grey"):
        load(method)  # imports and tables before any clock starts
    print(f"{n} trays per kind, 512 x 512 px at 4 px/mm, one core; end err in mm and angle in degrees "
          "are medians over the correct picks; ms/image is the median")
    masks: list = []
    results = {m: run_method(m, n, masks) for m in ("binary", "grey")}
    print("\nmedian ms per stage (the paper's Table I, on a VAX, put a whole look at 2-6 s):")
    for method, r in results.items():
        print(f"  {method:<7}", ", ".join(f"{k} {np.median(v):.2f}" for k, v in r["stages"].items()))
    t = time.perf_counter()
    for m in masks:
        thin(m)
    ours = (time.perf_counter() - t) / len(masks) * 1000
    print(f"\nthinning the same {len(masks)} 128 x 128 masks: rcl (the paper's passes) {ours:.2f} ms", end="")
    for name, ms in other_thinning(masks):
        print(f"; {name} {'not installed' if ms is None else f'{ms:.2f} ms'}", end="")
    print()


if __name__ == "__main__":
    main()
