"""Vision: the grey-scale system against the generated trays' ground truth, both systems on
any scale, and bad images of every kind (a clear error or an empty result, never a crash)."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import assert_both_ends_at_tips, lit_wires

from rcl.vision import VisionError, find_wires
from rcl.vision.grey import STEPS, chain_points, edge_at, edges, find_wires_grey
from rcl.vision.synth import KINDS, make_tray


def bar_image(end=(100.0, 200.0), angle_deg=20.0, length=600.0, width=8.0, size=512):
    """A dark straight bar on a light tray, one end at `end` (u, v), running off at angle_deg."""
    v, u = np.mgrid[0:size, 0:size] + 0.5
    d = np.array([math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))])
    along = (u - end[0]) * d[0] + (v - end[1]) * d[1]
    across = np.abs(-(u - end[0]) * d[1] + (v - end[1]) * d[0])
    inside = np.clip(along + 0.5, 0, 1) * np.clip(length - along + 0.5, 0, 1) * np.clip(width / 2 - across + 0.5, 0, 1)
    return 0.8 - 0.6 * inside


@pytest.mark.slow
@pytest.mark.parametrize("kind", KINDS)
def test_grey_first_pick_is_correct_on_nearly_every_tray(kind):
    verdicts = [make_tray(kind, seed).judge((find_wires_grey(make_tray(kind, seed).image).candidates or [None])[0])[0]
                for seed in range(12)]
    assert verdicts.count("correct") >= 11, verdicts
    assert verdicts.count("foul") <= 1, verdicts


def test_grey_places_a_bar_end_exactly():
    res = find_wires_grey(bar_image())
    s = res.candidates[0]
    assert math.dist(s.end, (100.0, 200.0)) < 1.5  # px: under 0.4 mm
    assert abs(s.end_angle - 20.0) < 2.0
    assert abs(s.grasp_angle - 20.0) < 2.0
    assert abs(math.dist(s.grasp, s.end) - 60.0) < 2.0  # 15 mm at 4 px/mm
    assert len(res.candidates) == 1  # the other end is 600 px on, past the border


def test_prewitt_on_demand_matches_the_whole_image_filter():
    img = make_tray("crossing", 2).image[::2, ::2]
    gc, gr = edges(img)
    for r, c in [(10, 10), (100, 37), (200, 250)]:
        assert edge_at(img, r, c) == pytest.approx((gc[r, c], gr[r, c]), abs=1e-6)
    # a ramp of slope 0.01 per column: d/dcolumn = 0.01, d/drow = 0
    ramp = np.tile(np.arange(20) * 0.01, (20, 1))
    assert edge_at(ramp, 5, 5) == pytest.approx((0.01, 0.0))


def test_boundaries_are_freeman_chains_and_an_isolated_wire_closes():
    res = find_wires_grey(bar_image(end=(150.0, 150.0), length=160.0))
    (start, codes), = res.chains
    pts = chain_points(start, codes)
    steps = np.diff(pts, axis=0)
    assert {tuple(s) for s in steps.astype(int).tolist()} <= set(STEPS)
    assert np.abs(pts[0] - pts[-1]).max() <= 1  # round the whole wire and back
    assert len(res.candidates) == 2  # both ends


@pytest.mark.parametrize("blur", [0.0, 2.0])
def test_grey_passes_over_an_ends_own_blurred_edge_in_front_of_it(blur):
    """A lone round black wire casting a soft shadow, sharp or slightly out of focus: in front of
    its end face the grey rises to the tray's over more than the 2.5 px where the isolation test
    looked for other things, and that rise (an edge going on away from the wire's level, ending
    where the tray is flat) is the end's own edge, not something beyond it. Before it was passed
    over, one of the two ends was refused as not isolated."""
    from scipy import ndimage

    image, (centre,) = lit_wires([((30.0, 40.0), 25.0, 70.0, 2.0)], board=0.8, gloss=0.3, shadow=0.25)
    res = find_wires_grey(ndimage.gaussian_filter(image, blur) if blur else image, 4.0)
    assert_both_ends_at_tips(res.candidates, centre)


@pytest.mark.slow
@pytest.mark.parametrize("method", ["grey", "binary"])
@pytest.mark.parametrize("px_per_mm", [2.0, 8.0])
def test_any_scale(method, px_per_mm):
    # the same sparse trays drawn at another scale: the finders take px/mm, not a fixed size
    good = 0
    for seed in range(6):
        tray = make_tray("sparse", seed, size=int(128 * px_per_mm), px_per_mm=px_per_mm)
        res = find_wires(tray.image, method, px_per_mm)
        good += tray.judge(res.candidates[0] if res.candidates else None)[0] == "correct"
    assert good >= 5


@pytest.mark.parametrize("method", ["grey", "binary"])
def test_hopeless_images_give_an_empty_result(method):
    rng = np.random.default_rng(3)
    for image in [np.zeros((0, 0)), np.zeros((1, 7)), np.zeros((3, 3)), np.full((64, 64), 0.5),
                  np.full((512, 512), 1.0), rng.uniform(size=(256, 256)), rng.normal(0.5, 0.3, (300, 200)),
                  (rng.uniform(size=(128, 128)) > 0.5).astype(float), np.zeros((512, 5)),
                  rng.integers(0, 65535, (128, 128), dtype=np.uint16)]:
        assert find_wires(image, method).candidates == []


@pytest.mark.parametrize("method", ["grey", "binary"])
def test_other_image_types_are_read_as_grey(method):
    tray = make_tray("sparse", 4)
    as16 = (tray.image * 65535).round().astype(np.uint16)
    as8 = (tray.image * 255).round().astype(np.uint8)
    rgb = np.repeat(as8[..., None], 3, axis=2)
    for image in (as16, as8, rgb, tray.image.astype(np.float32)):
        res = find_wires(image, method)
        assert tray.judge(res.candidates[0] if res.candidates else None)[0] == "correct"


def test_bad_arrays_and_arguments_are_clear_errors():
    from rcl.camera import ImageError

    with pytest.raises(ImageError, match="not finite"):
        find_wires(np.full((64, 64), np.nan))
    with pytest.raises(ImageError, match="rows x columns"):
        find_wires(np.zeros((4, 4, 4, 4)))
    with pytest.raises(VisionError, match="unknown method"):
        find_wires(np.zeros((64, 64)), "sonar")
    with pytest.raises(VisionError, match="must be 0.5 to 100 px per mm"):
        find_wires(np.zeros((64, 64)), "grey", 0.0)


@pytest.mark.slow
def test_a_huge_image_is_handled(capsys):
    tray = make_tray("sparse", 1, size=2048, px_per_mm=16.0)
    res = find_wires(tray.image, "grey", 16.0)
    assert tray.judge(res.candidates[0] if res.candidates else None)[0] == "correct"


def test_cli_json_contract_and_overlay(tmp_path):
    from PIL import Image

    from rcl.cli import main

    tray = make_tray("crossing", 5)
    Image.fromarray((tray.image * 255).round().astype(np.uint8)).save(tmp_path / "a.png")
    (tmp_path / "bad.png").write_bytes(b"\x89PNG\r\n\x1a\n not really")
    (tmp_path / "notes.txt").write_text("hello")
    import contextlib
    import io

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["vision", str(tmp_path / "a.png"), str(tmp_path / "bad.png"), str(tmp_path / "notes.txt"),
                     "--json", "--overlay", str(tmp_path / "pics"), "--method", "grey"])
    assert code == 2  # two images could not be read
    lines = [json.loads(line) for line in out.getvalue().splitlines()]
    assert [x["image"] for x in lines] == [str(tmp_path / n) for n in ("a.png", "bad.png", "notes.txt")]
    good = lines[0]
    assert good["method"] == "grey" and good["time_ms"] > 0
    w = good["wires"][0]
    assert set(w) >= {"end", "end_angle", "grasp", "grasp_angle"} and 0 <= w["grasp_angle"] < 180
    assert -180 <= w["end_angle"] <= 180
    assert "error" in lines[1] and "error" in lines[2] and "Traceback" not in err.getvalue()
    assert (tmp_path / "pics" / "a.png").exists()
    picture = Image.open(tmp_path / "pics" / "a.png")
    assert picture.size[0] == 512 and 512 < picture.size[1] <= 512 + 40 and picture.mode == "RGB"  # + the legend


def test_grey_does_not_take_a_wires_own_shadow_for_another_wire():
    """A lamp to one side: the wire's soft shadow shows a faint edge beside it, which the
    isolation test counted as another wire within a finger's clearance (both ends refused)."""
    image, (centre,) = lit_wires([((30.0, 50.0), 10.0, 70.0, 2.5)], gloss=0.0, shadow=0.2, lamp=(0.0, -0.6, 0.8))
    res = find_wires_grey(image, 4.0)
    for tip in (centre[0], centre[-1]):
        assert any(np.linalg.norm(np.array(s.end) / 4.0 - tip) < 1.0 for s in res.candidates), res.looks.rejected
    # the same edge where another wire lies: still not free
    image, lines = lit_wires([((30.0, 50.0), 10.0, 70.0, 2.5), ((30.0, 54.5), 10.0, 70.0, 1.0)], gloss=0.0,
                             shadow=0.2, lamp=(0.0, -0.6, 0.8))
    res = find_wires_grey(image, 4.0)
    assert not any(np.linalg.norm(np.array(s.end) / 4.0 - lines[0][0]) < 2.0 for s in res.candidates)
