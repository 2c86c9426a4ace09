"""The default wire finder: wire centre lines as ridges; every end classified; unsure means no.

The paper's systems threshold grey levels or follow grey-level edges, so they
need wires of one polarity on a plain board. This finder asks of every pixel
how far its colour is from the board's, so a red wire on a green mat, a white
wire beside a black one and a copper tip all stand out alike; it finds centre
lines as ridges of that contrast at the scales wires have, and it takes an end
only when what lies around it can be seen to be bare board.

1. The working image: averaged to 2-3 px/mm (k x k blocks, or 1.5 px wide ones at 3-4
   px/mm; below 3 px/mm the image as it is), colour kept; a tray's rim
   (or the bench round the tray) along a side of the frame found (find_rim): what
   lies beyond it is off the tray.
2. Contrast: the board's colour is estimated per BOARD_BLOCK_MM block (the median,
   then the median of each 3 x 3 blocks, so blocks full of wire are outvoted) and
   subtracted; a printed lattice (a cutting mat's grid) found in the spectrum and
   taken out (lattice.py); each channel is divided by its own robust spread (noise
   and board texture); the contrast F is the root mean square over the channels.
   Every board is also tried as printed in two tones (camouflage), and taken as two
   where nothing then stands out, where the two tones explain most of its spread, or
   where broad patches stand out as well as wires: each pixel's board is the tone
   under it.
3. Ridges: F smoothed at scales matched to wire diameters 0.8-3 mm; the Hessian's
   most negative eigenvalue, scale-normalised, is the ridge strength; each pixel
   keeps its best scale; non-maximum suppression across the ridge and hysteresis
   leave the centre lines (where that finds none, the suppression at each pixel's own
   scale: a wire whose contrast peaks at its flanks), thinned to one pixel.
4. The wire graph: ends (one neighbour) and crossings (three or more); spurs shorter
   than SPUR_MM are pruned; a trace jumps a break of up to GAP_MM to another line
   end facing it; only ends on lines long enough to hold SPAN_MM (across such breaks) are read.
5. Each end: traced inward for SPAN_MM (a crossing on the way: it touches another
   wire); the wire's width measured across it; the tip followed outward along the
   contrast past the ridge's end (a rounded cap, a ferrule, stripped copper) to
   where the board begins (a faint "conductor" that runs on past its own tip as a
   thin line is the board's print, and not followed, and so is one that reaches no further than
   an end's shadow with edges much softer than the insulation's: that shadow, to which a scan that
   ran on into it is taken back, and which the fan past the tip counts as board; the narrow stretch of a bright
   conductor the first scan took counts towards it, and its contrast is the
   conductor's; one that runs on into what looks like its end's shadow, the board's own colour
   darkened, no longer than the wire is thick, after metal of another colour, ends where that
   begins; one that runs on to the frame's border ends there, and one that runs on past the
   longest conductor is none; where the working image shows none and averages the input 1.5
   times or more, a thin one is sought in the input's own pixels, fine.py); an end at the frame border,
   or whose contrast runs on (under another wire) or fades but goes on past its tip,
   straight or bending up to 35 degrees (unless it fills the fan beyond the tip: a broad
   patch of print), or whose wire shows again in its own colour a few mm on, narrow, past
   something faint lying across its end (a wire of nearly the board's colour over it), or whose
   centre line turns more sharply than a wire bends (a trace run on past a junction
   onto another wire), is refused.
6. Free: the board must show beside the whole span, beyond the tip (out to 2.5 mm from its edge,
   unless the first 1.3 mm show bare board: what lies past that is another thing, clear of the
   end), and in a CLEARANCE_MM disc round the grasp point (room for the fingers); a faint band only
   next to the wire, along much of the span, is its own flank or shadow, a point beside it
   that falls on the wire itself (where its line hooks, at an end cut aslant) is the wire, and
   a speck of the board's texture (no more than SPECK_MM across, traced at half the threshold;
   on a board strewn with specks, SPECKLED a square cm or more, 3 mm traced at the threshold,
   as there specks run into each other at half of it) is no obstacle. An end refused
   for something beside it or in that disc is read again as one edge of a wire whose
   body does not stand out (a white wire on a white board: its two shaded sides), if
   another line runs beside it at a steady distance and the two end together; then as wide as
   all its contrast over the board (a round wire's shaded flank); then as a striped wire's (its
   width where its contrast, the most over 1 mm either way along it, stands above PEAK_SHARE of
   its peak: the dark stripes cover all of it there). The wire's own
   line in the fingers' room past the grasp point must keep the wire's colours (those 7-14 mm
   from its tip): another wire lying along that line is cleared from the disc as the wire itself.
7. The sighting: the tip; the direction into the wire at the tip, the chord of the
   centre line's TIP_FIT_MM nearest it (the tip put on that axis); the
   grasp point GRASP_MM along the centre line, centred across the wire; the tangent
   there. Of all free ends (ENOUGH), the one with the most room round it comes first:
   the least contrast, relative to the board's threshold, in bands 1-3 mm out beside
   its span, beyond its tip and round the grasp point (a nearby wire the free test
   just missed makes an end a worse bet); another centre line within LINE_NEAR_MM of
   the span's edge, however faint, makes it a worse bet too (LINE_WEIGHT); a tip found
   along a faint conductor, the less sure, counts a little less (CONDUCTOR_DOUBT).
8. Confirmed at two other scales: the image is read again at the next coarser and the next
   finer working scale (blocks one step wider and narrower; below 3 px/mm only the coarser),
   only the centre-line ends near the free ends being read (the rim the first reading found is
   taken, resampled, not sought again, and so is what it found the board printed with: no
   lattice or second tone is sought where it found none; what they check is how the wires and
   their ends were sampled, not where the tray is or what the board is); the best free end for which both
   readings find a free end too, its tip within CONFIRM_MM and its direction within
   CONFIRM_DEG, comes first. If no free end is so confirmed, the order of step 7 stands: it
   puts first an end that does not hang on how the image happened to be sampled (a thin
   conductor seen at one scale and not the next, a faint neighbour just over or under a
   threshold). But an end that a reading does not find free because it sees no room for the
   fingers at the grasp point there (the same end: its tip within CONFIRM_MM, its direction
   within CONFIRM_DEG) is refused: a thing in the fingers' room is something seen, where a
   reading that finds no end there may only have sampled it less well (a thin wire or a
   conductor close by the grasp point, clear at the finer scale). A lone free end is asked too
   where something stands near it (it scores under LONE_BELOW); one with room round it is not,
   as the two readings cost more than the rest of a look.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..common import Clock
from .contrast import contrast, working_image
from .graph import Graph
from .lines import centre_lines, ridges, thin_sparse
from .reader import MIDDLE_BOW, NO_ROOM, EndReader
from .rim import find_rim

__all__ = ["RidgeResult", "find_middle", "find_rim", "find_wires_ridge", "thin_sparse", "working_image"]

SATURATION = 12.0  # contrast (spreads) beyond which a wire is simply there: highlights count no more
LOOP_BOW = 0.8  # find_middle where no place bows as little as MIDDLE_BOW: a line bowing this much (a small loop)
ENOUGH = 0  # free ends to find before the search stops (0: all, which costs ~5 % more time); the roomiest is taken
CONFIRM_MM = 1.0  # a free end is confirmed where the image read at the next coarser and the next finer working
CONFIRM_DEG = 20.0  # scale has a free end too, its tip within CONFIRM_MM and its direction within CONFIRM_DEG
CONFIRM_NEAR_MM = 16.0  # ... (there only the centre-line ends this near a free end are read: a tip lies up to
# TIP_MAX_MM past its line's end)
LONE_BELOW = 0.7  # a lone free end is asked in step 8 too where it scores under this (something stands near it)


@dataclass
class RidgeResult:
    """What the ridge finder saw: candidates best-first, stage times, its centre lines and refusals."""

    candidates: list = field(default_factory=list)
    timings: dict = field(default_factory=dict)
    skeleton: np.ndarray | None = None  # the centre lines on the working grid
    scale: float = 1  # input pixels per working pixel (1.5 at 3-4 px/mm)
    rejected: list = field(default_factory=list)  # ((u, v) input px, why) for each refused end


def find_wires_ridge(image: np.ndarray, px_per_mm: float = 4.0, enough: int = ENOUGH,
                     confirm: bool = True) -> RidgeResult:
    """Graspable wire ends in an image (grey or colour) at px_per_mm, best first. confirm: the
    best free end that the image read at two other scales finds free too comes first (step 8)."""
    result, clock, began, graph, reader = _look(image, px_per_mm)
    ordered = graph.ends_in_order(reader.f)
    for end in graph.short:
        reader.refuse(graph.rc(int(end)), "its line meets another or stops within 20 mm")
    for end in ordered:
        s = reader.read(end)
        if s is not None:
            result.candidates.append(s)
            if enough and len(result.candidates) >= enough:
                break
    result.candidates.sort(key=lambda s: -s.score)
    clock("ends")
    if confirm and (len(result.candidates) >= 2 or result.candidates and result.candidates[0].score < LONE_BELOW):
        _confirm(image, px_per_mm, result, reader)
        clock("confirm")
    result.timings["total"] = (clock.last - began) * 1000.0
    return result


def _confirm(image: np.ndarray, px_per_mm: float, result: RidgeResult, first: EndReader) -> None:
    """Step 8: the free ends (best first) asked in turn whether the image read at the next
    coarser and the next finer working scale has a free end there too (CONFIRM_MM,
    CONFIRM_DEG); the first that both have is put first. One that a reading finds no room for
    the fingers at instead is refused. If none is confirmed, the order of the rest stands. The
    rim the first reading (first) found is taken, resampled, not sought again, and so are its
    findings about the board (a lattice, two tones: sought again only where it found them)."""
    from ...camera.images import ImageError

    others = []
    for k in _other_scales(result.scale):
        try:
            others.append(_Rereading(image, px_per_mm, k, first))
        except ImageError:  # the image is too small to read at that scale
            continue
    if not others:
        return
    cands = result.candidates
    tol = CONFIRM_MM * px_per_mm
    i = 0
    while i < len(cands):
        c = cands[i]
        found = [any(_agree(c, s, tol) for s in o.free_near(c)) for o in others]
        if all(found):
            cands.insert(0, cands.pop(i))
            return
        if any(not free and any(_agree(c, s, tol) for s in o.reader.no_room) for free, o in zip(found, others)):
            result.rejected.append((c.end, f"{NO_ROOM}, as read at another scale"))
            cands.pop(i)
            continue
        i += 1


def _other_scales(k: float) -> list[float]:
    """The working scales (input px per working px) next coarser and next finer than k."""
    coarser = {1: 1.5, 1.5: 2}.get(k, k + 1)
    finer = {1: None, 1.5: 1, 2: 1.5}.get(k, k - 1)
    return [s for s in (coarser, finer) if s is not None]


class _Rereading:
    """The image read again at working scale k, its centre-line ends read only where asked."""

    def __init__(self, image: np.ndarray, px_per_mm: float, k: float, first: EndReader | None = None) -> None:
        _, _, _, graph, self.reader = _look(image, px_per_mm, k, first)
        self.k = k
        self.ends = graph.ends_in_order(self.reader.f)
        self.at = graph.rcs(list(self.ends)) if self.ends else np.zeros((0, 2))
        self.near = CONFIRM_NEAR_MM * px_per_mm / k
        self.read: dict = {}  # end -> its Sighting or None

    def free_near(self, c) -> list:
        """The free ends whose centre line ends within CONFIRM_NEAR_MM of Sighting c's tip."""
        u, v = c.end
        tip = np.array([(v + 0.5) / self.k - 0.5, (u + 0.5) / self.k - 0.5])
        d2 = ((self.at - tip) ** 2).sum(axis=1)
        out = []
        for e in (e for e, d in zip(self.ends, d2) if d <= self.near * self.near):
            if e not in self.read:
                self.read[e] = self.reader.read(e)
            if self.read[e] is not None:
                out.append(self.read[e])
        return out


