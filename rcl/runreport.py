"""What `rcl run` tells about a run on the simulated cell: a summary line, the
--report JSON and the --pictures PNGs (one per look, with its outcome)."""
from __future__ import annotations

import json
import statistics
from dataclasses import dataclass
from pathlib import Path
from typing import Any


@dataclass
class Look:
    number: int  # the camera's grab count at this look
    image: Any
    result: Any
    ms: float


class RunWatcher:
    """Watches a session's looks on a SimCell and reports when the run is over."""

    def __init__(self, cell, session, keep_images: bool = True) -> None:
        self.cell = cell
        self.looks: list[Look] = []
        self.keep_images = keep_images
        session.on_look = self._look

    def _look(self, image, result, ms: float) -> None:
        keep = self.keep_images
        self.looks.append(Look(self.cell.camera.grabs, image if keep else None, result if keep else None, ms))

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

    def finish(self, report_path: str | None, pictures: str | None,
               frames: str | None = None) -> tuple[str | None, list[str]]:
        """Write what was asked for: (the summary line, or None without a cell run; what could not
        be written, each as `rcl: error: ...`). The caller shows them."""
        r = self.report()
        problems = []
        if report_path:
            try:
                Path(report_path).write_text(json.dumps(r, indent=2) + "\n")
            except OSError as e:
                problems.append(f"rcl: error: --report: cannot write {report_path}: {e.strerror or e}")
        for option, folder, write in (("--pictures", pictures, self.write_pictures),
                                       ("--frames", frames, self.write_frames)):
            if folder:
                try:
                    write(Path(folder))
                except OSError as e:
                    problems.append(f"rcl: error: {option}: cannot write into {folder}: {e.strerror or e}")
        return self.summary_line(r), problems

    def write_frames(self, folder: Path) -> None:
        """Each look's camera image as the finder got it, frame-NNN.png (NNN: the look's number, as
        on the pictures), 8 bits a channel: what `rcl vision` can be tried on."""
        import numpy as np
        from PIL import Image

        folder.mkdir(parents=True, exist_ok=True)
        for i, look in enumerate(self.looks, start=1):
            pixels = np.clip(np.asarray(look.image, float), 0.0, 1.0) * 255.0
            Image.fromarray(np.round(pixels).astype(np.uint8)).save(folder / f"frame-{i:03d}.png")

    def write_pictures(self, folder: Path) -> None:
        from PIL import ImageDraw

        from .vision.overlay import draw

        folder.mkdir(parents=True, exist_ok=True)
        for i, look in enumerate(self.looks, start=1):
            picture = draw(look.image, look.result)
            pen = ImageDraw.Draw(picture)
            lines = [f"look {i}: " + (f"{len(look.result.candidates)} free ends seen"
                                      if look.result.candidates else "no free wire end seen")]
            lines += [_outcome(e) for e in self.cell.events if e.look == look.number]
            y = 4
            for text in lines:
                caption(pen, (4, y), text)
                y += 12
            picture.save(folder / f"look-{i:03d}.png")


def caption(pen, xy: tuple[int, int], text: str) -> None:
    """Yellow text with a dark shadow at xy. The default font's space is 2 px wide, which the
    shadow fills ('4 free endsseen'): words are set apart by 4 px."""
    x, y = xy
    for word in text.split(" "):
        pen.text((x + 1, y + 1), word, fill=(0, 0, 0))
        pen.text((x, y), word, fill=(255, 255, 0))
        x += int(pen.textlength(word)) + 4


def _outcome(e) -> str:
    wire = f"wire {e.wire}" if e.wire is not None else ""
    if e.ok:
        return {"pick": f"{wire} taken", "press": f"{wire} crimped", "bath": f"{wire} tinned",
                "release": f"{wire} done", "shake": "tray shaken",
                "drop": f"{wire} dropped by its middle: it lies in a new shape",
                "putback": f"{wire} laid back on the tray"}.get(e.what, e.what)
    return f"{e.what} failed: {e.why}"
