"""What `rcl run` tells about a run: a summary line, the --report JSON, the --pictures PNGs
(one per look, with its outcome) and what the --page is made of (rcl.runpage): the looks,
the lines the program wrote, and the tray and the gripper as they were after each change."""
from __future__ import annotations

import copy
import json
import statistics
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any


@dataclass
class Look:
    number: int  # the camera's grab count at this look
    image: Any
    result: Any
    ms: float
    time_s: float = 0.0  # the arm's clock at the look


@dataclass
class Line:
    """A line the program wrote (WRITE, WRITELN): when, and how many looks it had made by then."""

    text: str
    time_s: float
    looks: int


@dataclass
class TrayState:
    """The wires on the tray from time_s on: number -> a copy of its rcl.vision.synth.Wire (tray
    mm). The cell moves a wire by giving it a new centre-line array, never by writing into one,
    so the copies share the arrays that did not change."""

    time_s: float
    wires: dict[int, Any]


@dataclass
class HeldState:
    """What the fingers held from time_s on: a wire's number and its centre line in the tool's
    frame (4 x N, homogeneous), or None."""

    time_s: float
    wire: int | None
    shape: Any = None


class RunWatcher:
    """Watches a session's looks, its output and, on a simulated cell, the cell's events, and
    reports when the run is over. Make it before the run:

        watcher = RunWatcher(session)
        session.run_file("crimp.rcl")
        watcher.finish(report_path=None, pictures=None, page="out")   # or rcl.runpage.write_page

    keep_images: keep each look's image and result (for pictures, frames and the page);
    keep_last: keep the images of only so many of the latest looks (a long REPL session)."""

    def __init__(self, session, keep_images: bool = True, keep_last: int | None = None) -> None:
        self.cell = cell = session.sim_cell
        self.session = session
        self.arm = getattr(session.robot, "inner", session.robot)  # the SimRobot behind a cell's arm
        self.looks: list[Look] = []
        self.lines: list[Line] = []
        self.trays: list[TrayState] = []
        self.held: list[HeldState] = []
        self.keep_images = keep_images
        self.keep_last = keep_last
        session.on_look = self._look
        session.out = _Tee(session.out, self._wrote)
        self._changes = -1
        self._order: dict[str, list[int]] = {"look": [], "event": [], "line": []}  # when each was recorded
        if cell is not None:
            cell.on_event = self._event
            self._tray_now()
            self.held.append(HeldState(self.clock, None))

    @property
    def clock(self) -> float:
        """The arm's clock (simulated seconds; 0 for an arm without one)."""
        return float(getattr(self.arm, "clock", 0.0))

    def _look(self, image, result, ms: float) -> None:
        keep = self.keep_images
        number = self.cell.camera.grabs if self.cell is not None else len(self.looks) + 1
        self.looks.append(Look(number, image if keep else None, result if keep else None, ms, self.clock))
        if self.keep_last is not None and len(self.looks) > self.keep_last:
            self.looks[-self.keep_last - 1].image = None
        self._recorded("look")
        if self.cell is not None:
            self._tray_now()

    def _wrote(self, line: str) -> None:
        self.lines.append(Line(line, self.clock, len(self.looks)))
        self._recorded("line")

    def _event(self, event) -> None:
        self._recorded("event")
        self._tray_now()
        held = self.cell.held  # a wire taken anew is a new Held with a shape of its own
        if (held.shape if held else None) is not self.held[-1].shape:
            self.held.append(HeldState(event.time_s, held.wire if held else None, held.shape if held else None))

    def _recorded(self, kind: str) -> None:
        self._order[kind].append(sum(len(v) for v in self._order.values()))

    def seq_of(self, kind: str, index: int) -> int:
        """The order in which the index-th look, event (of the cell's) or line was recorded: what
        happened at one time of the arm's clock is told in the order it happened."""
        order = self._order[kind]
        return order[index] if index < len(order) else -1

    def _tray_now(self) -> None:
        tray = self.cell.tray
        if tray.changes != self._changes:
            self._changes = tray.changes
            self.trays.append(TrayState(self.clock, {n: copy.copy(w) for n, w in tray.wires.items()}))

    def report(self) -> dict:
        r = self.cell.summary()
        r["sensing_ms"] = [round(k.ms, 3) for k in self.looks]
        r["looks"] = len(self.looks)
        r["camera_grabs"] = self.cell.camera.grabs  # the looks and the calibration's images
        for f in r["failures"]:  # numbered as the pictures: the look it followed (0: none yet)
            f["look"] = self.look_number(f["look"])
        return r

    def look_number(self, grab: int) -> int:
        """The number of the look (as the pictures number them) that the camera's grab-th image
        was, or the last one before it: calibration images are not looks."""
        return sum(1 for k in self.looks if k.number <= grab)

    def summary_line(self, r: dict) -> str | None:
        if not self.looks and not r["attempts"]:
            return None
        counts: dict[str, int] = {}
        for outcome in r["results"].values():
            counts[outcome] = counts.get(outcome, 0) + 1
        done = ", ".join(f"{n} {what}" for what, n in sorted(counts.items())) or "none done"
        vision = (f"; vision {statistics.median(r['sensing_ms']):.1f} ms median over {len(self.looks)} looks"
                  if self.looks else "")
        return (f"cell: {r['wires_total']} wires: {done}, {r['wires_left']} left on the tray; "
                f"{r['attempts']} picks tried, {len(r['failures'])} failures; "
                f"robot time {r['robot_time_s']:.1f} s{vision}")

    def finish(self, report_path: str | None, pictures: str | None, frames: str | None = None,
               page: str | None = None, meta: dict | None = None) -> tuple[str | None, list[str]]:
        """Write what was asked for: (the summary line, or None without a cell run; what could not
        be written, each as `rcl: error: ...`). The caller shows them. The report, pictures and
        frames are of a cell's run; a page is of any run (meta: what its heading names)."""
        r = self.report() if self.cell is not None else None
        problems = []
        if report_path and r is not None:
            try:
                Path(report_path).write_text(json.dumps(r, indent=2) + "\n")
            except OSError as e:
                problems.append(f"rcl: error: --report: cannot write {report_path}: {e.strerror or e}")
        for option, folder, write in (("--pictures", pictures, self.write_pictures),
                                       ("--frames", frames, self.write_frames)):
            if folder and r is not None:
                try:
                    write(Path(folder))
                except OSError as e:
                    problems.append(f"rcl: error: {option}: cannot write into {folder}: {e.strerror or e}")
        if page:
            from .runpage import PageError, write_page

            try:
                write_page(page, self, meta)
            except PageError as e:
                problems.append(f"rcl: error: --page: {e}")
            except OSError as e:
                problems.append(f"rcl: error: --page: cannot write into {page}: {e.strerror or e}")
        return (self.summary_line(r) if r is not None else None), problems

    def write_frames(self, folder: Path) -> None:
        """Each look's camera image as the finder got it, frame-NNN.png (NNN: the look's number, as
        on the pictures), 8 bits a channel: what `rcl vision` can be tried on."""
        folder.mkdir(parents=True, exist_ok=True)
        for i, look in enumerate(self.looks, start=1):
            frame_image(look).save(folder / f"frame-{i:03d}.png")

    def write_pictures(self, folder: Path) -> None:
        folder.mkdir(parents=True, exist_ok=True)
        for i, look in enumerate(self.looks, start=1):
            self.picture(i, look).save(folder / f"look-{i:03d}.png")

    def picture(self, i: int, look: Look):
        """The i-th look drawn: what vision saw and chose, captioned with what came of it (Pillow)."""
        from PIL import ImageDraw

        from .vision.overlay import draw

        picture = draw(look.image, look.result)
        pen = ImageDraw.Draw(picture)
        lines = [f"look {i}: " + (f"{len(look.result.candidates)} free ends seen"
                                  if look.result.candidates else "no free wire end seen")]
        if self.cell is not None:
            lines += [outcome_text(e) for e in self.cell.events if e.look == look.number]
        y = 4
        for text in lines:
            caption(pen, (4, y), text)
            y += 12
        return picture


