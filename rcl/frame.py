"""Frames: rigid homogeneous transforms as small immutable values.

Convention, stated once: a Frame is the 4x4 matrix [[n o a p], [0 0 0 1]] of
R. Paul's *Robot Manipulators*, whose columns n, o, a are the unit axes of a
coordinate frame and p its origin, all described in the frame it is relative
to. Composition is matrix multiplication, left to right as written:
``A * B`` is B described in the frame A is described in, and ``F * v``
transforms the point v. Lengths are in millimetres, angles in degrees.
Vectors are numpy arrays of shape (3,).

The type knows nothing of RCL and is usable from plain Python.
"""
from __future__ import annotations

import math

import numpy as np

Vector = np.ndarray
"""A 3-vector in millimetres: a numpy array of shape (3,), never mutated."""

ORTHONORMAL_TOLERANCE = 1e-6

_BOTTOM = np.array([0.0, 0.0, 0.0, 1.0])


def vec(x: float, y: float, z: float) -> Vector:
    """A read-only 3-vector."""
    v = np.array((x, y, z), dtype=float)
    v.flags.writeable = False
    return v


class FrameError(ValueError):
    """A matrix that is not a rigid homogeneous transform."""


class Frame:
    """An immutable rigid transform (see the module docstring for conventions)."""

    __slots__ = ("_m", "_inv")
    _m: np.ndarray
    _inv: Frame  # the inverse, once asked for (a frame never changes)

    def __init__(self, matrix) -> None:
        """Wrap a 4x4 matrix, checking that it is a rigid transform."""
        m = np.array(matrix, dtype=float)
        if m.shape != (4, 4):
            raise FrameError(f"a frame is a 4x4 matrix, not shape {m.shape}")
        if not np.all(np.isfinite(m)):
            raise FrameError("a frame's entries must be finite numbers")
        if not np.allclose(m[3], _BOTTOM, rtol=0.0, atol=ORTHONORMAL_TOLERANCE):
            raise FrameError("a frame's bottom row must be 0 0 0 1")
        check_rotation(m[:3, :3])
        m[3] = _BOTTOM
        m.flags.writeable = False
        self._m = m

    @classmethod
    def trusted(cls, m: np.ndarray) -> Frame:
        """Wrap a matrix known to be rigid, unchecked: for the results of frame algebra (a
        product of frames, an inverse), which are rigid by construction. m becomes read-only."""
        f = object.__new__(cls)
        m.flags.writeable = False
        f._m = m
        return f

    # Named constructors -------------------------------------------------

    @classmethod
    def identity(cls) -> Frame:
        return cls.trusted(np.eye(4))

    @classmethod
    def trans(cls, x: float, y: float, z: float) -> Frame:
        if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(z)):
            raise FrameError(f"a translation must be finite, not ({x:g}, {y:g}, {z:g})")
        m = np.eye(4)
        m[0, 3], m[1, 3], m[2, 3] = x, y, z
        return cls.trusted(m)

    @classmethod
    def rotx(cls, deg: float) -> Frame:
        c, s = _cos_sin(deg)
        return cls._from_rotation(np.array(((1.0, 0.0, 0.0), (0.0, c, -s), (0.0, s, c))))

    @classmethod
    def roty(cls, deg: float) -> Frame:
        c, s = _cos_sin(deg)
        return cls._from_rotation(np.array(((c, 0.0, s), (0.0, 1.0, 0.0), (-s, 0.0, c))))

    @classmethod
    def rotz(cls, deg: float) -> Frame:
        c, s = _cos_sin(deg)
        return cls._from_rotation(np.array(((c, -s, 0.0), (s, c, 0.0), (0.0, 0.0, 1.0))))

    @classmethod
    def rot(cls, axis, deg: float) -> Frame:
        """A rotation by deg about the axis through the origin (right-hand rule)."""
        from scipy.spatial.transform import Rotation

        k = np.asarray(axis, dtype=float)
        length = float(np.linalg.norm(k))
        if not length > 0.0 or not math.isfinite(length):
            raise FrameError("the axis of a rotation must be a non-zero vector")
        rotvec = k / length * math.radians(deg)
        return cls._from_rotation(Rotation.from_rotvec(rotvec).as_matrix())

    @classmethod
    def rpy(cls, roll: float, pitch: float, yaw: float) -> Frame:
        """ROTZ(yaw) * ROTY(pitch) * ROTX(roll)."""
        return cls.rotz(yaw) * cls.roty(pitch) * cls.rotx(roll)

    @classmethod
    def euler(cls, phi: float, theta: float, psi: float) -> Frame:
        """ROTZ(phi) * ROTY(theta) * ROTZ(psi)."""
        return cls.rotz(phi) * cls.roty(theta) * cls.rotz(psi)

    @classmethod
    def from_columns(cls, n, o, a, p) -> Frame:
        """The frame with axes n, o, a and origin p; the axes must be orthonormal and right-handed."""
        m = np.eye(4)
        m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = n, o, a, p
        return cls(m)

    @classmethod
    def _from_rotation(cls, r: np.ndarray) -> Frame:
        m = np.eye(4)
        m[:3, :3] = r
        return cls.trusted(m)

    # Algebra ------------------------------------------------------------

    def __mul__(self, other):
        if isinstance(other, Frame):
            return Frame.trusted(self._m @ other._m)
        if isinstance(other, np.ndarray) and other.shape == (3,):
            return self.apply(other)
        return NotImplemented

    def apply(self, v: Vector) -> Vector:
        """The point v transformed by this frame."""
        m = self._m
        out = m[:3, :3] @ v + m[:3, 3]
        out.flags.writeable = False
        return out

    def inv(self) -> Frame:
        """The inverse, in closed form: [R^T, -R^T p]; kept, as a program inverts the same base
        and tool frames over and over (INV(Z^) * ... * INV(E^) in every cycle)."""
        try:
            return self._inv
        except AttributeError:
            pass
        m = self._m
        out = m.T.copy()
        out[:3, 3] = -(out[:3, :3] @ m[:3, 3])
        out[3, :3] = 0.0
        self._inv = inverse = Frame.trusted(out)
        return inverse

    # Access -------------------------------------------------------------

    @property
    def matrix(self) -> np.ndarray:
        """The 4x4 matrix (read-only)."""
        return self._m

    @property
    def n(self) -> Vector:
        return self._m[:3, 0]

    @property
    def o(self) -> Vector:
        return self._m[:3, 1]

    @property
    def a(self) -> Vector:
        return self._m[:3, 2]

    @property
    def p(self) -> Vector:
        return self._m[:3, 3]

    def with_p(self, p: Vector) -> Frame:
        """The same axes with another origin."""
        m = self._m.copy()
        m[:3, 3] = p
        return Frame.trusted(m)

    def dist(self, other: Frame) -> float:
        """Distance between the two origins."""
        d = self._m[:3, 3] - other._m[:3, 3]
        return math.sqrt(float(d @ d))

    def rpy_angles(self) -> tuple[float, float, float]:
        """(roll, pitch, yaw) in degrees with self.rotation = RPY(roll, pitch, yaw)."""
        import warnings

        from scipy.spatial.transform import Rotation

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # gimbal lock: scipy then sets roll to 0, which is fine
            yaw, pitch, roll = Rotation.from_matrix(self._m[:3, :3]).as_euler("ZYX", degrees=True)
        return _clean(roll), _clean(pitch), _clean(yaw)

    def __array__(self, dtype=None, copy=None):
        return self._m if dtype is None else self._m.astype(dtype)

    def __eq__(self, other) -> bool:
        return isinstance(other, Frame) and bool(np.array_equal(self._m, other._m))

    def __hash__(self) -> int:
        return hash(self._m.tobytes())

    def __repr__(self) -> str:
        x, y, z = (float(c) for c in self._m[:3, 3])
        return f"Frame(p=({x:.6g}, {y:.6g}, {z:.6g}), n={_fmt(self.n)}, o={_fmt(self.o)}, a={_fmt(self.a)})"


