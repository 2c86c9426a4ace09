"""The run page of the main job: what writing it costs beyond the run, and how big it is.

    python benchmarks/page.py [SEED ...] [--screenshot FILE.png]   (default seed 0)

Per seed: the run's wall time without a page, the time write_page takes after it (the looks'
JPEGs, the arm drawn along its path, the data), and the folder's size in all and by part.
--screenshot: the first seed's page as headless Chromium draws it at 1400 x 1500 (docs/page.png
is made so), after a click on the first failure in its timeline (or the middle of the run).
"""
from __future__ import annotations

import io
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def one(seed: int, folder: Path) -> tuple[float, float, dict[str, int]]:
    from rcl import Session
    from rcl.runpage import write_page
    from rcl.runreport import RunWatcher
    from rcl.workcell import open_cell

    cell = open_cell(seed=seed)
    session = Session(out=io.StringIO(), cell=cell)
    watcher = RunWatcher(session)
    began = time.perf_counter()
    session.run_file(ROOT / "examples" / "crimp.rcl")
    run_s = time.perf_counter() - began
    began = time.perf_counter()
    write_page(folder, watcher, {"program": "examples/crimp.rcl", "cell": cell.config.name, "seed": seed})
    page_s = time.perf_counter() - began
    sizes = {"index.html": (folder / "index.html").stat().st_size,
             "plotly.min.js": (folder / "plotly.min.js").stat().st_size,
             "looks/": sum(p.stat().st_size for p in (folder / "looks").iterdir())}
    return run_s, page_s, sizes


def screenshot(index: Path, png: Path) -> None:
    sys.path.insert(0, str(ROOT / "tests"))
    from browser import Chromium

    with Chromium(1400, 1500) as b:
        b.open(index)
        b.wait_for("document.body && document.body.dataset.view")
        b.wait_for("Array.from(document.images).every(i => i.complete)")
        b.evaluate("(document.querySelector('#timeline li.fail') || document.querySelectorAll('#timeline li')"
                   "[Math.floor(document.querySelectorAll('#timeline li').length / 2)]).click()")
        b.pump(1.0)
        b.screenshot(png)
        if b.errors():
            print("the page reported:", *b.errors(), sep="\n  ")


def main(argv: list[str]) -> None:
    from machine import describe

    shot = None
    if "--screenshot" in argv:
        i = argv.index("--screenshot")
        shot = Path(argv[i + 1])
        argv = argv[:i] + argv[i + 2:]
    seeds = [int(a) for a in argv] or [0]
    print(describe())
    print(f"{'seed':>4} {'run s':>7} {'page s':>7} {'total MB':>9} {'index.html':>11} {'plotly.js':>10} {'looks/':>8}")
    for k, seed in enumerate(seeds):
        with tempfile.TemporaryDirectory() as tmp:
            folder = Path(tmp) / "page"
            run_s, page_s, sizes = one(seed, folder)
            total = sum(sizes.values())
            print(f"{seed:>4} {run_s:7.2f} {page_s:7.2f} {total / 1e6:9.2f} {sizes['index.html'] / 1e6:10.2f}M "
                  f"{sizes['plotly.min.js'] / 1e6:9.2f}M {sizes['looks/'] / 1e6:7.2f}M")
            if shot is not None and k == 0:
                screenshot(folder / "index.html", shot)
                print(f"wrote {shot}")


if __name__ == "__main__":
    main(sys.argv[1:])
