"""Vision accuracy and speed on randomized trays. Run by hand:

    python benchmarks/vision.py [TRAYS] [--seed0 N] [--methods ridge,grey,binary] [--jobs 2]
                                [--save FILE] [--against FILE]

TRAYS (default 2000) trays from rcl.vision.scenes.random_tray at seeds seed0.. (default
300000: seeds no finder was tuned on and no change judged on, for reporting; judge changes on
seeds below 300000: 100000-101999 were used so for many commits and are a tuning set now,
200000-202999 were looked at in ede0e86's stop), each drawn from
everything the generator varies. Per method, overall and per slice (a tray falls in every
slice its draw matches, see scenes.tags), the first pick is:
- correct: its end within 1.5 mm of a graspable true end, its direction into the wire within
  20 degrees, its grasp point on that wire 11-19 mm from the end and its tangent within 15
  degrees; or no pick where nothing is graspable;
- foul: any other pick (a wrong end, or a right end picked wrongly);
- miss: no pick although the tray has a graspable end.
The fouls are also counted by cause (synth.Tray.foul_cause: an end that is not graspable, and
why; a pick short of the end along its wire or past it; at no wire end; a direction, grasp
point or tangent off), and every verdict by how near the ground truth's rules it lies
(synth.Tray.nearness: the least change, mm, of the tray or the pick that would turn it over: a
foul a hair's breadth over the rule, or a miss of an end with a hair's room, against a gross one);
of the fouls for another wire in the way, those where wires drawn over it hide nearly all of it
inside the rule's region (synth.Tray.unseen: a wire lying under the picked one, which no camera
sees) are counted too.
The same counts by what the slices do not say: the board's kind, the image's size, how many
wires, colour or grey (drawn_with).
Also the median end and angle errors of the correct picks, the median time per image and
per stage on 512 x 512 images (one core), the paper's slices for the binary system (dark or
bright wires of one polarity on a plain board: plain_dark, plain_bright) and, with --old, the
seven fixed kinds of synth.make_tray the paper's systems were first measured on.

To judge a change tray by tray (on seeds below 300000): --save FILE writes every tray's verdict,
foul cause, nearness and unseen share per method (JSON); run again after the change with --against FILE, and
it lists the trays whose verdict changed, and counts them, before the tables.
"""
from __future__ import annotations

import argparse
import bisect
import collections
import json
import time
from pathlib import Path

import numpy as np


def judge_one(job):
    seed, methods = job
    from rcl.vision import find_wires
    from rcl.vision.scenes import random_tray, tags

    tray = random_tray(seed)
    out = {"tags": sorted(tags(tray.scene)), "drawn": drawn_with(tray.scene), "size": tray.image.shape[:2],
           "graspable": any(e.graspable for e in tray.ends)}
    for m in methods:
        t = time.perf_counter()
        res = find_wires(tray.image, m, tray.px_per_mm)
        ms = (time.perf_counter() - t) * 1000.0
        pick = res.candidates[0] if res.candidates else None
        verdict, err, ang = tray.judge(pick)
        foul = verdict == "foul"
        out[m] = (verdict, err, ang, ms, dict(res.timings), tray.foul_cause(pick) if foul else "",
                  tray.nearness(pick), tray.unseen(pick) if foul else None)
    return out


def slice_job(job):
    seed, name, methods = job
    from rcl.vision import find_wires
    from rcl.vision.scenes import random_tray

    tray = random_tray(seed, name)
    out = {}
    for m in methods:
        res = find_wires(tray.image, m, tray.px_per_mm)
        out[m] = tray.judge(res.candidates[0] if res.candidates else None)[0]
    return out


WIRES = ("1-4", "5-9", "10-19", "20+")  # drawn_with's groups by how many wires a tray holds


def drawn_with(scene) -> list[str]:
    """What a tray was drawn with that the slices do not say, as groups to count verdicts in: its
    board, its image's size (pixels), how many wires, colour or grey."""
    px = scene.width * scene.height
    size = "small" if px < 250_000 else "large" if px >= 750_000 else "medium"
    wires = WIRES[bisect.bisect_right((5, 10, 20), scene.count)]
    return [f"board {scene.board}", f"{size} image", f"{wires} wires", "colour" if scene.colour else "grey"]


def row(label: str, verdicts: list, errs=None, angs=None, ms=None) -> str:
    n = len(verdicts)
    c = collections.Counter(verdicts)
    pc = lambda k: f"{100 * c[k] / n:5.1f}%"
    med = lambda a: f"{np.median(a):.2f}" if a else "-"
    extra = f" {med(errs or []):>8} {med(angs or []):>7}" if errs is not None else ""
    t = f" {np.median(ms):8.1f}" if ms else ""
    return f"  {label:<16} {n:>5} {pc('correct'):>8} {pc('foul'):>7} {pc('miss'):>7}{extra}{t}"


