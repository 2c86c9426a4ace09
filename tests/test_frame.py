"""The Frame value type against independent references (closed forms, plain numpy)."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from rcl.frame import Frame, FrameError, vec

angles = st.floats(-720, 720, allow_nan=False)
coords = st.floats(-1e4, 1e4, allow_nan=False)


def rz(deg):
    t = math.radians(deg)
    return np.array([[math.cos(t), -math.sin(t), 0], [math.sin(t), math.cos(t), 0], [0, 0, 1]])


def ry(deg):
    t = math.radians(deg)
    return np.array([[math.cos(t), 0, math.sin(t)], [0, 1, 0], [-math.sin(t), 0, math.cos(t)]])


def rx(deg):
    t = math.radians(deg)
    return np.array([[1, 0, 0], [0, math.cos(t), -math.sin(t)], [0, math.sin(t), math.cos(t)]])


def rodrigues(axis, deg):
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    t = math.radians(deg)
    return np.eye(3) + math.sin(t) * K + (1 - math.cos(t)) * K @ K


def test_paul_textbook_example():
    # Paul, Robot Manipulators, ch. 1: u = 7i + 3j + 2k rotated by 90 degrees about z gives
    # (-3, 7, 2), then by 90 degrees about y gives (2, 7, 3): Rot(y,90) Rot(z,90) u.
    np.testing.assert_allclose(Frame.rotz(90) * vec(7, 3, 2), [-3, 7, 2], atol=1e-12)
    np.testing.assert_allclose(Frame.roty(90) * Frame.rotz(90) * vec(7, 3, 2), [2, 7, 3], atol=1e-12)
    # Trans(4, -3, 7) Rot(y, 90) Rot(z, 90): Paul's frame with n=(0,1,0), o=(0,0,1), a=(1,0,0)
    g = Frame.trans(4, -3, 7) * Frame.roty(90) * Frame.rotz(90)
    np.testing.assert_allclose(g.n, [0, 1, 0], atol=1e-12)
    np.testing.assert_allclose(g.o, [0, 0, 1], atol=1e-12)
    np.testing.assert_allclose(g.a, [1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(g.p, [4, -3, 7])


@given(angles, angles, angles)
def test_elementary_rotations_and_rpy_euler_match_closed_forms(a, b, c):
    np.testing.assert_allclose(Frame.rotx(a).matrix[:3, :3], rx(a), atol=1e-12)
    np.testing.assert_allclose(Frame.roty(b).matrix[:3, :3], ry(b), atol=1e-12)
    np.testing.assert_allclose(Frame.rotz(c).matrix[:3, :3], rz(c), atol=1e-12)
    np.testing.assert_allclose(Frame.rpy(a, b, c).matrix[:3, :3], rz(c) @ ry(b) @ rx(a), atol=1e-12)
    np.testing.assert_allclose(Frame.euler(a, b, c).matrix[:3, :3], rz(a) @ ry(b) @ rz(c), atol=1e-12)


@given(st.tuples(coords, coords, coords).filter(lambda k: np.linalg.norm(k) > 1e-3), angles)
def test_rot_about_any_axis_is_rodrigues(axis, deg):
    np.testing.assert_allclose(Frame.rot(axis, deg).matrix[:3, :3], rodrigues(axis, deg), atol=1e-9)


@given(coords, coords, coords, angles, angles, angles)
def test_closed_form_inverse_matches_numpy(x, y, z, a, b, c):
    f = Frame.trans(x, y, z) * Frame.rpy(a, b, c)
    np.testing.assert_allclose(f.inv().matrix, np.linalg.inv(f.matrix), atol=1e-8)
    np.testing.assert_allclose((f * f.inv()).matrix, np.eye(4), atol=1e-9)
    assert f.inv() is f.inv()  # kept: a frame never changes


@pytest.mark.parametrize("n", [2, 3, 4, 5, 7])
def test_a_chain_of_frame_products_in_rcl_matches_numpy(n):
    """The interpreter multiplies a chain of frames in one closure (2-4 factors written out, more
    in a loop), INVs among them: against numpy's own products and inverse."""
    import io

    from rcl import Session

    rng = np.random.default_rng(n)
    frames = [Frame.trans(*rng.uniform(-100, 100, 3)) * Frame.rpy(*rng.uniform(-180, 180, 3)) for _ in range(n)]
    s = Session(out=io.StringIO())
    for i, f in enumerate(frames):
        s[f"F{i}^"] = f
    s.run("P^ := " + " * ".join(f"INV(F{i}^)" if i % 2 else f"F{i}^" for i in range(n)))
    want = np.eye(4)
    for i, f in enumerate(frames):
        want = want @ (np.linalg.inv(f.matrix) if i % 2 else f.matrix)
    np.testing.assert_allclose(s["P^"].matrix, want, atol=1e-9)


@given(coords, coords, coords, angles, angles, coords, coords, coords)
def test_composition_and_points_match_numpy(x, y, z, a, b, u, v, w):
    f = Frame.trans(x, y, z) * Frame.rotx(a)
    g = Frame.roty(b) * Frame.trans(u, v, w)
    np.testing.assert_allclose((f * g).matrix, f.matrix @ g.matrix, atol=1e-9)
    np.testing.assert_allclose(f * vec(u, v, w), (f.matrix @ [u, v, w, 1])[:3], atol=1e-8)


def test_rotations_are_exact_at_right_angles():
    assert np.array_equal(Frame.rotz(90).matrix[:3, :3], [[0, -1, 0], [1, 0, 0], [0, 0, 1]])
    assert np.array_equal(Frame.rotx(-270).matrix[:3, :3], rx(90).round())


def test_from_columns_validates_orthonormal_right_handed():
    f = Frame.from_columns([0, 1, 0], [-1, 0, 0], [0, 0, 1], [1, 2, 3])
    np.testing.assert_allclose(f.matrix, Frame.trans(1, 2, 3).matrix @ Frame.rotz(90).matrix)
    with pytest.raises(FrameError, match="orthonormal"):
        Frame.from_columns([1, 0, 0], [1, 0, 0], [0, 0, 1], [0, 0, 0])
    with pytest.raises(FrameError, match="right-handed"):
        Frame.from_columns([1, 0, 0], [0, 1, 0], [0, 0, -1], [0, 0, 0])
    with pytest.raises(FrameError, match="orthonormal"):
        Frame.from_columns([1, 0, 0], [0, 1, 0], [0, 0, 1 + 2e-6], [0, 0, 0])
    Frame.from_columns([1, 0, 0], [0, 1, 0], [0, 0, 1 + 5e-7], [0, 0, 0])  # within 1e-6


def test_frames_are_immutable_values():
    f = Frame.trans(1, 2, 3)
    with pytest.raises(ValueError):
        f.matrix[0, 3] = 5
    with pytest.raises(ValueError):
        f.p[0] = 5
    assert f == Frame.trans(1, 2, 3) and f != Frame.trans(1, 2, 4)
    with pytest.raises(FrameError):
        Frame(np.ones((3, 3)))
    with pytest.raises(FrameError):
        Frame(np.full((4, 4), np.nan))


@given(angles, angles, angles)
def test_rpy_angles_round_trip(r, p, y):
    f = Frame.rpy(r, p, y)
    back = Frame.rpy(*f.rpy_angles())
    np.testing.assert_allclose(back.matrix, f.matrix, atol=1e-9)