def _agree(a, b, tol: float) -> bool:
    """Whether two Sightings are the same end: tips within tol input px, directions within CONFIRM_DEG."""
    turn = abs((b.end_angle - a.end_angle + 180.0) % 360.0 - 180.0)
    return bool(np.hypot(b.end[0] - a.end[0], b.end[1] - a.end[1]) <= tol and turn <= CONFIRM_DEG)


def find_middle(image: np.ndarray, px_per_mm: float = 4.0) -> RidgeResult:
    """Places to take a wire by its middle, best first: for a wire none of whose ends is free
    (a loop that crosses itself near both ends, say), to lift it and let it fall in a new
    shape. Each Sighting's end and grasp are the same point on a centre line, MIDDLE_AWAY_MM
    from every crossing (so on top) and MIDDLE_END_MM along its line from every end of the
    centre lines (so it hangs from the fingers), with the CLEARANCE_MM disc round it free (room
    for the fingers); end_angle and grasp_angle are the line's direction there. The roomiest
    comes first. Where there is no such place, places bowing up to LOOP_BOW (a small loop's
    far side)."""
    result, clock, began, graph, reader = _look(image, px_per_mm)
    places = graph.middles()
    for bow in (MIDDLE_BOW, LOOP_BOW):
        result.candidates = [s for s in (reader.middle(p, bow) for p in places) if s is not None]
        if result.candidates:
            break
    result.candidates.sort(key=lambda s: -s.score)
    clock("middles")
    result.timings["total"] = (clock.last - began) * 1000.0
    return result


