"""The run page: `rcl run FILE --page DIR` writes DIR/index.html, one page that opens offline and
shows what the run did: the summary, a timeline of looks, picks, station visits, failures and
the program's own lines, each look's camera frame beside what vision made of it, and a 3D view
of the cell (tray and wires as they lay, camera, stations, the arm drawn from its
Denavit-Hartenberg model, its recorded path) with a slider through time.

The 3D view and the chart are plotly's (the optional extra: pip install 'rcl[page]'); its
script is copied beside the page, the pictures go into DIR/looks, and the run's data is
embedded in the page as JSON, which the page's own script (page.html) draws."""
from __future__ import annotations

import bisect
import json
import math
import re
import shutil
from collections import Counter
from collections.abc import Sequence
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from .runreport import RunWatcher, frame_image, outcome_text

PLOTLY_MISSING = "the run page needs plotly, which is not installed: pip install 'rcl[page]'"
SAMPLE_S = 0.2  # the arm is drawn this often along a motion (simulated seconds) ...
MOST_SAMPLES = 16  # ... and at most this many times in one motion
WIRE_STEP_MM = 2.0  # the wires' centre lines, as drawn
JPEG_QUALITY = 88


class PageError(Exception):
    """The page cannot be written; the message says why and what to do."""


def plotly_script() -> Path:
    """Where plotly's own script (plotly.min.js) lies, or PageError if plotly is not installed."""
    try:
        path = resources.files("plotly") / "package_data" / "plotly.min.js"
    except ModuleNotFoundError:
        raise PageError(PLOTLY_MISSING) from None
    if not path.is_file():
        raise PageError(f"{PLOTLY_MISSING} (this plotly has no package_data/plotly.min.js)")
    return Path(str(path))


def write_page(folder: str | Path, watcher: RunWatcher, meta: dict[str, Any] | None = None) -> Path:
    """Write the page of a watched run into folder (made if need be): index.html, plotly.min.js
    and looks/. meta: what the page's heading names (program, cell, seed; error: the message a
    run that failed stopped with, shown at the top and last on the timeline). Returns index.html's
    path; PageError if plotly is missing, OSError if the folder cannot be written."""
    script = plotly_script()
    folder = Path(folder)
    (folder / "looks").mkdir(parents=True, exist_ok=True)
    data = page_data(watcher, meta or {}, folder)
    shutil.copyfile(script, folder / "plotly.min.js")
    text = json.dumps(data, separators=(",", ":"), allow_nan=False).replace("</", "<\\/")
    html = (resources.files("rcl") / "page.html").read_text(encoding="utf-8")
    index = folder / "index.html"
    index.write_text(html.replace("{{DATA}}", text), encoding="utf-8")
    return index


def page_data(watcher: RunWatcher, meta: dict[str, Any], folder: Path | None) -> dict[str, Any]:
    """Everything the page shows, as JSON-ready values; the looks' pictures are written into
    folder/looks (None: not written)."""
    cell = watcher.cell if watcher.cell is not None and (watcher.looks or watcher.cell.events) else None
    arm = watcher.arm
    report = watcher.report() if cell is not None else None
    base, tool = _base_and_tool(cell)
    moments = [k.time_s for k in watcher.looks] + ([e.time_s for e in cell.events] if cell is not None else [])
    times, qs = _sample_joints(arm, moments)
    samples, hands = _samples(arm, times, qs, base, tool)
    looks = _looks(watcher, cell, folder)
    data: dict[str, Any] = {
        "meta": {k: v for k, v in meta.items() if v is not None},
        "model": getattr(getattr(arm, "model", None), "name", type(arm).__name__),
        "robot_time_s": round(watcher.clock, 3),
        "summary": _summary(watcher, report),
        "looks": looks,
        "timeline": _timeline(watcher, cell, looks),
        "samples": samples,
        "static": _static(watcher, cell, times, samples["tip"], base),
    }
    if meta.get("error"):  # the run stopped on it: the timeline ends with it
        data["timeline"].append({"t": round(watcher.clock, 3), "kind": "error", "ok": False,
                                 "look": len(watcher.looks), "text": str(meta["error"]).splitlines()[0]})
    if cell is not None:
        data["cell"] = cell.config.name
        data["wires"] = _wires(watcher, cell, times)
        data["held"] = _held(watcher, times, hands)
    return data