def frame_image(look: Look):
    """A look's camera image as the finder got it, 8 bits a channel (Pillow)."""
    import numpy as np
    from PIL import Image

    a = np.asarray(look.image)
    if a.dtype != np.uint8:  # levels in [0, 1], as cameras here give them (16 bits: in [0, 65535])
        scale = 1.0 / 65535.0 if a.dtype == np.uint16 else 1.0
        a = np.round(np.clip(a.astype(float) * scale, 0.0, 1.0) * 255.0).astype(np.uint8)
    return Image.fromarray(a)


class _Tee:
    """A text stream that passes everything on to `inner` and tells `line` of each whole line.
    An inner that is sys.stdout is looked up at each write, as the session would have."""

    def __init__(self, inner, line) -> None:
        self._inner = None if inner is sys.stdout else inner
        self.line, self.pending = line, ""

    @property
    def inner(self):
        return self._inner if self._inner is not None else sys.stdout

    def write(self, text: str) -> int:
        self.inner.write(text)
        self.pending += text
        *done, self.pending = self.pending.split("\n")
        for whole in done:
            self.line(whole)
        return len(text)

    def flush(self) -> None:
        self.inner.flush()

    def __getattr__(self, name):  # isatty, encoding ...
        return getattr(self.inner, name)


def caption(pen, xy: tuple[int, int], text: str) -> None:
    """Yellow text with a dark shadow at xy. The default font's space is 2 px wide, which the
    shadow fills ('4 free endsseen'): words are set apart by 4 px."""
    x, y = xy
    for word in text.split(" "):
        pen.text((x + 1, y + 1), word, fill=(0, 0, 0))
        pen.text((x, y), word, fill=(255, 255, 0))
        x += int(pen.textlength(word)) + 4


def outcome_text(e) -> str:
    wire = f"wire {e.wire}" if e.wire is not None else ""
    if e.ok:
        return {"pick": f"{wire} taken", "press": f"{wire} crimped", "bath": f"{wire} tinned",
                "release": f"{wire} done", "shake": "tray shaken",
                "drop": f"{wire} dropped by its middle: it lies in a new shape",
                "putback": f"{wire} laid back on the tray"}.get(e.what, e.what)
    return f"{e.what} failed: {e.why}"
