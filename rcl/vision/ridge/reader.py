"""Reading one end of a centre line: its tip, width, the room round it and the sighting.

EndReader is about 750 lines, over the ~300 we hold classes to: reading an end is one chain
of steps (step 5-7 of the finder, see the package's docstring) over the same samplers of the
contrast, the shadows and the rim, which the class holds for the image; split into several
classes, each step would take the same half-dozen arrays again. Each method is one step."""
from __future__ import annotations

import math
from collections.abc import Callable
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np

from ..common import FRAME_MARGIN_MM, GRASP_MM, bridged, median, principal_direction
from ..sighting import Sighting
from .contrast import Contrast, _corners, _mix, bilinear, light_and_tint, shadow_free, unit
from .fine import follow as follow_in_input
from .graph import SPAN_MM, Graph
from .rim import RIM_EDGE_MM

if TYPE_CHECKING:
    from . import RidgeResult

CLEARANCE_MM = 4.6  # free board round the grasp point, from the centre line: the fingers' room
SIDE_FREE_MM = 0.9  # free board beside the wire's edges along the span and beyond its tip
RIM_GAP_MM = 1.0  # ... and between them and a tray's rim (0.5 mm, and as much for where the rim is found)
KINK_DEG, KINK_MM, KINK_FROM_MM = 45.0, 2.5, 5.0  # a line turning more than this between chords this long,
# past this far from the tip, turns at a junction onto another wire (no wire bends so tightly; a
# striped wire's centre line weaves with its stripes, which over shorter chords looks as sharp)
FRAME_SLACK_MM = 0.5  # the span and this much more must lie FRAME_MARGIN_MM inside the frame (the ground truth's
# rule, and a little for the tip's error; SPAN_SLACK_MM here refused ends whose first 20 mm lie 3.5-4.4 mm inside)
SIGHT_MM = 4.2  # the fingers' room in sight: the frame this far from the grasp point at least (the 4 mm they
# need, and 0.2 mm for where the grasp point is put: what lies beyond the frame is no nearer than that)
SPAN_SLACK_MM = 2.0  # ... along the span and this much more: a wire crossing just past it touches it (tip and arc errors)
SHADOW_LIKE_WIRE = 0.2  # a wire this much of whose centre line looks like shadow: shadows are not told from it
SHADOW_SIDE = 0.3  # ... and one that casts one: so much of the board along one side of it looks like shadow
TIP_MAX_MM = 12.0  # the longest ferrule or stripped conductor followed past the insulation
FINE_BLUR = 4.0  # ... reaching this many times as far as the insulation's edges are soft (softness())
FINE_LAST_MM, FINE_OWN_MM = (0.5, 2.0), (5.0, 12.0)  # ... if the wire's last mm are of its colour further in
FINE_SCALE = 1.5  # where the working image averages the input this much or more (4 px/mm and up), a conductor
# it does not show is sought in the input's own pixels (fine.py)
CONDUCTOR_RIDGE = 1.5  # the finest scale's ridge strength that marks a thin conductor
CONDUCTOR_CONTRAST = 1.2  # a faint conductor: its axis this far (spreads) above the board beside it
CONDUCTOR_MIN_MM = 2.5  # ... at least this long (a shorter one is the blur or the shadow of the end)
SHADE_PAST_MM = 0.5  # a conductor that runs on this far (up to its width) into what looks like board in shadow ends where that
SHADE_IN_METAL = 0.2  # begins, if no more than this share of it before looks so (and it is CONDUCTOR_MIN_MM long),
SHADE_METAL_TINT = 1.0  # ... if the metal has another colour than the board's, this much (spreads; not in grey),
SHADE_TINT_SHARE = 0.5  # ... and the shade no more than this share of that other colour: the board's own, darkened
CONDUCTOR_WINDOW_MM = 1.0  # ... on average over this much of its length
CONDUCTOR_NARROW = 0.7  # ... and narrower than the wire: 0.45 of its width off the axis, less than this share of it
RUN_ON_MM = (0.5, 3.0)  # ... and past its tip, this stretch free of a thin line going on (line_goes_on):
RUN_ON_CONTRAST = 1.5  # ... its peak across the stretch this far (spreads) above the median there,
RUN_ON_WIDE_MM = 0.8  # ... and no wider than this
# the part of a conductor the tip's scan has followed already (bright, it stood out as the insulation does):
FLANK_SHARE = 0.5  # its flanks stand out less than this share of the insulation's (each as a share of the
FLANK_OTHER = (0.3, 0.8)  # middle's contrast), or less than [1] of it where its contrast is [0] off the insulation's;
FLANK_MIN = 0.3  # asked only where the insulation's stand out this share or more (else narrow is not told from wide)
CONDUCTOR_STEADY = 0.7  # ... and past that, to the tip, the conductor holds this share of its contrast there
SOFT_REACH_MM = 3.5  # ... and one that reaches no further past the insulation than an end's soft shadow or blur
SHADOW_STEP = 0.7  # the scan for the tip run on into the end's shadow: past a step down to this share of
# the wire's contrast, a stretch reaching 0.8 mm to SOFT_REACH_MM on with edges as soft as SOFT_EDGES says
SHADOW_FOOT = 0.3  # ... to where the contrast is this share of the step above the stretch's (a rounded cap's
# taper starts before its tip: half way down put such tips 0.23-0.47 mm short)
SHADOW_DIM = 1.25  # ... and past a tip so taken back, the fan counts that shadow's contrast (so much of it) as board
SOFT_EDGES = 1.3  # ... has edges no softer than this times the insulation's (softness()): else it is that shadow
BROAD_SHADOW = (1.5, 0.32, 0.75)  # a conductor no longer than [0] times the wire's width, whose contrast is no more than
# [1] of the insulation's and which is [2] as broad as it or more (breadth()), is the end's shadow: as wide as the wire
SHADE_SHARE = 0.6  # ... where so much of it looks like board in shadow (shade(): the board's colour, darkened)
CONDUCTOR_DOUBT = 0.96  # an end whose tip lies on such a conductor ranks as this much less roomy (its tip
# is the less sure: of the free ends read on trays 3000-5399, 8 % of such tips lay over 1.5 mm off, 2 % of others)
TIP_START_MM = 10.0  # the search for the tip starts this far in along the centre line: on the insulation
END_FIT_MM = 8.0  # the ridge's direction at its end, to search for the tip along: over this much of it
TIP_FIT_MM = (1.0, 5.0)  # the end's direction: the chord of the centre line this far from the tip (its first
# mm may hook; a longer chord leans with a wire curving near its end, and a parabola's slope at the tip, tried
# too, is the noisiest of the three)
BRIDGE_MM = 0.6  # across a wire, a break in its contrast narrower than this is no edge (a specular line)
TANGENT_MM = 2.5  # the tangent at the grasp point: over this much either side
BOARD_FLOOR = 4.0  # contrast (spreads) below which a pixel may be bare board, whatever the wire
TIP_SHARE = 0.5  # the tip: where the contrast falls below half the wire's (a blurred edge's middle; a shadow is fainter)
BOARD_SHARE = 0.3  # ... and below this share of the wire's own contrast
FADE_SHARE = 0.12  # past a tip, this share of the wire's contrast still means wire
FADE_FLOOR = 2.5  # ... and so does this much (spreads): bare board beyond an end is darker than that
BROAD_SHARE = 0.6  # ... unless it fills this share of the fan beyond the tip: a broad patch of the board's print
BEND_RAYS = 1  # ... in three neighbouring rays of the fan (17.5 degrees apart) centred up to this many rays off
# the axis: a wire fading into a darker patch of the board as it bends (CVF-DLO BWH b3_9, 28 degrees)
BARE_RINGS = 3  # where the fan's first so many rings past the tip (of 5, out to 1.4 SIDE_FREE_MM past the wire's
# edge) are bare board at the fading threshold, what lies further out is another thing: neither the wire going on
# nor something just beyond its end (another wire 3.25 mm or more past a 2 mm wire's tip, where 3.75 were asked)
RUN_MM = 0.6  # beside the span: contrast this long along the wire is something there
SPECK_MM = 2.0  # ... unless it is a speck of the board's texture: no larger than this across
SPECK_TRACE = 0.5  # ... where its contrast is this share of the threshold for a thing there
SPECKLED = 5.0  # a board strewn with specks: this many a square cm over BOARD_FLOOR, each no more than SPECK_MM
# across (specks_per_cm2(); other boards count 0-0.3 at the median, a cutting mat up to 4.5); there a speck is traced at
SPECKLED_SPECK = (1.0, 3.0)  # this share of the threshold and may be this large (mm): at half, specks run together
EDGE_SHARE = 0.5  # ... unless only in the band nearest the wire, fainter than this share of it
EDGE_SPREAD_MM = 5.0  # ... and spread along this much of the span at least (not one thing in one place)
CAP_HITS = 3  # beyond the tip and round the grasp point: so many samples with contrast are something
DISC_HITS = 4
ROOM_CLEAR = 1.25  # step 8 refuses an end that a reading at another scale sees no room at only where the most
# it sees in the fingers' room stands this far over the threshold (at the threshold: the board's grain, sampled anew)
CROSS_SHARE = 0.1  # beside a wire of strong contrast, something this share of it (CROSS_FLOOR spreads at
CROSS_FLOOR = 6.0  # least) across all three bands alike (CROSS_FLAT) over no more than CROSS_MM of the
CROSS_FLAT = 0.5  # span is a fainter thing touching it (a thin wire's end): the threshold beside it,
CROSS_MM = 4.0  # BOARD_SHARE of its contrast, is for its own glow and blur
HIDDEN_AHEAD_MM = (1.0, 3.0)  # straight past a tip, the image this far out
HIDDEN_SHARE = 0.2  # ... each point nearer the wire's own colour (1-4 mm in from the tip) than this share of
HIDDEN_MM = 1.5  # the board's beside it, this far out from its edges: the wire may go on, unseen on a patch of its colour
HIDDEN_SIDE = 0.2  # (asked only where the wire differs from the board beside it by this share of its contrast)
ROOM_BAND_MM = (1.0, 2.0, 3.0)  # the room round a free end: bands this far out from the wire's edges along the span
ROOM_CAP_MM = (1.5, 3.0)  # ... arcs this far beyond its tip
LINE_NEAR_MM = 3.0  # another centre line this near the span's edge makes an end a worse bet (ranking only)
LINE_WEIGHT = 0.5  # ... its score divided by up to 1 + this
ROOM_PERCENTILE = 95.0  # ... each band and the disc round the grasp point judged by its nearly-highest contrast
HOLLOW_MM = (0.8, 3.3)  # a wire whose body does not stand out (light on a board of its colour): its edges this far apart
HOLLOW_END_MM = 1.5  # ... and they end together, to this much
MIDDLE_THROUGH = 0.8  # a middle grasp: its line runs on this share of the way out of the disc round it, both ways
MIDDLE_BOW = 0.5  # ... bowing from its tangent there by no more than this share of that
STRIPE_ALONG_MM = 1.0  # an end refused for something beside it or in the fingers' room is read again as a
# striped wire's: its width where its contrast, the most over this much either way along the wire, stands above
# PEAK_SHARE of its peak, if EXTENT_GROW times the width or more (and as EXTENT_ says); its centre line centred on
STRIPE_CENTRE = 0.6  # the contrast the most over this share of that width either way along (or STRIPE_ALONG_MM)
PEAK_SHARE = 0.4  # the wire's width: where its contrast stands above this share of its peak (and the board)
EXTENT_MAX_MM = 3.3  # an end refused for something beside it or in the fingers' room is read again as a
# wire as wide as all its contrast over the board, if that is no wider than this (a 3 mm wire and its blur),
EXTENT_GROW = 1.15  # ... this much wider than the width read at PEAK_SHARE or more,
EXTENT_STEADY_MM = 0.6  # ... as wide to this much at each of the places it is measured,
OUTLIER_SPREAD = 1.5  # ... or to two thirds of that at all places but the narrowest (where a flank meets a board of its tone)
EXTENT_FLOOR = 0.5  # ... and where all its contrast over the threshold is not that steady (a flank that flickers
# over and under it), as wide as its contrast over this share of the threshold
EXTENT_OFF = 0.2  # ... and centred on the centre line to this share of it (a wire lit from one side, its
# dim flank over the board but under PEAK_SHARE of the lit one; a neighbour close beside it is off to one side)
REAPPEAR_MM = 10.0  # past a tip, the wire's colour again starting within this (something across the way first),
REAPPEAR_RUN_MM = 2.0  # ... for this long, on a ray
REAPPEAR_DEG = 20.0  # ... straight on or turned up to this
REAPPEAR_SHARE = 0.4  # ... nearer the wire's colour than this share of the board's beside the wire
REAPPEAR_SIDE_MM = 1.0  # ... and narrow: not so this far out from its edges on either side
REAPPEAR_ACROSS = 0.1  # ... where what lies between stands out of the board by this share of the wire's contrast
REAPPEAR_DIFFERS = 0.3  # asked only where the wire differs from the board beside it by this share of its contrast
EDGES_ON = 0.4  # past a tip, 1-4 mm out, the wire's two edges going on this strong (share of their own 1-4 mm in)
EDGES_HUE = 0.7  # ... and its middle nearer the wire's colour than this share of the board's beside it: it goes on
COLOUR_CHANGE = 0.55  # along the line 1 mm past the grasp point to the fingers' room's edge, a colour this far (a
# share of the wire's contrast) from every colour of the wire 7-14 mm from its tip, over COLOUR_RUN_MM: another
COLOUR_RUN_MM = 1.0  # wire lies along its line there (a black wire's end in line with a grey wire: tray 205574)
STRANGE_AT_GRASP = 0.5  # across the wire within GRASP_ALONG_MM of the grasp point, at half the places along or more,
GRASP_ALONG_MM = 3.0  # a colour this far (a share of the wire's contrast) from every colour the wire shows across it
OWN_NEAR_MM = (0.5, 9.5)  # this far from its tip (its insulation past the longest metal, and the metal): another wire
OWN_ACROSS = (-0.35, -0.2, 0.0, 0.2, 0.35)  # lies along it at the grasp point (samples at these shares of its width)
BESIDE = "another wire or something lies beside it"
STRANGE = "at the grasp point it has a colour it has nowhere near its end: another wire lies along it there"
NO_ROOM = "no room for the fingers at the grasp point"
UNSEEN = "past its end the image has the wire's own colour: it may go on unseen"
UNDER = "its wire shows again past something across its end: it runs under it"
TWO_EDGES_ON = "past its end its two edges go on, its colour between them: it may go on unseen"
FADES = "its contrast fades but goes on past its end"
BEYOND = "something lies just beyond its end"
# refusals for what lies just past the insulation's end, which a thin conductor there would be
PAST_TIP = (UNSEEN, UNDER, TWO_EDGES_ON, FADES, BEYOND)