def _base_and_tool(cell) -> tuple[np.ndarray, np.ndarray]:
    """(world <- base, t5 <- tool): the cell's Z and E, or none for an arm alone."""
    if cell is None:
        return np.eye(4), np.eye(4)
    return cell.Z, cell.E


def _r(a) -> list:
    """Numbers (mm) rounded to 0.1, as a JSON list."""
    return np.round(np.asarray(a, float), 1).tolist()


def _samples(arm, times: list[float], qs: list[list[float]], base: np.ndarray,
             tool: np.ndarray) -> tuple[dict[str, list], list[np.ndarray]]:
    """The arm drawn along its recorded path: for each sample its time, its links' origins (base
    to flange, then the tool point) and a bar across the fingertips, in the world; and the
    tool's pose at each sample (world <- tool)."""
    from .robots.kinematics import frames

    xs, ys, zs, tips, hands = [], [], [], [], []
    for q in qs:
        links = [np.eye(4), *frames(arm.model, q)]
        hand = base @ links[-1] @ tool
        hands.append(hand)
        chain = np.array([(base @ f)[:3, 3] for f in links] + [hand[:3, 3]])
        bar = np.array([hand @ np.array([0.0, s * 6.0, 0.0, 1.0]) for s in (-1, 1)])[:, :3]
        xs.append([*_r(chain[:, 0]), None, *_r(bar[:, 0])])
        ys.append([*_r(chain[:, 1]), None, *_r(bar[:, 1])])
        zs.append([*_r(chain[:, 2]), None, *_r(bar[:, 2])])
        tips.append(_r(chain[-1]))
    return {"t": [round(v, 3) for v in times], "x": xs, "y": ys, "z": zs, "tip": tips}, hands


def _sample_joints(arm, moments: Sequence[float] = ()) -> tuple[list[float], list[list[float]]]:
    """(times, joint vectors) at which the arm is drawn: where it stood first, then every
    SAMPLE_S seconds (at most MOST_SAMPLES times) along each recorded motion, its end included,
    and at each of the moments (a look, an event: the arm stands still then), so that the page
    shows the tray and the fingers as they were at each.
    An arm that keeps no record of its path (a real one) is drawn once, at home unless it says
    where it is (q); one without a model is not drawn."""
    model = getattr(arm, "model", None)
    if model is None:
        return [], []
    motions = getattr(arm, "trajectory", [])
    times = [motions[0].start if motions else 0.0]
    qs = [list(motions[0].path[0]) if motions else list(getattr(arm, "q", model.home))]
    for m in motions:
        n = len(m.path)
        k = int(np.clip(round((m.end - m.start) / SAMPLE_S) + 1, 2, MOST_SAMPLES))
        for i in np.linspace(0, n - 1, k).round().astype(int)[1:]:
            qs.append(list(m.path[i]))
            times.append(m.start + (m.end - m.start) * i / max(n - 1, 1))
    for t in moments:  # each after the samples at or before it, where the arm stood then
        at = bisect.bisect_right(times, t)
        times.insert(at, t)
        qs.insert(at, qs[max(at - 1, 0)])
    return times, qs


