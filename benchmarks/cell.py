"""The main job on the simulated cell: examples/crimp.rcl over seeded trays of 10-15 wires.

    python benchmarks/cell.py [TRAYS [FIRST_SEED [WAY ...]]]   (default 20 trays from seed 0,
                                                                every way; runs on both cores)

Each tray looks as the randomized tray generator draws it from the tray's seed
(the cell's `tray.look = "random"`), or, where a way says so, as its slice
plain_dark draws it (dark wires on a plain light board: what the paper's
systems were made for). Ways, each over the same seeds: the default wire finder
with the bicubic warp (the example as it is), the paper's grey-scale and binary
vision with the warp (GREYWIRE, BINWIRE for FINDWIRE), and the default finder with the linear 3x4 camera
model in place of the warp (fitted to the marker seen at two heights, by the
same arm), which shows why the paper needed the warp: the linear model
cannot follow the lens's distortion or the arm's inaccuracy; and the two models
again with fingers that must close within 0.5 mm of the centre line, not 1 mm.

Per way: wires crimped on their first pick and in all, picks per wire crimped,
vision ms per look (median, 90th percentile), simulated robot time per wire
(calibration included), and what the failures were.
"""
from __future__ import annotations

import collections
import io
import statistics
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
SCRIPT = (ROOT / "examples" / "crimp.rcl").read_text()
# (label, finder, camera model, tray look, finger tolerance mm)
WAYS = (
    ("default + warp", "FINDWIRE", "warp", "random", 1.0),
    ("default + warp, plain dark trays", "FINDWIRE", "warp", "plain_dark", 1.0),
    ("grey + warp, plain dark trays", "GREYWIRE", "warp", "plain_dark", 1.0),
    ("binary + warp, plain dark trays", "BINWIRE", "warp", "plain_dark", 1.0),
    ("grey + warp", "GREYWIRE", "warp", "random", 1.0),
    ("default + linear", "FINDWIRE", "linear", "random", 1.0),
    ("default + warp, 0.5 mm fingers", "FINDWIRE", "warp", "random", 0.5),
    ("default + linear, 0.5 mm fingers", "FINDWIRE", "linear", "random", 0.5),
)



def linear_model(cell):
    """The 3x4 camera fitted to the marker on the fingertips at a 6 x 6 grid at two heights."""
    from rcl.camera import LinearCamera, find_mark
    from rcl.frame import Frame

    sim = cell.sim
    xyz, uv = [], []
    sim.arm.close()
    for z in (0.0, 15.0):
        for x in np.linspace(294, 406, 6):
            for y in np.linspace(-56, 56, 6):
                tool = Frame.trans(x, y, z) * Frame.rotx(180)
                sim.arm.move((Frame(sim.Z).inv() * tool * Frame(sim.E).inv()).matrix)
                found = find_mark(sim.camera.grab())
                if found is not None:
                    xyz.append((x, y, z))
                    uv.append(found)
    sim.arm.open()
    sim.arm.home()
    model, _ = LinearCamera.fit(np.array(xyz), np.array(uv))
    sim.camera.grabs = 0
    return model


def run(job: tuple[tuple, int]) -> dict:
    from rcl import Session
    from rcl.cell import load_config
    from rcl.runreport import RunWatcher
    from rcl.workcell import open_cell

    (_, finder, model, look, fingers), seed = job
    config = load_config()
    config.data["gripper"]["tolerance_mm"] = fingers
    config.data["tray"]["look"] = look
    cell = open_cell(config, seed=seed)
    source = SCRIPT.replace("FINDWIRE(", f"{finder}(")
    session = Session(out=io.StringIO(), cell=cell, step_budget=5_000_000)
    if model == "linear":
        session.camera_model.model = linear_model(cell)
        source = source.replace("\nGETWARP\n", "\n")
    watcher = RunWatcher(session, keep_images=False)
    error = ""
    try:
        session.run(source, "crimp.rcl")
    except Exception as e:
        error = str(e).splitlines()[0]
    r = watcher.report()
    picks = collections.Counter(e.wire for e in cell.sim.events if e.what == "pick")
    r["pick_off_mm"] = [e.off_mm for e in cell.sim.events if e.what == "pick" and e.off_mm is not None]
    r["first_try"] = sum(1 for w, res in cell.sim.results.items() if res == "crimped" and picks[w] == 1)
    r["error"] = error
    return r