NEAR_MM = (0.25, 0.5, 1.0)  # near_table's bins


UNSEEN_SHARE = 0.9  # cause_table: a foul for a wire in the way that wires over it hide this much of (Tray.unseen)


def cause_table(results: list, m: str) -> None:
    """The fouls counted by cause (Tray.foul_cause), and of each how many lie within NEAR_MM[1] of
    the rule (Tray.nearness), how many are gross, and how many are for a wire in the way that
    wires drawn over it hide (UNSEEN_SHARE of it or more, Tray.unseen: no camera sees it)."""
    fouls = [r[m] for r in results if r[m][0] == "foul"]
    causes = collections.Counter(f[5] for f in fouls)
    if not causes:
        return
    print(f"  the fouls by cause (Tray.foul_cause), % of the {len(results)} trays; of each, how many lie within "
          f"{NEAR_MM[1]} mm of the rule, how many over {NEAR_MM[-1]} mm or in degrees, and how many for a wire in "
          f"the way {100 * UNSEEN_SHARE:.0f} % hidden under others:")
    for why, k in causes.most_common():
        mine = [f for f in fouls if f[5] == why]
        close = sum(f[6] is not None and f[6] <= NEAR_MM[1] for f in mine)
        gross = sum(f[6] is None or f[6] > NEAR_MM[-1] for f in mine)
        unseen = sum(f[7] is not None and f[7] >= UNSEEN_SHARE for f in mine)
        print(f"    {100 * k / len(results):5.2f}%  {k:>4}  ({close:>3} near, {gross:>3} gross, {unseen:>3} unseen)  {why}")


def near_table(results: list, m: str) -> None:
    """Each verdict counted by how near the ground truth's rules it lies (Tray.nearness: the least
    change, mm, of the tray or the pick that would turn it over): how many fouls and misses are a
    hair's breadth from the rule, how many gross."""
    heads = [f"<={NEAR_MM[0]}", *(f"{a}-{b}" for a, b in zip(NEAR_MM, NEAR_MM[1:])), f">{NEAR_MM[-1]}", "not mm"]
    print("  each verdict by how near the ground truth's rules it lies (the least change, mm, that turns it over):")
    print(f"    {'verdict':<8} " + " ".join(f"{h:>9}" for h in heads))
    for v in ("correct", "foul", "miss"):
        near = [r[m][6] for r in results if r[m][0] == v]
        counts = [0] * (len(NEAR_MM) + 2)  # (each bin holds its upper bound; the last: not in mm)
        for x in near:
            counts[-1 if x is None else bisect.bisect_left(NEAR_MM, x)] += 1
        print(f"    {v:<8} " + " ".join(f"{c:>9}" for c in counts))


def changed(before: dict, after: dict) -> list[tuple[str, int, str, str]]:
    """The trays whose verdict differs between two saved runs ({method: {seed: [verdict, cause, ...]}},
    seeds as strings, as JSON keeps them): (method, seed, what it was, what it is), a verdict
    followed by its foul cause where there is one; only methods and seeds both runs hold."""
    out = []
    for m in sorted(set(before) & set(after)):
        for seed in sorted(set(before[m]) & set(after[m]), key=int):
            was, now = before[m][seed], after[m][seed]
            if was[0] != now[0]:
                out.append((m, int(seed), " ".join(filter(None, was[:2])), " ".join(filter(None, now[:2]))))
    return out