class EndReader:
    """Reads one centre-line end: classify it, follow its tip, check it is free, make a Sighting."""

    def __init__(self, con: Contrast, flat: np.ndarray, fine: np.ndarray, graph: Graph, wppm: float, k: float,
                 result: RidgeResult, outside: np.ndarray | None = None, source: np.ndarray | None = None) -> None:
        self.con = con
        self.f = con.f  # the contrast
        self.g = graph
        self.wppm = wppm
        self.k = k
        self.result = result
        self.h, self.w = self.f.shape
        # what sample() may be asked for: F, its saturated form (what centres the line), the finest
        # scale's ridge strength
        self.layers = (con.f, flat, fine)
        self.shadows = False  # whether shadows round the wire being read are told from things (set by read)
        self.outside = outside  # what lies off the tray (find_rim), if known
        self.rim = None  # how far (working px) each pixel lies from a rim or bench the frame shows, if any
        self._speck: tuple[float, float] | None = None  # how specks are traced and how large (speck())
        self.source = source  # the input image, if given (fine_conductor reads it)
        self._image: np.ndarray | None = None  # ... as float (rows, cols, channels), once asked for
        self.no_room: list[Sighting] = []  # the ends refused for no room at the grasp point, ROOM_CLEAR over the
        # threshold there, as they were seen
        self.crowding = 0.0  # what the last end refused for no room has there, the most, over the threshold
        if outside is not None and outside.any():
            from scipy import ndimage

            self.rim = ndimage.distance_transform_edt(~outside).astype(np.float32)

    def off_tray(self, pts: np.ndarray, margin: float) -> np.ndarray:
        """Which points lie within margin (working px) of a rim or bench the frame shows."""
        if self.rim is None:
            return np.zeros(len(pts), bool)
        r = np.clip(np.round(pts[:, 0]).astype(int), 0, self.h - 1)
        c = np.clip(np.round(pts[:, 1]).astype(int), 0, self.w - 1)
        return self.rim[r, c] < margin

    def speck(self) -> tuple[float, float]:
        """How a speck of the board's texture is traced (a share of the threshold) and how large
        it may be (mm): SPECK_TRACE and SPECK_MM, or on a board strewn with specks (SPECKLED or
        more a square cm), where a speck's halo at half the threshold runs into its neighbours',
        SPECKLED_SPECK."""
        if self._speck is None:
            self._speck = SPECKLED_SPECK if specks_per_cm2(self.f, self.wppm, self.outside) >= SPECKLED \
                else (SPECK_TRACE, SPECK_MM)
        return self._speck

    def refuse(self, at, why: str) -> None:
        r, c = at
        self.result.rejected.append(((float((c + 0.5) * self.k - 0.5), float((r + 0.5) * self.k - 0.5)), why))

    F, FLAT, FINE = 0, 1, 2  # the layers sample() may be asked for

    def sample(self, pts: np.ndarray, of: int = F) -> np.ndarray:
        """One layer (F, FLAT or FINE) at the points."""
        return bilinear(self.layers[of], pts)

    def shade(self, pts: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(F, F with the board in shadow counted as board, which points look so) at the points."""
        at = _corners(self.h, self.w, pts)
        f = _mix(self.f, *at)
        free, shade = shadow_free(self.con, _mix(self.con.work, *at), _mix(self.con.board, *at), f)
        return f, free, shade

    def around(self, pts: np.ndarray) -> np.ndarray:
        """The contrast at points round the wire (not on it): shadows on the board count as board
        unless the wire being read looks like a shadow itself."""
        return self.shade(pts)[1] if self.shadows else self.sample(pts)

    def read(self, end: int):
        g, mm = self.g, self.wppm
        start = np.array(g.rc(end), float)
        path, how = g.trace(end, (SPAN_MM + CLEARANCE_MM + 4.0) * mm * 1.1)  # past the disc round the grasp
        line = g.rcs(path)
        if len(line) >= 5:  # the pixel staircase smoothed, so arc lengths along it are true lengths
            from scipy import ndimage

            line = ndimage.uniform_filter1d(line, 5, axis=0, mode="nearest")
        arc = _arc(line)
        if how == "crossing" and arc[-1] < SPAN_MM * mm:
            return self.refuse(start, f"it meets another line {arc[-1] / mm:.0f} mm from its end")
        if how == "end" and arc[-1] < SPAN_MM * mm:
            return self.refuse(start, f"the line is only {arc[-1] / mm:.0f} mm long")
        fit = line[arc <= END_FIT_MM * mm]
        inward = principal_direction(fit) if len(fit) >= 3 else line[-1] - line[0]
        inward = inward / max(float(np.linalg.norm(inward)), 1e-9)
        if inward @ (line[min(len(line) - 1, len(fit))] - line[0]) < 0:
            inward = -inward
        # the wire's contrast and width along its first SPAN_MM
        core = self.sample(line)
        level = float(median(core))
        board = max(BOARD_FLOOR, BOARD_SHARE * level)
        width = self.width(line, board)
        took = self.take(start, line, how, inward, level, board, width)
        if took in (BESIDE, NO_ROOM):
            # a light wire on a board of its own colour shows only its two edges: the line read may
            # be one of them, and what lies beside it the other
            other = self.other_edge(line, arc, width, board)
            if other is not None:
                shift, gap = other
                n = _normals(line)
                middle = line + shift * n
                again = self.take(start + shift * n[0], middle, how, inward, level, board,
                                  self.width(middle, board, gap), gap)
                if not isinstance(again, str):
                    return again
        if took in (BESIDE, NO_ROOM) and len(line) >= 8:
            # a round wire lit from one side: its dim flank stands above the board, but under
            # PEAK_SHARE of the lit one, and the width leaves it out; what was seen beside the wire
            # may be that flank. Read again as wide as all its contrast (the EXTENT_ constants). A
            # striped wire: where its light stripes are faint, the width leaves them out too. Read
            # again as wide as its contrast is over 2 mm along it (its centre line, which weaves
            # with the stripes, centred on such contrast too: the STRIPE_ constants). Each if that
            # is a wire's width, the same all along, and about the centre line. A round wire whose lit
            # flank comes to about the board's shade: that flank's contrast flickers over and under
            # the threshold, so all of it over the threshold is no steady width. There only, read
            # again as wide as its contrast over EXTENT_FLOOR of the threshold
            flickers = False
            for share, stripes, floor in ((0.0, False, board), (PEAK_SHARE, True, board),
                                          (0.0, False, EXTENT_FLOOR * board)):
                if floor < board and not flickers:
                    break
                wide, spread, off = self._across(line, floor, 0.0, share, stripes)
                if share == 0.0 and floor == board:
                    flickers = spread > EXTENT_STEADY_MM * mm
                if width * EXTENT_GROW < wide <= EXTENT_MAX_MM * mm and spread <= EXTENT_STEADY_MM * mm \
                        and abs(off) <= EXTENT_OFF * wide:
                    n = _normals(line)
                    again = self.take(start + off * n[0], line + off * n, how, inward, level, board, wide,
                                      stripes=stripes)
                    if not isinstance(again, str):
                        return again
        if isinstance(took, str):
            return self.refuse(start, took)
        return took

    def take(self, start, line, how, inward, level, board, width, gap=0.0, stripes=False):
        """The Sighting of the end of centre line `line` (working px, from its end inward), or why
        it is refused. gap: 0, or the distance between the two edges of a wire whose body does
        not stand out (line then runs between them, and width spans both). stripes: the wire is
        centred on its contrast the most over STRIPE_CENTRE of its width either way along it (a
        striped wire)."""
        mm = self.wppm
        arc = _arc(line)
        self.shadows = self.casts_shadow(line, width)
        self.shadow_past = None  # (how far past the tip, its contrast): the end's soft shadow, where seen
        # the tip: from inside the wire, follow the contrast outward along the centre line and on
        # past the ridge's end (which smoothing may carry beyond the wire) to where it drops
        out = -inward
        beyond = np.arange(TIP_MAX_MM * mm, 0.0, -0.5)
        ext = np.vstack([start + beyond[:, None] * out, line])
        es = np.concatenate([-beyond, arc])
        inside = es <= TIP_START_MM * mm
        scan = ext[inside][::-1]  # from TIP_START_MM in, outward
        scan_s = es[inside][::-1]
        side = np.array([-out[1], out[0]])
        if gap:
            tip_s = self.edges_end(scan, scan_s, side, gap)
        else:
            lateral = np.array([-0.25, 0.0, 0.25]) * width
            ray = scan[:, None, :] + lateral[None, :, None] * side
            along = self.around(ray.reshape(-1, 2)).reshape(len(scan), len(lateral)).max(axis=1)
            thin = self.sample(ray.reshape(-1, 2), self.FINE).reshape(len(scan), len(lateral)).max(axis=1)
            # the wire goes on while it stands out as the insulation does (shadows on the board do
            # not count), or as a thin conductor does: a faint but sharp ridge on the axis (a shadow
            # or a blur is faint and broad; tin or a ferrule may have the colour of a shadow)
            conductor = (along >= BOARD_FLOOR) & (thin >= CONDUCTOR_RIDGE)
            edge = max(BOARD_FLOOR, TIP_SHARE * level)
            tip_s = _drop(np.where(conductor & (along < edge), edge, along), scan_s, edge)
            if not isinstance(tip_s, str):
                tip_s = self.short_of_shadow(scan, scan_s, along, tip_s, out, width)
        if isinstance(tip_s, str):
            return tip_s
        insulation = np.array([np.interp(tip_s, es, ext[:, 0]), np.interp(tip_s, es, ext[:, 1])])
        tip = self.conductor(insulation, out, width, lambda: self.flanks(line, arc, width))
        on = (ext[es > tip_s + 0.5], how, inward, level, board, width, gap, stripes)
        if gap or np.any(tip != insulation):
            return self.from_tip(tip, insulation, *on)
        # none seen here; one too thin or faint for the working image is looked for in the
        # input's pixels, but only where it could matter: where the end is free without it, or
        # refused for what lies just past the insulation (which such a conductor would be)
        took = self.from_tip(insulation, insulation, *on)
        if isinstance(took, str) and took not in PAST_TIP:
            return took
        fine = self.fine_conductor(insulation, out, width, level)
        return took if np.all(fine == insulation) else self.from_tip(fine, insulation, *on)

    def from_tip(self, tip, insulation, rest, how, inward, level, board, width, gap, stripes):
        """take() from the tip on: the Sighting of the end whose tip is `tip` (insulation: where
        its insulation ends) and whose centre line goes on as `rest`, or why it is refused."""
        mm = self.wppm
        border = FRAME_MARGIN_MM * mm
        out = -inward
        r, c = tip
        if r < border or c < border or r > self.h - 1 - border or c > self.w - 1 - border:
            return "its end is at the frame's border"
        if self.off_tray(tip[None, :], width / 2 + RIM_GAP_MM * mm)[0]:
            return "its end is at the tray's rim"
        # the centre line from the tip, and the grasp point GRASP_MM along it
        full = _resample(np.vstack([tip[None, :], rest]), 1.0)
        if not gap:  # (between two edges the middle is known)
            full = self.recentred(full, width, max(STRIPE_ALONG_MM * mm, STRIPE_CENTRE * width) if stripes else 0.0)
        s = _arc(full)
        if how == "crossing" and s[-1] < SPAN_MM * mm:  # (read() measured from the ridge's end, which
            # smoothing may carry past the wire's; the span is measured from the tip)
            return f"it meets another line {s[-1] / mm:.0f} mm from its end"
        if s[-1] < SPAN_MM * mm * 0.98 and how != "far":
            return "too little wire past its end"
        turn = _sharpest_turn(full, s, mm)
        if turn is not None:  # no wire bends so: the trace ran on past a junction onto another
            # wire whose end abuts this one
            return f"its line turns sharply {turn / mm:.0f} mm from its end (a junction)"
        # what must be seen: the span (the ground truth's 20 mm, and the slack), and the fingers'
        # room round the grasp point; what the wire does beyond that does not matter
        seen = full[s <= (SPAN_MM + SPAN_SLACK_MM) * mm]
        framed = full[s <= (SPAN_MM + FRAME_SLACK_MM) * mm]
        grasp = np.array([np.interp(GRASP_MM * mm, s, full[:, 0]), np.interp(GRASP_MM * mm, s, full[:, 1])])
        room = CLEARANCE_MM * mm
        if np.any(framed < border) or np.any(framed[:, 0] > self.h - 1 - border) \
                or np.any(framed[:, 1] > self.w - 1 - border) \
                or min(grasp[0], grasp[1], self.h - 1 - grasp[0], self.w - 1 - grasp[1]) < SIGHT_MM * mm:
            return "the wire runs off the frame near its end"
        if self.off_tray(seen, width / 2 + RIM_GAP_MM * mm).any() or self.off_tray(grasp[None, :], room)[0]:
            return "the wire runs to the tray's rim near its end"
        head = full[(s >= TIP_FIT_MM[0] * mm) & (s <= TIP_FIT_MM[1] * mm)]
        if len(head) >= 3:  # the direction at the tip itself (a ridge may bend as it overshoots the end)
            inward, on_axis = tip_axis(head, full[0])
        else:
            on_axis = full[0]
        near = (s >= (GRASP_MM - TANGENT_MM) * mm) & (s <= (GRASP_MM + TANGENT_MM) * mm)
        tangent = principal_direction(full[near]) if near.sum() >= 3 else inward
        if not gap and self.hidden(on_axis, inward, width, level):
            return UNSEEN
        if not gap and self.reappears(on_axis, inward, width, level):
            return UNDER
        span = self.span(full, grasp, width)
        why = self.crowded(span, tip, out, width, board, level)
        if why:
            if why == NO_ROOM and self.crowding >= ROOM_CLEAR:  # (step 8 asks where a reading at
                # another scale saw no room)
                self.no_room.append(self.sighting(on_axis, inward, grasp, tangent, 0.0))
            return why
        if self.changes_colour(full, width, level):
            return "its line changes colour past the grasp point: another wire lies along it there"
        if self.strange_at_grasp(full, width, level):
            return STRANGE
        if not gap and self.edges_go_on(on_axis, inward, width):  # (asked last: the ends still free are few)
            return TWO_EDGES_ON
        clutter = self.clutter(span, tip, out, width, board)
        if not gap:
            grasp = self.centred(grasp, tangent, width)
        score = 1.0 / (1.0 + clutter)
        near = self.line_near(span, width)
        if near < LINE_NEAR_MM:
            score /= 1.0 + LINE_WEIGHT * (LINE_NEAR_MM - near) / LINE_NEAR_MM
        if np.any(tip != insulation):  # a tip found along a faint conductor is the less sure
            score *= CONDUCTOR_DOUBT
        return self.sighting(on_axis, inward, grasp, tangent, score)

    def changes_colour(self, full: np.ndarray, width: float, level: float) -> bool:
        """Whether the centre line `full` (from the tip), in the fingers' room past the grasp
        point (1 mm past it to CLEARANCE_MM), has a colour COLOUR_CHANGE of the wire's contrast
        from every colour it has 7-14 mm from the tip (where a ferrule or copper has ended, and a
        striped wire shows its stripes), over COLOUR_RUN_MM: something else lies along its line,
        which the disc round the grasp point clears as the wire itself. Each colour the median
        of three points across the middle of the wire (not its flanks or highlight)."""
        mm = self.wppm
        line = _resample(full, 0.25 * mm)
        s = _arc(line)
        pick = ((s >= (GRASP_MM - 8.0) * mm) & (s <= (GRASP_MM - 1.0) * mm)) | \
            ((s >= (GRASP_MM + 1.0) * mm) & (s <= (GRASP_MM + CLEARANCE_MM) * mm))
        line, s = line[pick], s[pick]
        if len(line) < 8:
            return False
        colours, seen = self._across_colours(line, np.array([-0.2, 0.0, 0.2]) * width)
        seen = seen.all(axis=1)
        colour = np.median(colours, axis=1)
        own = seen & (s < GRASP_MM * mm)
        past = seen & (s > GRASP_MM * mm)
        if np.count_nonzero(own) < 4 or not past.any():
            return False
        far = np.sqrt(((colour[past][:, None, :] - colour[own][None, :, :]) ** 2).sum(axis=2)).min(axis=1)
        return bool(np.count_nonzero(far > COLOUR_CHANGE * level) >= COLOUR_RUN_MM / 0.25)

    def strange_at_grasp(self, full: np.ndarray, width: float, level: float) -> bool:
        """Whether the wire whose centre line is `full` (from the tip) shows, across it near the
        grasp point, colours it shows nowhere near its end: at each place along it within
        GRASP_ALONG_MM of the grasp point, the farthest of the OWN_ACROSS samples across it from
        every such sample OWN_NEAR_MM from its tip (the metal and the insulation past it); if that
        is STRANGE_AT_GRASP of the wire's contrast or more at half those places or more, another
        wire lies along this one there, read with it as one wider wire whose end is this one's (or
        the line near its "end" is not this wire's). Samples out of the frame are left out."""
        mm = self.wppm
        line = _resample(full, 0.25 * mm)
        s = _arc(line)
        near = (s >= OWN_NEAR_MM[0] * mm) & (s <= OWN_NEAR_MM[1] * mm)
        at = np.abs(s - GRASP_MM * mm) <= GRASP_ALONG_MM * mm
        if np.count_nonzero(near) < 4 or np.count_nonzero(at) < 4:
            return False
        colours, seen = self._across_colours(line, np.asarray(OWN_ACROSS) * width, near | at)
        inner = near[near | at]
        own = colours[inner][seen[inner]]
        if len(own) < 4:
            return False
        there = colours[~inner]  # (places, across, channels)
        far = np.sqrt(((there[:, :, None, :] - own[None, None, :, :]) ** 2).sum(axis=3)).min(axis=2)
        far = np.where(seen[~inner], far, 0.0).max(axis=1)
        return bool(median(far) >= STRANGE_AT_GRASP * level)

    def _across_colours(self, line: np.ndarray, offs: np.ndarray, where: np.ndarray | None = None):
        """The raw colours across centre line `line` at offsets `offs` (px) along its normals, at
        its points `where` (all, if None): ((places, offsets, channels), which lie in the frame
        (places, offsets))."""
        pts = line[:, None, :] + offs[None, :, None] * _normals(line)[:, None, :]
        if where is not None:
            pts = pts[where]
        pts = pts.reshape(-1, 2)
        return self._raw(pts).reshape(-1, len(offs), self.con.work.shape[2]), self._in_frame(pts).reshape(-1, len(offs))

    def hidden(self, tip: np.ndarray, inward: np.ndarray, width: float, level: float) -> bool:
        """Whether past the tip the image has the wire's own colour where the board beside the wire
        has not: a line's end where it runs onto a patch of the scene as dark (or as light) as the
        wire, which the board's estimate follows, so the contrast ends while the wire may not (a
        cable in front of a dark chair, a key's edge running into the key). Colours are compared
        raw, in F's units: the wire's mean on its axis 1-4 mm in from the tip, the board's beside
        that stretch HIDDEN_MM out from the wire's edges (on each side), and every point on the
        axis HIDDEN_AHEAD_MM past the tip (each, not their mean: board and a rim's dark mix to
        any colour)."""
        ahead = tip - np.arange(HIDDEN_AHEAD_MM[0], HIDDEN_AHEAD_MM[1] + 0.01, 0.5)[:, None] * self.wppm * inward
        wire, beside, _ = self._own_colour(tip, inward, width)
        past = float(np.linalg.norm(self._raw(ahead) - wire, axis=1).max())
        return beside >= HIDDEN_SIDE * level and past < HIDDEN_SHARE * beside

    def _in_frame(self, pts: np.ndarray) -> np.ndarray:
        """Which points lie in the frame (where they can be sampled as they are)."""
        return (pts >= 0).all(axis=1) & (pts[:, 0] <= self.h - 1) & (pts[:, 1] <= self.w - 1)

    def _raw(self, pts: np.ndarray) -> np.ndarray:
        """The image's colours at the points, in F's units (not against the board's estimate)."""
        return bilinear(self.con.work, pts) * self.con.unit

    def _own_colour(self, tip: np.ndarray, inward: np.ndarray, width: float) -> tuple[np.ndarray, float, np.ndarray]:
        """(the wire's colour, raw: its mean on its axis 1-4 mm in from the tip; how far that lies
        from the board's beside that stretch, HIDDEN_MM out from the wire's edges, on the nearer
        side; the points sampled)."""
        mm = self.wppm
        side = np.array([-inward[1], inward[0]])
        inner = tip + np.arange(1.0, 4.01, 0.5)[:, None] * mm * inward
        off = (width / 2 + HIDDEN_MM * mm) * side
        pts = np.vstack([inner, inner + off, inner - off])
        values = self._raw(pts)
        n = len(inner)
        wire = values[:n].mean(axis=0)
        beside = min(float(np.linalg.norm(values[n:2 * n].mean(axis=0) - wire)),
                     float(np.linalg.norm(values[2 * n:].mean(axis=0) - wire)))
        return wire, beside, pts

    def reappears(self, tip: np.ndarray, inward: np.ndarray, width: float, level: float) -> bool:
        """Whether the wire shows again past its tip, beyond something lying across the way that
        does not stand out (a wire of nearly the board's colour lying over it): on a ray from the
        tip (straight on, or bending up to REAPPEAR_DEG), after a stretch not of the wire's colour,
        the wire's own colour again for REAPPEAR_RUN_MM or more, starting within REAPPEAR_MM of
        the tip, and narrow: the board's colour beside it, REAPPEAR_SIDE_MM out from its edges on
        both sides (a wire of the same colour lying across the way is that colour there too); and
        what lies between stands out of the board, if faintly (REAPPEAR_ACROSS of the wire's
        contrast, at the median: bare board between is the wire's end, with another wire of its
        colour beyond). Colours compared raw, in F's units, as in hidden(); asked only where the
        wire differs from the board beside it by REAPPEAR_DIFFERS of its contrast. Out of the
        frame nothing is the wire's colour: a ray may still see it again before it leaves."""
        wire, beside, own = self._own_colour(tip, inward, width)
        if not self._in_frame(own).all() or beside < REAPPEAR_DIFFERS * level:
            return False
        mm = self.wppm
        side = np.array([-inward[1], inward[0]])
        steps = np.arange(0.5, REAPPEAR_MM + REAPPEAR_RUN_MM + 0.01, 0.25) * mm
        angles = np.radians(np.arange(-REAPPEAR_DEG, REAPPEAR_DEG + 0.1, REAPPEAR_DEG / 2))
        rays = -np.cos(angles)[:, None] * inward + np.sin(angles)[:, None] * side  # (A, 2)
        pts = tip[None, None, :] + steps[None, :, None] * rays[:, None, :]  # (A, S, 2)
        lat = (width / 2 + REAPPEAR_SIDE_MM * mm) * np.stack([-rays[:, 1], rays[:, 0]], axis=1)  # (A, 2)
        grid = np.vstack([pts.reshape(-1, 2), (pts + lat[:, None, :]).reshape(-1, 2),
                          (pts - lat[:, None, :]).reshape(-1, 2)])
        m = pts.shape[0] * pts.shape[1]
        # out of the frame: not the wire's colour on a ray, and nothing of it beside one
        near = (np.linalg.norm(self._raw(grid) - wire, axis=1) < REAPPEAR_SHARE * beside) & self._in_frame(grid)
        on = near[:m].reshape(pts.shape[:2])
        narrow = on & ~near[m:2 * m].reshape(pts.shape[:2]) & ~near[2 * m:].reshape(pts.shape[:2])
        run = max(int(round(REAPPEAR_RUN_MM / 0.25)), 1)
        latest = int(round((REAPPEAR_MM - 0.5) / 0.25))  # the last step a run may start at
        for a in range(len(angles)):
            gone = np.flatnonzero(~on[a])
            if not len(gone):
                continue  # the wire's colour all the way: not this test's (hidden() or the tip's)
            left = int(gone[0])  # where the wire's colour is first left
            good = np.concatenate([[0], np.cumsum(narrow[a])])
            for start in range(left + 1, min(latest, len(steps) - run) + 1):
                if good[start + run] - good[start] == run:
                    # something lies across the way between (bare board there: the wire ended, and
                    # another of its colour lies beyond)
                    if median(self.sample(pts[a, left:start])) >= REAPPEAR_ACROSS * level:
                        return True
                    break
        return False

    def edges_go_on(self, tip: np.ndarray, inward: np.ndarray, width: float) -> bool:
        """Whether the wire's two edges go on past the tip, with its colour between them: a line's
        end where the wire passes in front of something that changes the contrast (a band of
        another colour behind a hanging cable, a patch the board's estimate follows), and the
        ridge stops while the wire does not. Across the axis, from 1 mm beyond one edge to 1 mm
        beyond the other, the raw colour's change between neighbouring samples: its median over
        1-4 mm in from the tip has its steepest step on each side of the axis (the wire's edges);
        1-4 mm past the tip (the steps in the frame, four at least), the steepest step within a
        px of each edge must stand EDGES_ON of the edge's own on each side, at the median, and
        the axis's colour there lie nearer the wire's than EDGES_HUE of the board's beside it
        (_own_colour). At a true end the board past it has no such edges (a conductor is
        narrower, a shadow falls to one side, a wire across the way crosses them)."""
        mm = self.wppm
        side = np.array([-inward[1], inward[0]])
        half = max(width, 0.8 * mm) / 2
        lat = np.arange(-(half + mm), half + mm + 0.01, 0.5)
        ds = np.arange(1.0, 4.01, 0.5) * mm

        def steps(sign: float) -> tuple[np.ndarray, np.ndarray]:
            pts = (tip + sign * ds[:, None, None] * inward + lat[None, :, None] * side).reshape(-1, 2)
            seen = np.asarray(self._in_frame(pts).reshape(len(ds), len(lat)).all(axis=1))
            v = self._raw(pts).reshape(len(ds), len(lat), -1)
            return np.linalg.norm(np.diff(v, axis=1), axis=2), seen

        inside, seen_in = steps(1.0)
        past, seen_past = steps(-1.0)
        if not seen_in.all() or np.count_nonzero(seen_past) < 4:
            return False
        own = np.median(inside, axis=0)
        mid = (lat[:-1] + lat[1:]) / 2
        past = past[seen_past]
        for part in (np.flatnonzero(mid < 0), np.flatnonzero(mid > 0)):
            e = int(part[np.argmax(own[part])])
            near = past[:, max(e - 2, 0):e + 3].max(axis=1)
            if median(near) < EDGES_ON * max(float(own[e]), 1e-9):
                return False
        wire, beside, _ = self._own_colour(tip, inward, width)
        axis = (tip - ds[:, None] * inward)[seen_past]
        return bool(median(np.linalg.norm(self._raw(axis) - wire, axis=1)) < EDGES_HUE * beside)

    def middle(self, p: np.ndarray, bow: float = MIDDLE_BOW):
        """A Sighting to take the wire by its middle at centre-line point p, or None (refused):
        its line must bow from its tangent by no more than `bow` of the disc's radius."""
        mm = self.wppm
        reach = (CLEARANCE_MM + 2.0) * mm  # past the fingers' disc (and so the frame's margin)
        if min(p[0], p[1], self.h - 1 - p[0], self.w - 1 - p[1]) < reach or self.off_tray(p[None, :], reach)[0]:
            return None  # the disc for the fingers would run off the frame or the tray
        skel = self.g.skeleton
        r0, c0 = int(p[0]), int(p[1])
        rad = int(math.ceil(reach))
        win = skel[r0 - rad:r0 + rad + 1, c0 - rad:c0 + rad + 1]
        from scipy import ndimage

        pieces, _ = ndimage.label(win, np.ones((3, 3)))
        own = np.column_stack(np.nonzero(pieces == pieces[rad, rad])).astype(float) + (p - rad)
        near = own[((own - p) ** 2).sum(axis=1) <= (TANGENT_MM * mm) ** 2]
        if len(near) < 3:
            return None
        tangent = principal_direction(near)
        # the local centre line through p, ordered along the tangent: it must run on through the
        # disc round p both ways and bend no more than a wire does (a small thing's outline, a
        # printed line's broken grid does not)
        along = (own - p) @ tangent
        across = np.abs((own - p) @ np.array([-tangent[1], tangent[0]]))
        if along.min() > -MIDDLE_THROUGH * reach or along.max() < MIDDLE_THROUGH * reach \
                or across.max() > bow * reach:
            return None
        line = own[np.argsort(along)]
        level = float(median(self.sample(line)))
        board = max(BOARD_FLOOR, BOARD_SHARE * level)
        width = self.width(line, board)
        seen = self._seen(self.fingers_room(p, own, width))
        if np.count_nonzero(seen >= board) >= DISC_HITS:
            return None
        room = float(np.percentile(seen, ROOM_PERCENTILE)) / board if len(seen) else 0.0
        return self.sighting(p, tangent, p, tangent, 1.0 / (1.0 + room))

    def edges_end(self, scan: np.ndarray, scan_s: np.ndarray, side: np.ndarray, gap: float) -> float | str:
        """Where the first of a wire's two edges ends, `gap` apart either side of `scan` (a line
        from inside the wire out past its end; scan_s: arc length along it), each where its
        contrast falls to TIP_SHARE of its own along the wire: the edge on the side the light
        comes from ends with the wire, the other runs on into the shadow the end casts. Or why
        there is no such end."""
        mm = self.wppm
        ends: list[float] = []
        for sign in (-1.0, 1.0):
            lateral = sign * gap / 2 + np.array([-0.3, 0.0, 0.3]) * mm
            ray = scan[:, None, :] + lateral[None, :, None] * side
            along = self._seen(ray.reshape(-1, 2), False).reshape(len(scan), len(lateral)).max(axis=1)
            on = scan_s >= 2.0 * mm
            level = float(median(along[on])) if on.any() else 0.0
            if level < BOARD_FLOOR:
                return "no wire to be seen at its end"
            end = _drop(along, scan_s, max(0.5 * BOARD_FLOOR, TIP_SHARE * level))
            if isinstance(end, str):
                return end
            ends.append(end)
        if abs(ends[0] - ends[1]) > HOLLOW_END_MM * mm:  # not one wire's edges: two wires side by side
            return BESIDE
        return max(ends)

    def other_edge(self, line: np.ndarray, arc: np.ndarray, width: float, board: float) -> tuple[float, float] | None:
        """For a line that may be one edge of a wire whose body hardly stands out (a white wire on
        a white board shows as two dark lines, its shaded sides): (the shift along the line's
        normals to halfway to the other edge, the distance between the edges), or None. The
        other edge must run beside the line, on one side only, at a distance within HOLLOW_MM
        that stays the same (to 0.8 mm), from SPAN_MM in to the line's first mm, with no more
        than the board's contrast between them. arc: the arc length along line at its points."""
        mm = self.wppm
        idx = np.searchsorted(arc, np.linspace(1.0, SPAN_MM, 10) * mm).clip(0, len(line) - 1)
        n = _normals(line)[idx]
        offs = np.arange(0.0, HOLLOW_MM[1] * mm + 0.01, 0.5)
        far = int(np.searchsorted(offs, HOLLOW_MM[0] * mm))
        found = []
        at = np.arange(len(offs))[None, :]
        for sign in (-1.0, 1.0):
            pts = line[idx][:, None, :] + sign * offs[None, :, None] * n[:, None, :]
            prof = self._seen(pts.reshape(-1, 2), False).reshape(len(idx), len(offs))
            j = far + np.argmax(prof[:, far:], axis=1)  # the other edge: the most contrast far enough out
            peak = prof[np.arange(len(idx)), j]
            valley = np.where((at >= 1) & (at < np.maximum(j, 2)[:, None]), prof, np.inf).min(axis=1)  # between
            ok = (peak >= board) & (valley < board) & (valley < 0.5 * peak)
            found.append((int(ok.sum()), sign, offs[j]))
        (n_a, _, _), (n_b, _, _) = found
        best = max(found, key=lambda f: f[0])
        if best[0] < len(idx) or min(n_a, n_b) > len(idx) // 2:
            return None
        d = best[2]
        if float(d.max() - d.min()) > 0.8 * mm:
            return None
        gap = float(median(d))
        return best[1] * gap / 2.0, gap

    def casts_shadow(self, line: np.ndarray, width: float) -> bool:
        """Whether the wire casts a shadow that can be told from it: its own centre line does not
        look like board in shadow, and the board along one side of it does, much more than along
        the other (a light from one side)."""
        if len(line) < 5:
            return False
        n = _normals(line)
        offs = width / 2 + np.array([0.6, 1.0]) * self.wppm  # past the blur of the wire's edge
        offs = np.concatenate([-offs, offs])  # one side, then the other
        pts = (line[:, None, :] + offs[None, :, None] * n[:, None, :]).reshape(-1, 2)
        f, _, shade = self.shade(np.vstack([line, pts]))
        if float(shade[:len(line)].mean()) >= SHADOW_LIKE_WIRE:
            return False
        looks = (shade & (f >= BOARD_FLOOR))[len(line):].reshape(len(line), 2, 2)
        share = looks.mean(axis=(0, 2))
        # a blurred edge looks like shadow on both sides alike
        return bool(share.max() >= SHADOW_SIDE and share.min() <= 0.5 * share.max())

    def flanks(self, line: np.ndarray, arc: np.ndarray, width: float) -> tuple[float, float]:
        """How much a wire's flanks stand out of the board, as a share of its middle: F 0.45 of its
        width out from the centre line, over what it is within 0.2 of it (each above the board 1 mm
        past its edges), the median over the centre line from TIP_START_MM to SPAN_MM in (on the
        insulation, past any conductor); and the median of its middle's contrast there. (0, 0) where
        the line is shorter."""
        on = (arc >= TIP_START_MM * self.wppm) & (arc <= SPAN_MM * self.wppm)
        if len(line) < 5 or on.sum() < 3:
            return 0.0, 0.0
        pts, n = line[on], _normals(line)[on]
        offs = _across_tip(width, self.wppm)
        v = self.sample((pts[:, None, :] + offs[None, :, None] * n[:, None, :]).reshape(-1, 2)).reshape(len(pts), -1)
        board = v[:, 3:5].mean(axis=1)
        middle = v[:, :3].max(axis=1) - board
        return float(median((v[:, 5:7].mean(axis=1) - board) / np.maximum(middle, 1e-9))), float(median(middle))

    def conductor(self, end: np.ndarray, out: np.ndarray, width: float,
                  flanks: Callable[[], tuple[float, float]] = lambda: (0.0, 0.0)) -> np.ndarray:
        """The tip of a faint conductor or ferrule running on straight past the insulation's end
        (end), or end itself if there is none. It runs while the contrast on the axis (the most
        of three samples across it), averaged over CONDUCTOR_WINDOW_MM, stands CONDUCTOR_CONTRAST
        above the board beside it, narrower than the wire; its tip is where that contrast falls
        to TIP_SHARE of its own, and past that tip no thin line may go on (line_goes_on: a line
        of the board's print), and one that reaches no further past end than SOFT_REACH_MM must
        have edges no softer than SOFT_EDGES times the insulation's (else it is the end's shadow,
        whose edges are its penumbra's). The tip's scan may already have followed part of it (a bright
        conductor stands out as the insulation does, but not all the way): the narrow stretch
        just inside end counts towards its length and its contrast. One that runs on to the
        frame's border ends there; one that runs on past TIP_MAX_MM is none."""
        from scipy import ndimage

        mm = self.wppm
        n = max(round(CONDUCTOR_WINDOW_MM * mm * 2), 1)  # steps of 0.5 px in the window
        ahead = np.arange(0.5, TIP_MAX_MM * mm, 0.5)
        at = end + ahead[:, None] * out
        inside = self._in_frame(at)
        framed = int(np.argmin(inside)) if not inside.all() else len(ahead)
        # board in shadow beyond the tip is no conductor, unless a sharp ridge runs on it: where the
        # wire casts shadows that can be told from it, and past an end lighter than the board (what
        # runs on from it darker than the board and of the board's colour is its shadow)
        shaded = self.shadows or self.lighter(end, out)
        steps = np.concatenate([np.arange(-TIP_START_MM * mm, 0.0, 0.5), ahead[:framed]])  # inside end too
        z = int(np.count_nonzero(steps < 0))  # the first step past end
        rise, wide = self._profile(end, out, width, steps, shaded)
        mean = ndimage.uniform_filter1d(rise, n, mode="nearest")  # over the window centred on each step
        # a dip shorter than half the window is no gap: a line thinner than two pixels comes and
        # goes as it crosses the pixel grid (and strands or JPEG blocks break it up)
        held = ndimage.maximum_filter1d(rise, max(n // 2, 1), mode="nearest")
        on = (mean >= CONDUCTOR_CONTRAST) & (held >= 0.5 * CONDUCTOR_CONTRAST)
        on = bridged(on[None, :], 1)[0]  # (nor is a dip of the average itself for one step: a grain across a thin line)
        # what the scan followed: back from end, the steps where the wire stands out but narrow:
        # its flanks stand out less, as a share of its middle, than the insulation's (`flanks`,
        # the FLANK_ constants; a round wire's flanks are darker than its middle, so under 1),
        # looked for only where the whole window just inside end stands out with its flanks under
        # CONDUCTOR_NARROW of its middle (a stretch shorter than the window is not counted)
        beside = ndimage.uniform_filter1d(wide, n, mode="nearest") / np.maximum(mean, 1e-9)
        narrow = np.zeros(len(steps), bool)
        if on[z - n:z].all() and (beside[z - n:z] <= CONDUCTOR_NARROW).all():
            share, middle = flanks()
            other = np.abs(mean - middle) >= FLANK_OTHER[0] * middle  # a contrast not the insulation's
            narrow = on & (share >= FLANK_MIN) & (beside <= CONDUCTOR_NARROW) \
                & ((beside <= FLANK_SHARE * share) | (other & (beside <= FLANK_OTHER[1] * share)))
        kept = np.flatnonzero(~narrow[:z][::-1])
        followed = int(kept[0]) if kept.size else z
        if followed < n:  # less than the window: the blur of the insulation's own end
            followed = 0
        s0 = z - followed
        off = np.flatnonzero(~on[z:])
        run = z + (int(off[0]) if off.size else len(on) - z)  # one past the conductor's last step
        length = steps[run - 1] - (steps[s0] if followed else 0.0)
        if run == z or (not followed and run - z < n) or length < CONDUCTOR_MIN_MM * mm:
            return end  # nothing that runs on far enough: the blur of the end itself, or its shadow
        if median(wide[s0:run]) > CONDUCTOR_NARROW * median(rise[s0:run]):
            return end  # as wide as the wire: the end's shadow or the blur of a rounded end
        # its tip, as the insulation's: where its contrast, averaged over the window, falls to
        # TIP_SHARE of what it is along it over half the window (an average over a centred window
        # crosses a step's half height where it steps; over less, the dips of a line thinner than two
        # pixels fall below it well inside the conductor)
        short = ndimage.uniform_filter1d(rise, max(n // 2, 1), mode="nearest")
        own = float(median(short[s0:run]))
        edge = max(CONDUCTOR_CONTRAST, TIP_SHARE * own)
        low = z + np.flatnonzero(~bridged((mean[z:run] >= edge)[None, :], 1)[0])
        if not followed:  # not in the tip's own first window (it reaches back onto the insulation)
            low = low[low >= z + n]
        i = int(low[0]) if low.size else run
        if i >= run:
            reach = float(steps[run - 1])
        elif i == z:
            return end  # the scan took it to its tip already
        else:
            a, b = mean[i - 1], mean[i]
            reach = float(steps[i - 1] + np.clip((a - edge) / max(a - b, 1e-6), 0, 1) * 0.5)
        if followed and median(mean[z:i]) < CONDUCTOR_STEADY * median(mean[s0:z]):
            return end  # it does not hold its contrast past end: the end's blur or shadow
        if not shaded:
            reach = self.out_of_shade(end, out, width, reach)
        stretch = end + np.linspace(0.3, 0.8, 5)[:, None] * reach * out
        inside = end - np.linspace(1.0, 3.0, 5)[:, None] * mm * out
        longest, faint, broad = BROAD_SHADOW
        if reach <= longest * width and own <= faint * median(rise[(steps >= -3.0 * mm) & (steps <= -mm)]) \
                and self.shade(stretch)[2].mean() >= SHADE_SHARE \
                and self.breadth(stretch, out, width) >= broad * self.breadth(inside, out, width):
            return end  # as wide as the wire, faint, short, the board's colour darkened: the cut end's shadow
        if reach <= SOFT_REACH_MM * mm:  # metal is as sharp as the insulation; a shadow is soft
            if self.shadow_edges(stretch, inside, out, width):
                return end
        if i >= run == len(steps):
            if framed < len(ahead):
                return end + out * reach  # on to the frame's border
            return end  # on past TIP_MAX_MM, as no conductor: the board's print or its light
        if self.line_goes_on(end + out * reach, out, width):
            return end  # a line of the board's print, not a conductor
        return end + out * reach

    def fine_conductor(self, end: np.ndarray, out: np.ndarray, width: float, level: float) -> np.ndarray:
        """The tip of a thin conductor past the insulation's end `end` that the working image
        blurs away, followed in the input's own pixels (fine.py), or end itself if there is
        none, if the input has no more pixels than the working image (below FINE_SCALE), or if
        what the scan took for the insulation's end is metal already: the wire's last FINE_LAST_MM
        has a colour COLOUR_CHANGE of its contrast from every colour it has FINE_OWN_MM in (a bright
        tin or ferrule the scan ran on along; past it, a line or speck would be taken for more)."""
        if self.source is None or self.k < FINE_SCALE:
            return end
        mm = self.wppm
        last = end - np.linspace(FINE_LAST_MM[0], FINE_LAST_MM[1], 4)[:, None] * mm * out
        own = end - np.arange(FINE_OWN_MM[0], FINE_OWN_MM[1] + 0.01, 0.5)[:, None] * mm * out
        pts = np.vstack([last, own])
        if not self._in_frame(pts).all():
            return end
        colours = self._raw(pts)
        tipward = np.median(colours[:len(last)], axis=0)
        if float(np.linalg.norm(colours[len(last):] - tipward, axis=1).min()) > COLOUR_CHANGE * level:
            return end
        if self._image is None:  # (fine.follow takes colours 0-1, as working_image() reads them)
            a = np.asarray(self.source)
            img = a[:, :, :3] if a.ndim == 3 else a[:, :, None]
            self._image = img.astype(np.float32) * np.float32(unit(a))
        k = self.k
        tip = follow_in_input(self._image, (end + 0.5) * k - 0.5, out, width * k, self.wppm * k,
                          CONDUCTOR_MIN_MM, TIP_MAX_MM)
        if tip is None:
            return end
        tip = (tip + 0.5) / k - 0.5
        reach = float(np.linalg.norm(tip - end))
        inside = end - np.linspace(1.0, 3.0, 5)[:, None] * mm * out
        soft = self.softness(inside, out, width)
        if reach < FINE_BLUR * soft:  # no further than the halo of a blurred end and its soft shadow reach
            return end
        if reach <= SOFT_REACH_MM * mm:  # as conductor(): a stretch no longer than an end's shadow, with edges
            stretch = end + np.linspace(0.3, 0.8, 5)[:, None] * reach * out  # softer than the insulation's
            if self.softness(stretch, out, width) > SOFT_EDGES * soft:
                return end
        return tip

    def out_of_shade(self, end: np.ndarray, out: np.ndarray, width: float, reach: float) -> float:
        """A conductor's reach (working px past the insulation's end `end`) taken back to where
        it runs on into what looks like board in shadow (shade()), if its own metal does not: the
        end's shadow, past a metal of another colour than the board's, carries its contrast on.
        The shadow is the board's colour, darkened, and no longer than the wire's width; the metal
        has another colour (SHADE_ constants). In a grey image colour cannot tell them: unchanged."""
        mm = self.wppm
        steps = np.arange(0.0, reach + 0.01, 0.5)
        if len(steps) < 4:
            return reach
        side = np.array([-out[1], out[0]])
        lateral = np.array([-0.2, 0.0, 0.2]) * width
        pts = (end + steps[:, None, None] * out + lateral[None, :, None] * side).reshape(-1, 2)
        at = _corners(self.h, self.w, pts)
        p, b = _mix(self.con.work, *at), _mix(self.con.board, *at)  # (N, channels)
        _, shade = shadow_free(self.con, p, b, _mix(self.f, *at))
        shade = shade.reshape(len(steps), len(lateral)).sum(axis=1) >= 2
        tint = light_and_tint(self.con, p, b)[1].reshape(len(steps), len(lateral)).mean(axis=1)
        # the last stretch of shade reaching the tip, and the metal before it
        off = np.flatnonzero(~shade)
        if not off.size or off[-1] == len(steps) - 1:
            return reach
        j = int(off[-1]) + 1  # the first step of the shade that runs to the tip
        if not SHADE_PAST_MM * mm <= reach - steps[j] <= width or steps[j] < CONDUCTOR_MIN_MM * mm \
                or shade[:j].mean() > SHADE_IN_METAL:
            return reach  # (a shadow past the tip is no longer than the wire is thick, in light 45 degrees up)
        metal = float(median(tint[:j]))
        if metal < SHADE_METAL_TINT or median(tint[j:]) > SHADE_TINT_SHARE * metal:
            return reach  # the metal has the board's colour, or what follows it keeps some of the metal's
        return float(steps[j])

    def short_of_shadow(self, scan: np.ndarray, scan_s: np.ndarray, along: np.ndarray, tip_s: float,
                        out: np.ndarray, width: float) -> float:
        """The tip's arc position (as tip_s, which the scan for it found: `along` sampled at the
        points `scan`, arc positions scan_s, outward) taken back to where the wire's contrast
        steps down, if the scan ran on into the end's soft shadow: a stretch of SHADOW_STEP of the
        wire's contrast (4-7 mm inside) or less, 0.8 mm to SOFT_REACH_MM long, whose edges are over
        SOFT_EDGES times as soft as the insulation's. The tip is then where the contrast stands
        SHADOW_FOOT of the step above the stretch's (near the step's foot)."""
        mm = self.wppm
        body = (scan_s >= tip_s + 4.0 * mm) & (scan_s <= tip_s + 7.0 * mm)
        if np.count_nonzero(body) < 3:
            return tip_s
        wire = float(median(along[body]))
        start = int(np.flatnonzero(body)[-1])  # outward from there
        low = np.flatnonzero(along[start:] < SHADOW_STEP * wire)
        if not low.size:
            return tip_s
        s1 = float(scan_s[start + int(low[0])])
        if not 0.8 * mm <= s1 - tip_s <= SOFT_REACH_MM * mm:
            return tip_s
        past = (scan_s <= s1) & (scan_s >= tip_s)
        level = float(median(along[past]))
        stretch = scan[(scan_s <= s1 - 0.2 * (s1 - tip_s)) & (scan_s >= s1 - 0.7 * (s1 - tip_s))]
        inside = scan[(scan_s >= s1 + 1.0 * mm) & (scan_s <= s1 + 3.0 * mm)]
        if len(stretch) < 2 or len(inside) < 2 or \
                not self.shadow_edges(stretch, inside, out, width):
            return tip_s
        self.shadow_past = (s1 - tip_s, level)
        foot = level + SHADOW_FOOT * (wire - level)
        i = start + int(np.flatnonzero(along[start:] < foot)[0]) if (along[start:] < foot).any() else start
        if i == start:
            return s1
        a, b = along[i - 1], along[i]
        return float(scan_s[i - 1] + np.clip((a - foot) / max(a - b, 1e-6), 0, 1) * (scan_s[i] - scan_s[i - 1]))

    def shadow_edges(self, stretch: np.ndarray, inside: np.ndarray, out: np.ndarray, width: float) -> bool:
        """Whether what lies at the points `stretch` has edges over SOFT_EDGES times as soft as the
        insulation's at the points `inside` (softness()): an end's shadow, not metal."""
        return bool(self.softness(stretch, out, width) > SOFT_EDGES * self.softness(inside, out, width))

    def softness(self, pts: np.ndarray, out: np.ndarray, width: float) -> float:
        """How soft the edges of what lies across the axis `out` are at the points `pts` (working
        px; NaN if nothing stands out there): the median over the points of the contrast's rise
        across (its peak over the board a whole width and 1 mm out from the axis) divided by its
        steepest slope, about the width of a blurred step. A shadow's edges are as soft as its
        penumbra; a conductor's or a ferrule's as sharp as the insulation's (the same blur)."""
        f = self._across_axis(pts, out, width)
        rise = f.max(axis=1) - np.median(np.hstack([f[:, :4], f[:, -4:]]), axis=1)
        slope = np.abs(np.diff(f, axis=1)).max(axis=1) / 0.25
        seen = (rise > 0.5) & (slope > 0)
        return float(median(rise[seen] / slope[seen])) if seen.any() else math.nan

    def breadth(self, pts: np.ndarray, out: np.ndarray, width: float) -> float:
        """How broad what lies across the axis `out` is at the points `pts` (working px; NaN if
        nothing stands out there): the median over the points of the width of its contrast at half
        its peak over the board a whole width and 1 mm out from the axis. A conductor is narrower
        than its insulation; the shadow a cut end casts past it is as wide as the wire."""
        f = self._across_axis(pts, out, width)
        f = f - np.median(np.hstack([f[:, :4], f[:, -4:]]), axis=1)[:, None]
        widths = []
        for row in f:
            j = int(np.argmax(row))
            if row[j] <= 0.5:
                continue
            low = np.flatnonzero(row < 0.5 * row[j])
            left, right = low[low < j], low[low > j]
            widths.append(((right[0] if right.size else len(row)) - (left[-1] if left.size else -1) - 1) * 0.25)
        return float(median(np.array(widths))) if widths else math.nan

    def _across_axis(self, pts: np.ndarray, out: np.ndarray, width: float) -> np.ndarray:
        """F across the axis `out` at each of the points `pts`: a row a point, sampled every 0.25
        px a whole width and 1 mm out either side (softness() and breadth() read these rows)."""
        side = np.array([-out[1], out[0]])
        lateral = np.arange(-(width + self.wppm), width + self.wppm + 0.01, 0.25)
        return self.sample((pts[:, None, :] + lateral[None, :, None] * side).reshape(-1, 2)).reshape(len(pts), -1)

    def _profile(self, end: np.ndarray, out: np.ndarray, width: float, steps: np.ndarray,
                 shaded: bool) -> tuple[np.ndarray, np.ndarray]:
        """conductor()'s samples at `steps` (working px) along out from end: (the most contrast of
        three samples across the axis, 0.2 of the wire's width apart, above the board 1 mm past the
        wire's edges; the mean 0.45 of its width off the axis, above that board). shaded: board in
        shadow counts as board, unless a sharp ridge runs on it."""
        side = np.array([-out[1], out[0]])
        lateral = _across_tip(width, self.wppm)
        flat_pts = (end + steps[:, None, None] * out + lateral[None, :, None] * side).reshape(-1, 2)
        if shaded:
            v, free, shade = self.shade(flat_pts)
            v = np.where(shade & (self.sample(flat_pts, self.FINE) < CONDUCTOR_RIDGE), free, v)
        else:
            v = self.sample(flat_pts)
        v = v.reshape(len(steps), len(lateral))
        board = v[:, 3:5].mean(axis=1)
        return v[:, :3].max(axis=1) - board, v[:, 5:7].mean(axis=1) - board  # (a thin conductor may lie off the axis)

    def line_goes_on(self, tip: np.ndarray, out: np.ndarray, width: float) -> bool:
        """Whether a thin line goes on past a conductor's tip (out: its direction). At each step
        over RUN_ON_MM past it, across the wire's width and 1 mm either side: the most contrast,
        above that row's median, in a peak no wider than RUN_ON_WIDE_MM (a broad patch's edge
        beside the tip is no line); a line goes on where that stands RUN_ON_CONTRAST or more at
        half the steps (a speck of the board's texture holds a step or two). Past its tip a
        conductor gives way to board; a line that goes on is the board's print (a cutting mat's
        grid line, crossed at a slant by the scan for the tip), taken for a conductor."""
        mm = self.wppm
        side = np.array([-out[1], out[0]])
        ahead = np.arange(RUN_ON_MM[0] * mm, RUN_ON_MM[1] * mm, 0.5)
        across = np.arange(-(width / 2 + mm), width / 2 + mm + 0.01, 0.5)
        near = self.sample((tip + ahead[:, None, None] * out + across[None, :, None] * side).reshape(-1, 2))
        near = near.reshape(len(ahead), len(across))
        base = np.median(near, axis=1)
        peak = near.max(axis=1) - base
        wide = np.count_nonzero(near - base[:, None] >= 0.5 * peak[:, None], axis=1) * 0.5 > RUN_ON_WIDE_MM * mm
        return bool(median(np.where(wide, 0.0, peak)) >= RUN_ON_CONTRAST)

    def lighter(self, end: np.ndarray, out: np.ndarray) -> bool:
        """Whether the wire's last mm before end (out: out of the wire) is lighter than the board
        there: its colour, projected on the board's, more than the board's."""
        pts = end[None, :] - np.linspace(0.3, 1.0, 4)[:, None] * self.wppm * out[None, :]
        at = _corners(self.h, self.w, pts)
        p = _mix(self.con.work, *at).reshape(len(pts), -1)
        b = _mix(self.con.board, *at).reshape(len(pts), -1)
        light = (p * b).sum(axis=1) / np.maximum((b * b).sum(axis=1), 1e-9)
        return bool(median(light) > 1.0)

    def recentred(self, line: np.ndarray, width: float, along: float = 0.0) -> np.ndarray:
        """The centre line moved across the wire to the middle of its contrast (sub-pixel), that
        contrast the most over `along` px either way along the line, if not 0; the first point,
        the tip, put on the centred line's extension."""
        from scipy import ndimage

        if len(line) < 5:
            return line
        n = _normals(line)
        offs = np.linspace(-0.8 * width, 0.8 * width, 9)
        prof = self._across_most(line, n, offs, along, self.FLAT)
        wts = np.clip(prof - 0.5 * prof.max(axis=1, keepdims=True), 0, None)
        total = wts.sum(axis=1)
        shift = np.where(total > 0, (wts * offs).sum(axis=1) / np.maximum(total, 1e-9), 0.0)
        shift = ndimage.median_filter(np.clip(shift, -0.5 * width, 0.5 * width), 5, mode="nearest")
        shift = ndimage.uniform_filter1d(shift, 5, mode="nearest")
        out = line + shift[:, None] * n
        # the tip: on the centred line's own extension, as far out as the tip search put it
        ahead = out[1] - out[min(4, len(out) - 1)]
        ahead /= max(float(np.linalg.norm(ahead)), 1e-9)
        out[0] = out[1] + ahead * float(np.linalg.norm(line[0] - line[1]))
        return out

    def _across_most(self, at: np.ndarray, n: np.ndarray, offs: np.ndarray, along: float, of: int = F) -> np.ndarray:
        """A layer across a line: at each point `at`, at the offsets `offs` (px) along its unit
        normal n, the most of five samples over `along` px either way along the line (or the one
        sample, if along is 0): (len(at), len(offs))."""
        ahead = np.linspace(-along, along, 5) if along else np.zeros(1)
        t = np.column_stack([n[:, 1], -n[:, 0]])
        pts = at[:, None, None, :] + ahead[None, :, None, None] * t[:, None, None, :] \
            + offs[None, None, :, None] * n[:, None, None, :]
        return self.sample(pts.reshape(-1, 2), of).reshape(len(at), len(ahead), len(offs)).max(axis=1)

    def width(self, line: np.ndarray, board: float, bridge: float = 0.0) -> float:
        """The wire's width (working px): across it at five places, how far its contrast stands
        above the board (and above PEAK_SHARE of its peak) without a break (none narrower than BRIDGE_MM,
        or than `bridge` px if more), the median."""
        if len(line) < 8:
            return 2.0
        return self._across(line, board, bridge, PEAK_SHARE)[0]

    def _across(self, line: np.ndarray, board: float, bridge: float, share: float,
                stripes: bool = False) -> tuple[float, float, float]:
        """width()'s measure with the contrast above `share` of its peak (and the board): (the
        median width, how unsteady the five are (unsteadiness), the median offset of their middles from
        the line along its normals), working px. stripes: each profile across is the most over
        STRIPE_ALONG_MM either way along the line (a striped wire's dark stripes cover its width)."""
        idx = np.linspace(len(line) // 4, len(line) - 2, 5).astype(int)
        t = line[np.minimum(idx + 2, len(line) - 1)] - line[np.maximum(idx - 2, 0)]
        t /= np.maximum(np.linalg.norm(t, axis=1, keepdims=True), 1e-9)
        n = np.column_stack([-t[:, 1], t[:, 0]])
        offs = np.arange(-4.0 * self.wppm, 4.0 * self.wppm + 0.01, 0.5)
        prof = self._across_most(line[idx], n, offs, STRIPE_ALONG_MM * self.wppm if stripes else 0.0)
        mid = len(offs) // 2
        peak = prof[:, mid - 4:mid + 5].max(axis=1, keepdims=True)
        above = prof >= np.maximum(share * peak, board)
        # a break narrower than BRIDGE_MM is no edge: the specular line along a glossy wire (it may
        # be as light as the board), or a grain
        above = bridged(above, int(round(max(BRIDGE_MM * self.wppm, bridge) / 0.5)))
        # in each row, the run of `above` through the sample nearest the centre line that is in it
        window = above[:, mid - 3:mid + 4]
        seen = window.any(axis=1)
        if not seen.any():
            return 2.0, 99.0, 0.0
        m = mid - 3 + np.argmin(np.where(window, np.abs(np.arange(7) - 3), 99), axis=1)[:, None]
        at = np.arange(above.shape[1])[None, :]
        lo = np.where(~above & (at < m), at, -1).max(axis=1) + 1
        hi = np.where(~above & (at > m), at, above.shape[1]).min(axis=1) - 1
        widths = (hi - lo + 1)[seen] * 0.5
        middle = ((lo + hi)[seen] * 0.5 - mid) * 0.5
        return float(np.clip(median(widths), 1.0, 4.0 * self.wppm)), unsteadiness(widths), float(median(middle))

    def span(self, full, grasp, width) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """What the free test and the room round an end look beside: the centre line along the
        span (its first SPAN_MM and the slack: what lies beside the wire further on is no
        matter) at 1 px steps, its normals, and the points of the CLEARANCE_MM disc round the
        grasp point less the wire itself (clear of its centre line near the grasp point)."""
        mm = self.wppm
        dense = _resample(full, 1.0)
        ds = _arc(dense)
        along = ds <= (SPAN_MM + SPAN_SLACK_MM) * mm
        local = dense[np.abs(ds - GRASP_MM * mm) <= (CLEARANCE_MM + 3.0) * mm]
        disc = self.fingers_room(grasp, local, width)
        return dense[along], _normals(dense)[along], disc

    def fingers_room(self, at: np.ndarray, line: np.ndarray, width: float) -> np.ndarray:
        """The points of the CLEARANCE_MM disc round `at` less the wire itself: those farther
        than its half width (and a little) from the centre-line points `line` near there."""
        mm = self.wppm
        disc = _disc(CLEARANCE_MM * mm) + at
        if not len(line):
            return disc
        d2 = ((disc * disc).sum(axis=1)[:, None] + (line * line).sum(axis=1)[None, :]
              - 2.0 * disc @ line.T).min(axis=1)
        return disc[d2 > (width / 2 + 0.6 * SIDE_FREE_MM * mm) ** 2]

    def crowded(self, span, tip, out, width, board, level) -> str:
        """Why the wire near its end is not free (board must show around it), or ''."""
        mm = self.wppm
        half = width / 2
        line, n, disc = span
        # beside the span, both sides
        offs = half + np.array([0.6, 0.9, 1.2]) * SIDE_FREE_MM * mm
        band = (line[:, None, None, :] + (np.array([-1, 1])[None, :, None, None] * offs[None, None, :, None])
                * n[:, None, None, :]).reshape(-1, 2)
        # beyond the tip
        dirs = _fan(out)
        cap = (tip[None, None, :] + (half + np.array([0.7, 1.0, 1.4, 2.0, 2.8]) * SIDE_FREE_MM * mm)[None, :, None]
               * dirs[:, None, :]).reshape(-1, 2)
        values = self._seen(np.vstack((band, cap, disc)))
        nb, nc = len(band), len(cap)
        # where the line bends (a ridge hooking at an end cut aslant, a tight curl), a point of the
        # bands on the inside of the bend may fall on the wire itself, nearer its centre line than
        # half its width: that is no thing beside it
        low = max(CROSS_FLOOR, CROSS_SHARE * level)  # (the least that counts beside it, below)
        seen = np.flatnonzero(values[:nb] >= min(board, low))
        if len(seen):
            values[seen[_on_itself(band[seen], seen // (nb // len(line)), line, half, 2.0 * offs[-1])]] = 0.0
        if self.shadow_past is not None:  # the end's own soft shadow past its tip, as short_of_shadow saw it,
            # is board (no more than SHADOW_DIM of its contrast, out to 1 mm past where it was seen)
            reach, dim = self.shadow_past
            fan_at = values[nb:nb + nc]
            fan_at[(np.linalg.norm(cap - tip, axis=1) <= reach + mm) & (fan_at <= SHADOW_DIM * dim)] = 0.0
        # past bare board just beyond the tip, what lies further out is another thing, clear of the
        # end (the fan's rings: a view of its samples, rays by rings out from the tip)
        rings = values[nb:nb + nc].reshape(len(_FAN), -1)
        fading = max(FADE_FLOOR, FADE_SHARE * level)
        if (rings[:, :BARE_RINGS] < min(board, fading)).all():
            rings[:, BARE_RINGS:] = 0.0
        hit = values >= board
        # on past the tip, straight or bending a little, even a faint contrast that goes on is the
        # wire going on into light or a colour that hides it, not its end; but not one that fills
        # most of the fan beyond the tip, as no wire going on does: a broad patch of the board's print
        fan = rings >= fading
        mid = len(_FAN) // 2
        ahead = max((fan[j - 1:j + 2] for j in range(mid - BEND_RAYS, mid + BEND_RAYS + 1)), key=np.count_nonzero)
        if np.count_nonzero(ahead) >= ahead.size // 2 and np.count_nonzero(fan) < BROAD_SHARE * fan.size:
            return FADES
        # beside the span, something that goes on for RUN_MM along it (a speck of the board's
        # texture or a thin printed line does not)
        runs = hit[:nb].reshape(len(line), 2, 3).copy()
        beside = values[:nb].reshape(len(line), 2, 3)  # (rows along the span, its two sides, the bands)
        at = band.reshape(len(line), 2, 3, 2)  # ... and where they were sampled
        # but on a side where only the band nearest the wire sees anything, faint beside the wire
        # and all along it, that is the wire's own edge (a round wire's flank of nearly the board's
        # shade, which its width leaves out) or its soft shadow: another wire near enough to touch
        # is wide enough to reach the bands further out too; and so is what lies that near the
        # wire on that side in the disc round the grasp point
        inner = beside[:, :, 0]
        in_disc = hit[nb + nc:].copy()
        across = None  # each disc point's signed distance from the line, along its normal there
        for k, sign in ((0, -1.0), (1, 1.0)):
            rows = np.flatnonzero(runs[:, k, 0])
            if not len(rows) or runs[:, k, 1:].any() or inner[:, k].max() >= EDGE_SHARE * level \
                    or rows[-1] - rows[0] < EDGE_SPREAD_MM * mm:
                continue
            runs[:, k, 0] = False
            if len(disc):
                if across is None:
                    j = ((disc[:, None, :] - line[None, :, :]) ** 2).sum(axis=2).argmin(axis=1)
                    across = ((disc - line[j]) * n[j]).sum(axis=1)
                on_side = sign * across
                in_disc &= ~((on_side > 0) & (on_side < offs[-1]))
        need = max(round(RUN_MM * mm), 2)
        if _runs_on(runs, need):
            self._drop_specks(runs, at, line, half, board, level, need)
            if _runs_on(runs, need):
                return BESIDE
        if low < board and self._faint_across(beside, at, line, half, low, level, need):
            return BESIDE
        if np.count_nonzero(hit[nb:nb + nc]) >= CAP_HITS:
            return BEYOND
        if np.count_nonzero(in_disc) >= DISC_HITS:  # (specks there leave the fingers room)
            grasp = line[np.argmin(np.abs(np.arange(len(line)) - GRASP_MM * mm))]  # (line: 1 px steps from the tip)
            in_disc &= ~self._specks(grasp, (CLEARANCE_MM + 1.0) * mm, line, half, board, level)(disc)
        if np.count_nonzero(in_disc) >= DISC_HITS:
            self.crowding = float(values[nb + nc:][in_disc].max()) / board
            return NO_ROOM
        return ""

    def _faint_across(self, values: np.ndarray, band: np.ndarray, line: np.ndarray, half: float, low: float,
                      level: float, need: int) -> bool:
        """Whether something fainter than the threshold beside a wire of strong contrast lies
        across the bands beside its span (`values` at the points `band`: rows along `line`, its
        two sides, the bands out from it): a thin wire of less contrast that touches it. Such a
        thing stands `low` or more in all three bands, as much in each (within CROSS_FLAT: the
        wire's own glow and blur fade outward, and what starts further out rises), over a stretch
        of the span no longer than CROSS_MM (what runs along the wire is its halo or shadow, and
        the main test's to see), and is no speck of the board."""
        from scipy import ndimage

        mm = self.wppm
        v = ndimage.maximum_filter1d(values, 3, axis=0, mode="nearest")  # (a thin thing slants across the bands)
        across = (v >= low).all(axis=2) & (v.min(axis=2) >= CROSS_FLAT * v.max(axis=2))
        for k in (0, 1):
            for a, b in _stretches(across[:, k]):
                if b - a > CROSS_MM * mm:
                    across[a:b, k] = False
        if not _runs_on(across, need):
            return False
        runs = np.repeat(across[:, :, None], 3, axis=2)
        self._drop_specks(runs, band, line, half, low, level, need)
        return _runs_on(runs, need)

    def _drop_specks(self, runs: np.ndarray, band: np.ndarray, line: np.ndarray, half: float, board: float,
                     level: float, need: int) -> None:
        """Clear from `runs` (hits beside the span at the points `band`: rows along `line`, its two
        sides, the bands out from it) what is only a speck of the board's texture: on one side, a
        stretch of hits no longer than SPECK_MM along the wire, all of it on specks (_specks).
        (Only stretches that hold `need` hits in a row in one band are looked at: no others count.)"""
        mm = self.wppm
        for k in (0, 1):
            seen = runs[:, k, :].any(axis=1)
            if not seen.any():
                continue
            for a, b in _stretches(seen):  # each stretch of hits, rows a to b - 1
                if b - a > self.speck()[1] * mm or not _runs_on(runs[a:b, k:k + 1, :], need):
                    continue
                specks = self._specks(band[(a + b - 1) // 2, k, 1], 3.0 * mm, line, half, board, level)
                if specks(band[a:b, k].reshape(-1, 2))[runs[a:b, k, :].reshape(-1)].all():
                    runs[a:b, k, :] = False

    def _specks(self, at: np.ndarray, radius: float, line: np.ndarray, half: float, board: float, level: float):
        """Which points lie on specks of the board's texture near `at` (working px): a function of
        (N, 2) points. A speck stands out over SPECK_TRACE of the board's threshold, clear of the wire being read
        (farther than half its width and 0.5 mm from its centre line `line`, its blurred edge, or
        standing out more than its contrast `level` there: another wire touching it), and is small: all
        of it within SPECK_MM / 2 of its middle, and inside the square `radius` round `at`.
        Anything that can touch a wire or the fingers and matter (another wire, its end, a
        tray's rim, a thing lying there) is larger."""
        from scipy import ndimage

        mm = self.wppm
        size = 2 * int(radius) + 1
        r0, c0 = int(round(at[0])) - int(radius), int(round(at[1])) - int(radius)
        grid = np.mgrid[r0:r0 + size, c0:c0 + size].reshape(2, -1).T.astype(float)
        near = line[(np.abs(line - at) <= radius + half + mm).all(axis=1)]
        seen = self._seen(grid)
        trace, most = self.speck()
        on = seen >= trace * board  # (a faint wire's pieces over the threshold joined)
        if len(near):  # (what stands out more than the wire does there is not the wire)
            d2 = ((grid[:, None, :] - near[None, :, :]) ** 2).sum(axis=2).min(axis=1)
            on &= (d2 > (half + 0.5 * mm) ** 2) | (seen > level)
        pieces, count = ndimage.label(on.reshape(size, size), np.ones((3, 3)))
        small = np.zeros(count + 1, bool)
        for i, box in enumerate(ndimage.find_objects(pieces), start=1):
            if box is None or box[0].start == 0 or box[1].start == 0 or box[0].stop == size or box[1].stop == size:
                continue
            rc = np.argwhere(pieces[box] == i)
            small[i] = bool((((rc - rc.mean(axis=0)) ** 2).sum(axis=1) <= (most / 2 * mm) ** 2).all())
        speck = _grown(small[pieces]) if small.any() else np.zeros((size, size), bool)  # (a sample between pixels)

        def on_speck(pts: np.ndarray) -> np.ndarray:
            rc = np.round(pts).astype(int) - (r0, c0)
            inside = (rc >= 0).all(axis=1) & (rc < size).all(axis=1)
            out = np.zeros(len(pts), bool)
            out[inside] = speck[rc[inside, 0], rc[inside, 1]]
            return out

        return on_speck

    def clutter(self, span, tip, out, width, board) -> float:
        """How near something comes to a free end: the most contrast, relative to the board's
        threshold, in bands ROOM_BAND_MM out from the wire's edges along its span (each band's
        ROOM_PERCENTILE), on arcs ROOM_CAP_MM beyond its tip (the most), and in the disc round
        the grasp point (its ROOM_PERCENTILE). 1 or more: something as strong as the threshold
        for a thing there comes that near (within the free test's bands only if it is too
        small or too short to count there)."""
        mm = self.wppm
        half = width / 2
        line, n, disc = span
        worst = []
        for d in ROOM_BAND_MM:
            off = half + d * mm
            band = np.vstack((line + off * n, line - off * n))
            worst.append(np.percentile(self._seen(band), ROOM_PERCENTILE))
        cap = (tip[None, None, :] + (half + np.array(ROOM_CAP_MM) * mm)[:, None, None] * _fan(out)[None, :, :])
        worst.append(self._seen(cap.reshape(-1, 2)).max())
        if len(disc):
            worst.append(np.percentile(self._seen(disc), ROOM_PERCENTILE))
        return float(max(worst)) / board

    def line_near(self, span, width) -> float:
        """How near (mm) another centre line comes to the wire's edge along its span (inf: none
        within LINE_NEAR_MM and a pixel of it, across or along): pixels of the centre lines within
        that reach, less the wire's own (within half its width and 1 mm of its line, or nearest its
        first or last point: its line going on)."""
        mm = self.wppm
        line = span[0]
        if len(line) < 3:
            return math.inf
        half = width / 2
        reach = half + LINE_NEAR_MM * mm + 1.0
        lo = np.maximum(np.floor(line.min(axis=0) - reach).astype(int), 0)
        hi = np.ceil(line.max(axis=0) + reach).astype(int) + 1
        win = self.g.skeleton[lo[0]:hi[0], lo[1]:hi[1]]
        pix = np.column_stack(np.nonzero(win)).astype(float) + lo
        if not len(pix):
            return math.inf
        d2 = ((pix[:, None, :] - line[None, :, :]) ** 2).sum(axis=2)
        j = d2.argmin(axis=1)
        d = np.sqrt(d2[np.arange(len(pix)), j])
        other = (d > half + mm) & (j > 0) & (j < len(line) - 1)
        if not other.any():
            return math.inf
        return float(d[other].min() - half) / mm

    def _seen(self, pts: np.ndarray, shadows: bool = True) -> np.ndarray:
        """around() at the points (or F, if not shadows); nothing where they fall off the image or
        within RIM_EDGE_MM of a rim or the bench round the tray (which is neither board nor a thing
        there)."""
        inside = self._in_frame(pts)
        if self.rim is not None:
            inside &= ~self.off_tray(pts, RIM_EDGE_MM * self.wppm)
        return np.where(inside, self.around(pts) if shadows else self.sample(pts), 0.0)

    def centred(self, grasp, tangent, width) -> np.ndarray:
        """The grasp point moved across the wire to the middle of its contrast."""
        n = np.array([-tangent[1], tangent[0]])
        offs = np.arange(-width, width + 0.01, 0.25)
        prof = self.sample(grasp + offs[:, None] * n)
        wts = np.clip(prof - 0.5 * prof.max(), 0, None)
        if wts.sum() <= 0:
            return grasp
        shift = float((wts * offs).sum() / wts.sum())
        return grasp + np.clip(shift, -0.5 * width, 0.5 * width) * n

    def sighting(self, tip, inward, grasp, tangent, score) -> Sighting:
        k = self.k

        def to_input(p):
            return ((p[1] + 0.5) * k - 0.5, (p[0] + 0.5) * k - 0.5)

        end_angle = math.degrees(math.atan2(inward[0], inward[1]))
        grasp_angle = math.degrees(math.atan2(tangent[0], tangent[1])) % 180.0
        return Sighting(to_input(tip), end_angle, to_input(grasp), grasp_angle, score)


def unsteadiness(widths: np.ndarray) -> float:
    """How much a wire's widths measured at several places differ: their range, or OUTLIER_SPREAD
    times the range of all but the narrowest, if less (one place where a flank meets a patch of
    the board of its own tone reads narrower; one that reads wider may be a neighbour touching)."""
    r = np.sort(np.asarray(widths, float))
    if len(r) < 3:
        return float(r[-1] - r[0]) if len(r) else 0.0
    return float(min(r[-1] - r[0], OUTLIER_SPREAD * (r[-1] - r[1])))


def specks_per_cm2(f: np.ndarray, wppm: float, outside: np.ndarray | None = None) -> float:
    """How many specks a square cm of the tray holds: places where the contrast f stands
    BOARD_FLOOR or more, each no more than SPECK_MM across (8-connected), over the area not
    `outside` it."""
    from scipy import ndimage

    on = f >= BOARD_FLOOR
    if outside is not None:
        on &= ~outside
    pieces, count = ndimage.label(on, np.ones((3, 3)))
    if not count:
        return 0.0
    r, c = np.nonzero(pieces)
    order = np.argsort(pieces[r, c], kind="stable")
    r, c = r[order], c[order]
    first = np.flatnonzero(np.diff(pieces[r, c], prepend=0))  # where each piece's pixels start
    tall = np.maximum.reduceat(r, first) - np.minimum.reduceat(r, first) + 1
    wide = np.maximum.reduceat(c, first) - np.minimum.reduceat(c, first) + 1
    small = int(np.count_nonzero((tall <= SPECK_MM * wppm) & (wide <= SPECK_MM * wppm)))
    area = (on.size - (np.count_nonzero(outside) if outside is not None else 0)) / (10.0 * wppm) ** 2
    return small / max(area, 1e-9)


def _across_tip(width: float, mm: float) -> np.ndarray:
    """Where conductor() and flanks() sample across a wire (px from its axis): the middle (0.2 of
    its width apart), the board 1 mm past its edges, its flanks 0.45 of its width out."""
    return np.array([-0.2 * width, 0.0, 0.2 * width, -(width / 2 + mm), width / 2 + mm, -0.45 * width, 0.45 * width])


def _grown(mask: np.ndarray) -> np.ndarray:
    """A 2-d mask dilated by a 3 x 3 square (as scipy's binary_dilation with np.ones((3, 3)),
    without its cost on the small windows it is used on)."""
    h, w = mask.shape
    padded = np.pad(mask, 1)
    out = np.zeros_like(mask)
    for dr in range(3):
        for dc in range(3):
            out |= padded[dr:dr + h, dc:dc + w]
    return out


def _stretches(mask: np.typing.ArrayLike) -> list[tuple[int, int]]:
    """Each run of True in a 1-d mask, as (first index, one past the last)."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], np.asarray(mask, np.int8), [0]))))
    return list(zip(edges[::2].tolist(), edges[1::2].tolist()))


def _runs_on(hits: np.ndarray, need: int) -> bool:
    """Whether `need` hits lie in a row down any one column of hits (rows along the span, then
    any other axes: its sides and bands)."""
    cols = hits.reshape(len(hits), -1)
    if len(cols) < need:
        return False
    c = np.cumsum(np.vstack([np.zeros((1, cols.shape[1]), int), cols]), axis=0)
    return int((c[need:] - c[:-need]).max()) >= need


def _drop(along: np.ndarray, scan_s: np.ndarray, edge: float) -> float | str:
    """Where `along` (contrast sampled outward from inside a wire, at arc lengths scan_s) first
    falls below `edge` for two samples running, between samples; or why it does not."""
    below = along < edge
    gone = np.flatnonzero(below[:-1] & below[1:])
    if not gone.size:
        return "its contrast runs on past its end (under or into something)"
    i = int(gone[0])
    if i == 0:
        return "no wire to be seen at its end"
    a, b = along[i - 1], along[i]
    frac = float(np.clip((a - edge) / max(a - b, 1e-6), 0, 1))
    return float(scan_s[i - 1] + frac * (scan_s[i] - scan_s[i - 1]))


def _sharpest_turn(full: np.ndarray, s: np.ndarray, mm: float) -> float | None:
    """Where (arc length from the tip) the centre line `full` (1 px steps, arc lengths s) turns by
    more than KINK_DEG between its chords KINK_MM long before and after a point, over the span and
    its slack from KINK_FROM_MM on (the tip's own hook is tip_axis's), or None."""
    w = max(int(round(KINK_MM * mm)), 2)
    m = int(np.count_nonzero(s <= (SPAN_MM + SPAN_SLACK_MM) * mm))
    i = np.arange(w, m - w)
    i = i[s[i] >= KINK_FROM_MM * mm]
    if not len(i):
        return None
    a = full[i] - full[i - w]
    b = full[i + w] - full[i]
    cos = (a * b).sum(axis=1) / np.maximum(np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1), 1e-9)
    k = int(np.argmin(cos))
    return float(s[i[k]]) if cos[k] < math.cos(math.radians(KINK_DEG)) else None


def tip_axis(head: np.ndarray, tip: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The unit direction into the wire at its tip, the chord of the centre line's head (the
    first few mm past the tip), and the tip put on that axis (a hooked ridge end is off it)."""
    chord = principal_direction(head)
    if chord @ (head[-1] - head[0]) < 0:
        chord = -chord
    middle = head.mean(axis=0)
    return chord, middle + chord * float((tip - middle) @ chord)


_FAN = np.radians(np.linspace(-70, 70, 9))


def _fan(out: np.ndarray) -> np.ndarray:
    """Unit directions within 70 degrees either side of out."""
    c, s = np.cos(_FAN), np.sin(_FAN)
    return np.column_stack([out[0] * c - out[1] * s, out[0] * s + out[1] * c])


@lru_cache(maxsize=16)
def _disc_template(radius10: int) -> np.ndarray:
    radius = radius10 / 10.0
    grid = np.arange(-radius, radius + 0.01, 0.75)
    a, b = np.meshgrid(grid, grid)
    inside = a * a + b * b <= radius * radius
    return np.column_stack([a[inside], b[inside]])


def _disc(radius: float) -> np.ndarray:
    """Points 0.75 px apart filling a disc of the radius (px) round the origin."""
    return _disc_template(round(radius * 10))


def _on_itself(pts: np.ndarray, at: np.ndarray, line: np.ndarray, half: float, reach: float) -> np.ndarray:
    """Which points lie nearer than half to the polyline `line` (1 px steps) within reach px along
    it of line[at] (each point's own place on it, where it was sampled round): on the wire itself,
    where its line bends. (A part of the same wire farther along that comes back beside it is not itself.)"""
    m = int(math.ceil(reach))
    j = np.clip(at[:, None] + np.arange(-m, m + 1)[None, :], 0, len(line) - 1)
    d2 = ((line[j] - pts[:, None, :]) ** 2).sum(axis=2)
    return d2.min(axis=1) < half * half


def _normals(line: np.ndarray) -> np.ndarray:
    """The unit normal (row, col) at each point of a polyline, from its central differences."""
    t = np.empty_like(line, dtype=float)  # (np.gradient's values, without its cost on short lines)
    if len(line) < 2:
        t[:] = 0.0
    else:
        t[1:-1] = (line[2:] - line[:-2]) / 2.0
        t[0] = line[1] - line[0]
        t[-1] = line[-1] - line[-2]
    size = np.sqrt(t[:, 0] * t[:, 0] + t[:, 1] * t[:, 1])
    np.maximum(size, 1e-9, out=size)
    return np.column_stack([-t[:, 1] / size, t[:, 0] / size])


def _arc(pts: np.ndarray) -> np.ndarray:
    """The arc length along a polyline at each of its points, from 0 at the first."""
    d = pts[1:] - pts[:-1]
    out = np.zeros(max(len(pts), 1))  # (an empty polyline: [0], as before)
    np.cumsum(np.sqrt(d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1]), out=out[1:])
    return out


def _resample(pts: np.ndarray, step: float) -> np.ndarray:
    """A polyline sampled every `step` along it, up to (not past) its length: unlike
    synth.resample it never repeats the last point, so directions along it stay defined."""
    cum = _arc(pts)
    s = np.arange(0.0, cum[-1] + 1e-9, step)
    return np.column_stack([np.interp(s, cum, pts[:, 0]), np.interp(s, cum, pts[:, 1])])