def _look(image: np.ndarray, px_per_mm: float, k: float | None = None, first: EndReader | None = None):
    """The stages before ends are read: (result, clock, start time, the wire graph, its reader);
    k: the working scale, if not the usual; first: a reading of the image at another scale, whose
    rim is taken (resampled), not sought again, and whose findings about the board are taken
    (contrast's like)."""
    result = RidgeResult()
    clock = Clock(result.timings)
    began = clock.last
    work, k = working_image(image, px_per_mm, k)
    wppm = px_per_mm / k
    result.scale = k
    clock("average")
    if first is not None and first.outside is not None:
        outside = _resampled(first.outside, first.k, k, work.shape[:2])
    else:
        outside = find_rim(work, wppm)
    clock("rim")
    con = contrast(work, wppm, outside, k, first.con if first is not None else None)
    clock("contrast")
    flat = SATURATION * np.tanh(con.f * (1.0 / SATURATION))  # a wire's body, not its highlight, makes the ridge
    strength, smoothed, which, each = ridges(flat, wppm)
    clock("ridges")
    skeleton = centre_lines(strength, smoothed, which, wppm, each)
    clock("centre lines")
    graph = Graph(skeleton, wppm)
    graph.prune_spurs()
    result.skeleton = graph.skeleton
    clock("graph")
    reader = EndReader(con, flat, each[0], graph, wppm, k, result, outside, image)
    if first is not None:
        reader._image = first._image  # (the input as float, if the first reading made it)
    return result, clock, began, graph, reader


def _resampled(mask: np.ndarray, k_from: float, k_to: float, shape: tuple[int, int]) -> np.ndarray:
    """A mask on the working grid of scale k_from (input px per working px) on that of k_to:
    each pixel takes the value of the one whose area holds its centre."""
    rows = np.clip(np.floor((np.arange(shape[0]) + 0.5) * k_to / k_from).astype(int), 0, mask.shape[0] - 1)
    cols = np.clip(np.floor((np.arange(shape[1]) + 0.5) * k_to / k_from).astype(int), 0, mask.shape[1] - 1)
    return mask[rows[:, None], cols[None, :]]