def main() -> None:
    # benchmarks/machine.py, imported here as tests load some of these files as modules
    from machine import describe, interval, one_core_pool

    print(describe())
    ap = argparse.ArgumentParser()
    ap.add_argument("trays", nargs="?", type=int, default=2000)
    ap.add_argument("--seed0", type=int, default=300000)
    ap.add_argument("--methods", default="ridge,grey,binary")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--slice-trays", type=int, default=100, help="trays drawn within each named slice")
    ap.add_argument("--save", help="write every tray's verdict per method to this file (JSON)")
    ap.add_argument("--against", help="list the trays whose verdict differs from this saved run")
    args = ap.parse_args()
    methods = args.methods.split(",")
    from rcl.vision import load
    from rcl.vision.scenes import SLICES

    for m in methods:
        load(m)
    print(f"{args.trays} randomized trays, seeds {args.seed0}..{args.seed0 + args.trays - 1}; "
          f"{args.jobs} processes (times are per image, one core each)")
    jobs = [(args.seed0 + i, methods) for i in range(args.trays)]
    with one_core_pool(args.jobs) as pool:
        results = list(pool.map(judge_one, jobs, chunksize=8))
    print(f"  {sum(r['graspable'] for r in results)} trays have a graspable end")
    verdicts = {m: {str(seed): [r[m][0], r[m][5], r[m][6], r[m][7]] for (seed, _), r in zip(jobs, results)} for m in methods}
    if args.save:
        Path(args.save).write_text(json.dumps(verdicts))
    if args.against:
        diff = changed(json.loads(Path(args.against).read_text()), verdicts)
        for m in methods:
            mine = [d for d in diff if d[0] == m]
            better = sum(now == "correct" or (now == "miss" and was.startswith("foul")) for _, _, was, now in mine)
            print(f"  {m}: {len(mine)} trays changed against {args.against} ({better} for the better)")
            for _, seed, was, now in mine:
                print(f"    {seed}: {was} -> {now}")
    for m in methods:
        print(f"\n{m}: the first pick on every tray (end err mm and angle deg: medians of the correct picks)")
        print(f"  {'slice':<16} {'trays':>5} {'correct':>8} {'foul':>7} {'miss':>7} {'end err':>8} {'angle':>7} {'ms':>8}")
        groups: dict[str, list] = collections.defaultdict(list)
        for r in results:
            groups["all"].append(r)
            for t in r["tags"]:
                groups[t].append(r)
            groups["no graspable end" if not r["graspable"] else "a graspable end"].append(r)
        for name in ["all", "a graspable end", "no graspable end", *sorted(k for k in groups if k not in
                                                                         ("all", "a graspable end", "no graspable end"))]:
            rs = groups[name]
            if not rs:
                continue
            v = [r[m][0] for r in rs]
            errs = [r[m][1] for r in rs if r[m][0] == "correct" and r[m][1] is not None]
            angs = [r[m][2] for r in rs if r[m][0] == "correct" and r[m][2] is not None]
            print(row(name, v, errs, angs, [r[m][3] for r in rs]))
        print("  by what the tray is drawn with (small images: under 0.25 Mpx; large: 0.75 Mpx or more):")
        drawn: dict[str, list] = collections.defaultdict(list)
        for r in results:
            for g in r["drawn"]:
                drawn[g].append(r[m][0])
        order = [*(f"{k} image" for k in ("small", "medium", "large")), *(f"{k} wires" for k in WIRES), "colour", "grey"]
        for name in sorted(drawn, key=lambda g: (order.index(g) if g in order else -1, g)):
            print(row(name, drawn[name]))
        n_all = len(results)
        shares = collections.Counter(r[m][0] for r in results)
        print("  95 % intervals (Wilson) over all trays: " + ", ".join(
            f"{k} {100 * shares[k] / n_all:.1f} % ({100 * lo:.1f}-{100 * hi:.1f})"
            for k in ("correct", "foul", "miss") for lo, hi in [interval(shares[k], n_all)]))
        at512 = [r[m] for r in results if tuple(r["size"]) == (512, 512)]
        if at512:
            stages = collections.defaultdict(list)
            for _, _, _, _, timings, *_ in at512:
                for k, v in timings.items():
                    stages[k].append(v)
            print(f"  512 x 512 ({len(at512)} images), median ms per stage: "
                  + ", ".join(f"{k} {np.median(v):.2f}" for k, v in stages.items()))
        cause_table(results, m)
        near_table(results, m)
    if args.slice_trays <= 0:
        return
    print(f"\nwithin each named slice ({args.slice_trays} trays each, seeds {args.seed0}..):")
    print(f"  {'slice':<16} " + " ".join(f"{m + ' c/f/m %':>18}" for m in methods))
    sj = [(args.seed0 + i, name, methods) for name in SLICES for i in range(args.slice_trays)]
    with one_core_pool(args.jobs) as pool:
        sres = list(pool.map(slice_job, sj, chunksize=8))
    for name in SLICES:
        rs = [r for (_, n, _), r in zip(sj, sres) if n == name]
        cells = []
        for m in methods:
            c = collections.Counter(r[m] for r in rs)
            cells.append(f"{100 * c['correct'] / len(rs):5.0f}/{100 * c['foul'] / len(rs):3.0f}/"
                         f"{100 * c['miss'] / len(rs):3.0f}")
        print(f"  {name:<16} " + " ".join(f"{x:>18}" for x in cells))


if __name__ == "__main__":
    main()