def main() -> None:
    # benchmarks/machine.py, imported here as tests load some of these files as modules
    from machine import describe, one_core_pool

    args = sys.argv[1:]
    names = [w[0] for w in WAYS]
    bad = [a for a in args[2:] if a not in names]
    if any(a in ("-h", "--help") for a in args) or bad or not all(a.isdigit() for a in args[:2]):
        if bad:
            print(f"unknown way {bad[0]!r}", file=sys.stderr)
        print(__doc__.split("\n\n")[1] + "\nWAY is one of:\n" + "\n".join(f"    {n!r}" for n in names),
              file=sys.stderr)
        sys.exit(0 if not bad and any(a in ("-h", "--help") for a in args) else 2)
    print(describe())
    trays = int(args[0]) if args else 20
    start = int(args[1]) if len(args) > 1 else 0
    ways = [w for w in WAYS if len(args) < 3 or w[0] in args[2:]]
    jobs = [(way, seed) for way in ways for seed in range(start, start + trays)]
    with one_core_pool(2) as pool:
        results = list(pool.map(run, jobs))
    print(f"examples/crimp.rcl on {trays} seeded trays of 10-15 wires (the built-in simulated cell), "
          f"seeds {start}-{start + trays - 1}\n")
    print("| way | wires | crimped first try | crimped in all | picks per crimped wire | "
          "fingers off the centre line, mm median (p90) | vision ms/look median (p90) | robot s per wire | "
          "runs ended by an error |")
    print("|---|---|---|---|---|---|---|---|---|")
    why_by_way = {}
    for way in ways:
        rs = [r for (w, _), r in zip(jobs, results) if w == way]
        total = sum(r["wires_total"] for r in rs)
        done = sum(r["wires_done"] for r in rs)
        first = sum(r["first_try"] for r in rs)
        attempts = sum(r["attempts"] for r in rs)
        ms = [m for r in rs for m in r["sensing_ms"]]
        robot = sum(r["robot_time_s"] for r in rs)
        errors = sum(1 for r in rs if r["error"])
        off = [m for r in rs for m in r["pick_off_mm"]]
        print(f"| {way[0]} | {total} | {100 * first / total:.1f} % | {100 * done / total:.1f} % | "
              f"{attempts / max(done, 1):.2f} | {_median_p90(off, '.2f')} | {_median_p90(ms, '.1f')} | "
              f"{robot / total:.1f} | {errors} |")
        why_by_way[way[0]] = collections.Counter(_kind(f) for r in rs for f in r["failures"]
                                              if f["what"] != "release")  # a release only repeats why
        why_by_way[way[0]].update(f"run ended: {r['error'][:60]}" for r in rs if r["error"])
        why_by_way[way[0]].update({"left on the tray": sum(r["wires_left"] for r in rs)})
    print()
    for way, counts in why_by_way.items():
        parts = ", ".join(f"{what} {n}" for what, n in counts.most_common() if n)
        print(f"{way}: {parts or 'no failures'}")


def _median_p90(values: list, fmt: str) -> str:
    """'median (p90)', or '-' when there is nothing to measure (no pick, no look)."""
    if not values:
        return "-"
    return f"{statistics.median(values):{fmt}} ({np.percentile(values, 90):{fmt}})"


def _kind(f: dict) -> str:
    """A failure's reason without its numbers: what kind of thing went wrong."""
    why = f["why"]
    for key in ("closed on nothing", "off square", "lies under", "no room", "off the die's axis",
                "off its axis", "into the die", "slipped", "let go", "above the tray"):
        if key in why:
            return f"{f['what']}: {key}"
    for key, what in (("pushed", "the end too deep"), ("only", "the end not deep enough")):
        if key in why:
            return f"{f['what']}: {what}"
    return f"{f['what']}: {why[:40]}"


if __name__ == "__main__":
    main()