def check_rotation(r: np.ndarray) -> None:
    """Raise FrameError unless the columns of r are unit length and at right angles within
    ORTHONORMAL_TOLERANCE, and right-handed (a = n x o)."""
    n, o, a = r[:, 0], r[:, 1], r[:, 2]
    lengths = np.abs(np.sqrt((r * r).sum(axis=0)) - 1.0)
    dots = np.abs([n @ o, o @ a, a @ n])
    if lengths.max() > ORTHONORMAL_TOLERANCE or dots.max() > ORTHONORMAL_TOLERANCE:
        raise FrameError("the axes n, o, a must be orthonormal (unit length, at right angles)")
    if np.cross(n, o) @ a < 0.0:
        raise FrameError("the axes n, o, a must be right-handed (a = n x o)")


def _cos_sin(deg: float) -> tuple[float, float]:
    """cos and sin of an angle in degrees, exact at multiples of 90."""
    if not math.isfinite(deg):
        raise FrameError(f"an angle must be a finite number, not {deg:g}")
    q, r = divmod(float(deg), 90.0)
    if r == 0.0:
        return ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))[int(q) % 4]
    t = math.radians(deg)
    return math.cos(t), math.sin(t)


def _clean(x) -> float:
    """Round away the last-bit noise of a conversion (1e-14 degrees is 0)."""
    return round(float(x), 9) + 0.0


def _fmt(v) -> str:
    return "(" + ", ".join(f"{float(c):.6g}" for c in v) + ")"