def _looks(watcher: RunWatcher, cell, folder: Path | None) -> list[dict[str, Any]]:
    """Each look: its number, time, vision time, what was seen and what came of it, and its two
    pictures (the camera's frame and the overlay) written as JPEG into folder/looks."""
    out = []
    for i, look in enumerate(watcher.looks, start=1):
        entry: dict[str, Any] = {"n": i, "t": round(look.time_s, 3), "ms": round(look.ms, 2),
                                 "seen": 0, "outcomes": []}
        if cell is not None:
            entry["outcomes"] = [outcome_text(e) for e in cell.events if e.look == look.number]
        if look.result is not None:
            entry["seen"] = len(look.result.candidates)
        if folder is not None and look.image is not None:
            frame_image(look).convert("RGB").save(folder / "looks" / f"frame-{i:03d}.jpg", quality=JPEG_QUALITY)
            watcher.picture(i, look).save(folder / "looks" / f"look-{i:03d}.jpg", quality=JPEG_QUALITY)
            entry["frame"] = f"looks/frame-{i:03d}.jpg"
            entry["overlay"] = f"looks/look-{i:03d}.jpg"
        out.append(entry)
    return out


def _summary(watcher: RunWatcher, report: dict | None) -> dict[str, Any]:
    looks = [k.ms for k in watcher.looks]
    s: dict[str, Any] = {"looks": len(looks), "vision_ms": [round(v, 2) for v in looks],
                         "lines": len(watcher.lines),
                         "motions": len(getattr(watcher.arm, "trajectory", []))}
    if report is None:
        return s
    counts = Counter(report["results"].values())
    reasons = Counter(f"{f['what']}: " + re.sub(r"-?\d+(\.\d+)?", "N", f["why"] or "failed")
                      for f in report["failures"])
    s.update({"wires_total": report["wires_total"], "wires_left": report["wires_left"],
              "crimped": counts.get("crimped", 0), "tinned": counts.get("tinned", 0),
              "rejected": counts.get("rejected", 0), "lost": counts.get("lost", 0),
              "picks": report["attempts"], "failures": len(report["failures"]),
              "reasons": sorted(reasons.items(), key=lambda kv: (-kv[1], kv[0]))})
    return s


def _timeline(watcher: RunWatcher, cell, looks: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The run in order: looks, the cell's events, the program's lines (and, for an arm alone,
    its motions), each with its time and the look it followed."""
    items: list[tuple[float, int, dict[str, Any]]] = []
    for k, look in zip(looks, watcher.looks):
        text = (f"look {k['n']}: {k['seen']} free ends seen" if k["seen"] else f"look {k['n']}: no free wire end seen")
        items.append((look.time_s, watcher.seq_of("look", k["n"] - 1), {"kind": "look", "ok": k["seen"] > 0,
                                                                        "look": k["n"], "text": text}))
    if cell is not None:
        for j, e in enumerate(cell.events):
            items.append((e.time_s, watcher.seq_of("event", j),
                          {"kind": e.what, "ok": e.ok, "look": watcher.look_number(e.look), "wire": e.wire,
                           "text": outcome_text(e)}))
    for j, line in enumerate(watcher.lines):
        items.append((line.time_s, watcher.seq_of("line", j),
                      {"kind": "line", "ok": True, "look": line.looks, "text": line.text}))
    if cell is None:
        for m in getattr(watcher.arm, "trajectory", []):
            items.append((m.start, 1 << 30, {"kind": "motion", "ok": "halted" not in m.kind, "look": 0,
                                        "text": f"{m.kind.upper()}: {m.end - m.start:.2f} s"}))
    items.sort(key=lambda it: (it[0], it[1]))  # a motion begins after what was told at its start
    return [{"t": round(t, 3), **entry} for t, _, entry in items]


def _wires(watcher: RunWatcher, cell, times: list[float]) -> dict[str, Any]:
    """The wires on the tray in each recorded state (world mm, drawn WIRE_STEP_MM apart), each
    wire's colour and width, and for each sample the state it shows."""
    from .vision.synth import resample

    origin, z0 = cell.tray.origin, cell.tray_z
    states, colours, widths = [], {}, {}
    for state in watcher.trays:
        drawn = {}
        for n, w in state.wires.items():
            p = resample(np.asarray(w.centre, float), WIRE_STEP_MM)
            z = z0 + w.width / 2 + 0.3 * w.layer
            drawn[str(n)] = [_r(p[:, 0] + origin[0]), _r(p[:, 1] + origin[1]), _r(np.full(len(p), z))]
            colours[str(n)] = _colour(w.level)
            widths[str(n)] = round(float(w.width), 2)
        states.append({"t": round(state.time_s, 3), "wires": drawn})
    starts = [s.time_s for s in watcher.trays]
    at = [_state_at(starts, t) for t in times]
    numbers = sorted(colours, key=int)
    return {"numbers": numbers, "colour": colours, "width": widths, "states": states, "at": at}


def _held(watcher: RunWatcher, times: list[float], hands: list[np.ndarray]) -> list:
    """For each sample (its time, the tool's pose), the held wire in the world ([number, x, y,
    z]) or None."""
    starts = [h.time_s for h in watcher.held]
    out: list = []
    for t, pose in zip(times, hands):
        h = watcher.held[_state_at(starts, t)]
        if h.wire is None or h.shape is None:
            out.append(None)
            continue
        pts = (pose @ np.asarray(h.shape)[:, ::8])[:3]
        out.append([h.wire, _r(pts[0]), _r(pts[1]), _r(pts[2])])
    return out


def _static(watcher: RunWatcher, cell, times: list[float], tips: list, base: np.ndarray) -> dict[str, Any]:
    """What does not move: the tray, the camera, the stations, the arm's base, the whole path of
    the tool, and where each pick closed the fingers."""
    s: dict[str, Any] = {"base": _r(base[:3, 3])}
    if tips:
        s["path"] = [[p[i] for p in tips] for i in range(3)]
    if cell is None:
        return s
    x0, y0 = cell.tray.origin
    size, z = cell.tray.size, cell.tray_z
    s["tray"] = [_r([x0, x0 + size, x0 + size, x0, x0]), _r([y0, y0, y0 + size, y0 + size, y0]), _r([z] * 5)]
    cam = cell.lens.pose[:3, 3]
    corners = [(x0, y0), (x0 + size, y0), (x0 + size, y0 + size), (x0, y0 + size)]
    s["camera"] = {"at": _r(cam), "rays": [[_r([cam[0], cx]), _r([cam[1], cy]), _r([cam[2], z])] for cx, cy in corners]}
    stations = []
    for name, die, cfg in (("press", cell.press, cell.press_cfg), ("bath", cell.bath, cell.bath_cfg)):
        if die is None:
            continue
        if name == "bath":
            a = np.linspace(0, 2 * math.pi, 33)
            r = float(cfg["radius_mm"])
            ring = [die.target[0] + r * np.cos(a), die.target[1] + r * np.sin(a), np.full(len(a), die.target[2])]
            stations.append({"name": "solder bath", "at": _r(die.target), "line": [_r(v) for v in ring]})
        else:
            mouth = die.target - die.axis * 30.0
            line = [_r([mouth[i], die.target[i]]) for i in range(3)]
            stations.append({"name": "press (die)", "at": _r(die.target), "line": line})
    s["stations"] = stations
    picks: list[dict[str, Any]] = []
    for e in cell.events:
        if e.what != "pick" or not tips:
            continue
        if e.slip and picks:  # the wire taken slipped out on the way: that pick failed, where it was taken
            picks[-1].update(ok=False, text=outcome_text(e))
            continue
        i = _state_at(times, e.time_s)
        picks.append({"at": tips[i], "ok": e.ok, "text": outcome_text(e), "look": watcher.look_number(e.look)})
    s["picks"] = picks
    return s


def _state_at(starts: Sequence[float], t: float) -> int:
    """The index of the last of the (sorted) start times at or before t; 0 if none is."""
    return max(bisect.bisect_right(starts, t) - 1, 0)


def _colour(level) -> str:
    v = np.atleast_1d(np.asarray(level, float))
    rgb = np.clip(np.resize(v, 3) if v.size == 1 else v[:3], 0.0, 1.0) * 255
    return "rgb({},{},{})".format(*(int(round(c)) for c in rgb))

