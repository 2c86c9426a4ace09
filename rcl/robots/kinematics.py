"""Arm models and their kinematics: forward, analytic inverse, numerical fallback.

An ArmModel comes from a TOML file of standard Denavit-Hartenberg parameters
(A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i), theta_i = q_i + offset_i),
joint limits, speeds and home. Lengths are millimetres, angles degrees, T5
(the flange) is described in robot base coordinates.

Analytic solvers, chosen by the file's `solver`:
- "5dof": waist, shoulder, elbow, wrist pitch, wrist roll (SmartArms, AL5D).
  A 5-axis arm reaches only frames whose approach vector lies in the vertical
  plane through its waist axis; a frame that leans out of it by more than
  APPROACH_TOLERANCE_DEG is refused, saying by how much.
- "puma": the PUMA 560 (Paul; Corke's parameters): shoulder left/right, elbow
  up/down, wrist flip: up to 8 solutions.
Every solution is returned; `solve` picks the one nearest the current joints
within the limits. Models without an analytic solver use a numerical one.
"""
from __future__ import annotations

import math
import tomllib
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .base import RobotError

APPROACH_TOLERANCE_DEG = 0.01
POSITION_TOLERANCE_MM = 1e-6
MODELS_DIR = Path(__file__).resolve().parent / "models"


class IKError(RobotError):
    """A pose the arm cannot take; the message says why."""


@dataclass(frozen=True)
class Joint:
    name: str
    a: float
    alpha: float
    d: float
    offset: float
    min: float
    max: float
    speed: float  # degrees per second at full speed


@dataclass
class ArmModel:
    name: str
    joints: list[Joint]
    home: list[float]
    solver: str | None = None
    table_z: float = 0.0
    linear_speed: float = 250.0
    gripper_seconds: float = 0.5
    ssc32: dict = field(default_factory=dict)
    source: str = ""

    @property
    def axes(self) -> int:
        return len(self.joints)

    def check_limits(self, q: Sequence[float]) -> None:
        """RobotError naming the first joint outside its limits."""
        for j, x in zip(self.joints, q):
            if not j.min - 1e-9 <= x <= j.max + 1e-9:
                raise RobotError(f"joint {j.name} would be at {x:.3f} degrees, outside its limits "
                                 f"{j.min:g}..{j.max:g}")


# Loading -------------------------------------------------------------------------


def builtin_models() -> list[str]:
    return sorted(p.stem for p in MODELS_DIR.glob("*.toml"))


def load_model(name_or_path: str | Path) -> ArmModel:
    """A built-in model by name (smartarms, al5d, puma560) or a TOML file."""
    path = Path(name_or_path)
    if not path.suffix and (MODELS_DIR / f"{name_or_path}.toml").is_file():
        path = MODELS_DIR / f"{name_or_path}.toml"
    try:
        doc = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise RobotError(f"no arm model {name_or_path!s} (built in: {', '.join(builtin_models())}; "
                         f"or give a .toml file)") from None
    except (OSError, UnicodeDecodeError) as e:
        raise RobotError(f"cannot read {path}: {e}") from None
    except tomllib.TOMLDecodeError as e:
        raise RobotError(f"{path}: not valid TOML: {e}") from None
    except RecursionError:
        raise RobotError(f"{path}: arrays or tables nested too deep for an arm model") from None
    try:
        return _model_from(doc, str(path))
    except (KeyError, TypeError, ValueError) as e:
        raise RobotError(f"{path}: not a valid arm model: {e}") from None


def _model_from(doc: dict, source: str) -> ArmModel:
    joints = []
    for k, j in enumerate(doc["joints"], start=1):
        values = {f: float(j[f]) for f in ("a", "alpha", "d", "min", "max", "speed")}
        values["offset"] = float(j.get("offset", 0.0))
        if not all(math.isfinite(v) for v in values.values()):
            raise ValueError(f"joint {k} has a value that is not a finite number")
        if values["min"] >= values["max"] or values["speed"] <= 0:
            raise ValueError(f"joint {k}: min must be below max and speed positive")
        joints.append(Joint(str(j.get("name", f"joint {k}")), **values))
    if not 1 <= len(joints) <= 8:
        raise ValueError("an arm has 1 to 8 joints")
    home = [float(x) for x in doc.get("home", [0.0] * len(joints))]
    if len(home) != len(joints):
        raise ValueError(f"home has {len(home)} angles for {len(joints)} joints")
    table_z = _real(doc.get("table_z", 0.0), "table_z")
    linear_speed = _real(doc.get("linear_speed", 250.0), "linear_speed", positive=True)
    seconds = _real(doc.get("gripper", {}).get("seconds", 0.5), "gripper.seconds")
    if seconds < 0:
        raise ValueError(f"gripper.seconds must be 0 or more, not {seconds:g}")
    ssc32 = dict(doc.get("ssc32", {}))
    if ssc32:
        _check_ssc32(ssc32, len(joints))
    model = ArmModel(str(doc.get("name", Path(source).stem)), joints, home, doc.get("solver"),
                     table_z, linear_speed, seconds, ssc32, source)
    if model.solver not in (None, "5dof", "puma", "numerical"):
        raise ValueError(f"unknown solver {model.solver!r} (5dof, puma or numerical)")
    if model.solver in ("5dof", "puma"):
        _check_structure(model)
    model.check_limits(home)
    return model


def _real(value, key: str, positive: bool = False) -> float:
    """A model's number: finite (and above zero if positive); ValueError says which key."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(float(value)):
        raise ValueError(f"{key} must be a finite number, not {str(value)[:40]}")
    if positive and not value > 0:
        raise ValueError(f"{key} must be above zero, not {value:g}")
    return float(value)


def _whole(v) -> bool:
    return isinstance(v, int) and not isinstance(v, bool)


def _check_ssc32(cfg: dict, axes: int) -> None:
    """The [ssc32] section: a channel (0-31, each once), a pulse width per degree (finite, not
    zero) and a direction (1 or -1) per joint; the gripper's channel and pulse widths; the baud."""
    def ints(key, default=None):
        v = cfg.get(key, default)
        if not isinstance(v, list) or not all(_whole(x) for x in v):
            raise ValueError(f"ssc32.{key} must be a list of whole numbers")
        return v
    channels = ints("channels")
    direction = ints("direction", [1] * len(channels))
    us = cfg.get("us_per_degree")
    if not isinstance(us, list):
        raise ValueError("ssc32.us_per_degree must be a list of numbers")
    for x in us:
        if _real(x, "each ssc32.us_per_degree") == 0:
            raise ValueError("ssc32.us_per_degree must not be 0: the joint would never move")
    if not len(channels) == len(us) == len(direction) == axes:
        raise ValueError(f"ssc32 must give one channel, us_per_degree and direction per joint ({axes})")
    if not all(0 <= c <= 31 for c in channels) or len(set(channels)) != len(channels):
        raise ValueError("ssc32.channels must be distinct channels 0 to 31")
    if not all(d in (1, -1) for d in direction):
        raise ValueError("ssc32.direction must hold 1 or -1 per joint")
    grip = cfg.get("gripper_channel", -1)
    if not _whole(grip) or not -1 <= grip <= 31 or grip in channels:
        raise ValueError("ssc32.gripper_channel must be a channel 0 to 31 no joint uses (or -1: none)")
    for key in ("gripper_open_us", "gripper_closed_us"):
        v = cfg.get(key, 1500)
        if not _whole(v) or not 500 <= v <= 2500:
            raise ValueError(f"ssc32.{key} must be a pulse width of 500 to 2500 us, not {str(v)[:40]}")
    baud = cfg.get("baud", 115200)
    if not _whole(baud) or not 300 <= baud <= 4_000_000:
        raise ValueError(f"ssc32.baud must be a whole number of baud, not {str(baud)[:40]}")


def _check_structure(m: ArmModel) -> None:
    """The analytic solvers assume a joint layout; say so if the file has another."""
    j = m.joints
    if m.solver == "5dof":
        ok = (len(j) == 5 and j[0].a == 0 and abs(j[0].alpha) == 90 and j[1].alpha == 0 and j[1].d == 0
              and j[2].alpha == 0 and j[2].d == 0 and j[3].a == 0 and j[3].d == 0 and j[3].alpha == 90
              and j[4].a == 0 and j[4].alpha == 0 and j[0].alpha == 90)
    else:
        ok = (len(j) == 6 and [x.alpha for x in j] == [90, 0, -90, 90, -90, 0] and j[0].a == 0
              and j[0].d == 0 and j[1].d == 0 and j[3].a == 0 and j[4].a == 0 and j[4].d == 0
              and j[5].a == 0 and j[5].d == 0)
    if not ok:
        raise ValueError(f"its joints do not have the layout the {m.solver!r} solver needs; "
                         f"use solver = \"numerical\"")


# Forward kinematics ----------------------------------------------------------------


def _dh(theta: float, d: float, a: float, alpha: float) -> np.ndarray:
    ct, st = math.cos(theta), math.sin(theta)
    ca, sa = _cos_sin_deg(alpha)
    return np.array([[ct, -st * ca, st * sa, a * ct],
                     [st, ct * ca, -ct * sa, a * st],
                     [0.0, sa, ca, d],
                     [0.0, 0.0, 0.0, 1.0]])


def _cos_sin_deg(deg: float) -> tuple[float, float]:
    if deg % 90 == 0:
        return ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))[int(deg // 90) % 4]
    r = math.radians(deg)
    return math.cos(r), math.sin(r)


def frames(model: ArmModel, q: Sequence[float]) -> list[np.ndarray]:
    """The frame of every link, base first excluded: [T1, T2, ..., Tn = T5]."""
    t = np.eye(4)
    out = []
    for j, x in zip(model.joints, q):
        t = t @ _dh(math.radians(x + j.offset), j.d, j.a, j.alpha)
        out.append(t)
    return out


def fk(model: ArmModel, q: Sequence[float]) -> np.ndarray:
    """T5 for joint angles q (degrees)."""
    return frames(model, q)[-1]


# Inverse kinematics ----------------------------------------------------------------


def solutions(model: ArmModel, t5: np.ndarray, near: Sequence[float] | None = None) -> list[list[float]]:
    """Every joint solution (degrees, each within (-180, 180]) of the analytic solver."""
    if model.solver == "5dof":
        thetas = _ik_5dof(model, t5, near)
    elif model.solver == "puma":
        thetas = _ik_puma(model, t5, near)
    else:
        raise IKError(f"the {model.name} model has no analytic solver")
    return [[_wrap(math.degrees(th) - j.offset) for th, j in zip(sol, model.joints)] for sol in thetas]


def solve(model: ArmModel, t5: np.ndarray, current: Sequence[float]) -> list[float]:
    """The joint angles reaching t5 that are nearest current, within the joint limits."""
    if model.solver in ("5dof", "puma"):
        candidates = solutions(model, t5, current)
    else:
        candidates = [_numerical(model, t5, current)]
    best, best_cost, refused = None, math.inf, None
    for sol in candidates:
        q = _nearest_equivalent(model, sol, current)
        if q is None:
            refused = sol
            continue
        cost = sum((a - b) ** 2 for a, b in zip(q, current))
        if cost < best_cost:
            best, best_cost = q, cost
    if best is None:
        q = refused if refused is not None else candidates[0]
        try:
            model.check_limits(q)
        except RobotError as e:
            raise IKError(f"every way of reaching the pose breaks a joint limit: {e}") from None
        raise IKError("no joint angles within the limits reach the pose")
    return best


def _nearest_equivalent(model: ArmModel, sol: Sequence[float], current: Sequence[float]) -> list[float] | None:
    """Each angle moved by whole turns to be nearest the current one and within limits, or None."""
    out = []
    for x, c, j in zip(sol, current, model.joints):
        y = x + 360.0 * round((c - x) / 360.0)
        if y > j.max + 1e-9:
            y -= 360.0
        elif y < j.min - 1e-9:
            y += 360.0
        if not j.min - 1e-9 <= y <= j.max + 1e-9:
            return None
        out.append(y)
    return out


def _wrap(deg: float) -> float:
    w = math.fmod(deg + 180.0, 360.0)
    return (w + 360.0 if w <= 0.0 else w) - 180.0


def _planar_two_link(a2: float, a3: float, r: float, h: float, what: str) -> list[tuple[float, float]]:
    """(theta2, theta3) with a2 (cos t2, sin t2) + a3 (cos t2+t3, sin t2+t3) = (r, h): elbow both ways."""
    dist2 = r * r + h * h
    c3 = (dist2 - a2 * a2 - a3 * a3) / (2 * a2 * a3)
    if c3 > 1 + 1e-12 or c3 < -1 - 1e-12:
        reach = a2 + a3 if c3 > 1 else abs(a2 - a3)
        raise IKError(f"out of reach: the {what} would be {math.sqrt(dist2):.1f} mm from the shoulder, "
                      f"and the arm reaches {'at most' if c3 > 1 else 'no closer than'} {reach:.1f} mm")
    c3 = max(-1.0, min(1.0, c3))
    out = []
    for s3 in (math.sqrt(1 - c3 * c3), -math.sqrt(1 - c3 * c3)):
        t3 = math.atan2(s3, c3)
        t2 = math.atan2(h, r) - math.atan2(a3 * s3, a2 + a3 * c3)
        out.append((t2, t3))
    return out


def _ik_5dof(model: ArmModel, t: np.ndarray, near) -> list[list[float]]:
    j1, j2, j3, _, j5 = model.joints
    ax, ay, az = t[0, 2], t[1, 2], t[2, 2]
    wx, wy, wz = t[0, 3] - j5.d * ax, t[1, 3] - j5.d * ay, t[2, 3] - j5.d * az  # the wrist centre
    if math.hypot(wx, wy) > 1e-9:
        base = math.atan2(wy, wx)
    elif math.hypot(ax, ay) > 1e-9:
        base = math.atan2(ay, ax)
    else:
        base = math.radians((near[0] if near is not None else 0.0) + j1.offset)
    out: list[list[float]] = []
    problem = IKError("the pose is out of reach")  # replaced by why each way fails
    for t1 in (base, base + math.pi):
        c1, s1 = math.cos(t1), math.sin(t1)
        lean = math.degrees(math.asin(max(-1.0, min(1.0, s1 * ax - c1 * ay))))
        if abs(lean) > APPROACH_TOLERANCE_DEG:
            problem = IKError(f"a 5-axis arm cannot point its approach vector there: it leans "
                              f"{abs(lean):.3g} degrees out of the arm's vertical plane (tolerance "
                              f"{APPROACH_TOLERANCE_DEG:g}); turn the frame about its approach axis "
                              f"or point it in the plane through the waist axis")
            continue
        r, h = c1 * wx + s1 * wy, wz - j1.d
        try:
            arms = _planar_two_link(j2.a, j3.a, r, h, "wrist centre")
        except IKError as e:
            problem = e
            continue
        for t2, t3 in arms:
            # R03 = Rz(t1) Rx(90) Rz(t2 + t3); M = R03^T R = Rz(t4) Rx(90) Rz(t5)
            c23, s23 = math.cos(t2 + t3), math.sin(t2 + t3)
            x3 = (c1 * c23, s1 * c23, s23)
            y3 = (-c1 * s23, -s1 * s23, c23)
            z3 = (s1, -c1, 0.0)
            col = t[:3, :3]
            m02 = x3[0] * ax + x3[1] * ay + x3[2] * az
            m12 = y3[0] * ax + y3[1] * ay + y3[2] * az
            m20 = z3[0] * col[0, 0] + z3[1] * col[1, 0]
            m21 = z3[0] * col[0, 1] + z3[1] * col[1, 1]
            t4 = math.atan2(m02, -m12)
            t5 = math.atan2(m20, m21)
            out.append([t1, t2, t3, t4, t5])
    if not out:
        raise problem
    return out


def _ik_puma(model: ArmModel, t: np.ndarray, near) -> list[list[float]]:
    a2, a3, d3, d4 = model.joints[1].a, model.joints[2].a, model.joints[2].d, model.joints[3].d
    px, py, pz = t[0, 3], t[1, 3], t[2, 3]
    rho = math.hypot(px, py)
    if rho < abs(d3) - 1e-9:
        raise IKError(f"out of reach: the wrist centre is {rho:.1f} mm from the waist axis, closer than "
                      f"the shoulder offset {abs(d3):.2f} mm")
    (nx, ox, ax), (ny, oy, ay), (nz, oz, az) = t[0, :3], t[1, :3], t[2, :3]
    phi = math.atan2(py, px)
    alpha = math.asin(max(-1.0, min(1.0, d3 / rho))) if rho > 0 else 0.0
    forearm = math.hypot(a3, d4)
    beta = math.atan2(d4, a3)
    out = []
    for t1 in (phi + alpha, phi + math.pi - alpha):  # shoulder right, left
        c1, s1 = math.cos(t1), math.sin(t1)
        r = c1 * px + s1 * py
        for t2, psi in _planar_two_link(a2, forearm, r, pz, "wrist centre"):
            t3 = psi - beta
            # the wrist: R36 = R03^T R = Rz(t4) Ry(-t5) Rz(t6)
            c23, s23 = math.cos(t2 + t3), math.sin(t2 + t3)
            # rows of R03^T: x3 = (c1 c23, s1 c23, s23), y3 = (-s1, c1, 0), z3 = (-c1 s23, -s1 s23, c23)
            m02 = c1 * c23 * ax + s1 * c23 * ay + s23 * az
            m12 = -s1 * ax + c1 * ay
            m22 = -c1 * s23 * ax - s1 * s23 * ay + c23 * az
            s5 = math.hypot(m02, m12)
            if s5 > 1e-9:
                m20 = -c1 * s23 * nx - s1 * s23 * ny + c23 * nz
                m21 = -c1 * s23 * ox - s1 * s23 * oy + c23 * oz
                t4 = math.atan2(-m12, -m02)
                t5 = math.atan2(s5, m22)
                t6 = math.atan2(-m21, m20)
                out.append([t1, t2, t3, t4, t5, t6])
                out.append([t1, t2, t3, t4 + math.pi, -t5, t6 + math.pi])
            else:  # wrist singular: only t4 + t6 matters; keep t4 where it is
                m00 = c1 * c23 * nx + s1 * c23 * ny + s23 * nz
                m10 = -s1 * nx + c1 * ny
                t4 = math.radians(near[3]) if near is not None else 0.0
                t5 = 0.0 if m22 > 0 else math.pi
                total = math.atan2(m10, m00)
                t6 = total - t4 if m22 > 0 else t4 + math.pi - total
                out.append([t1, t2, t3, t4, t5, t6])
    return out


def _numerical(model: ArmModel, t5: np.ndarray, current: Sequence[float]) -> list[float]:
    """Least squares on position and orientation from the current joints, then from random starts."""
    from scipy.optimize import least_squares

    target_p, target_r = t5[:3, 3], t5[:3, :3]
    scale = max(sum(abs(j.a) + abs(j.d) for j in model.joints), 1.0) / 4  # mm per radian of orientation error

    def residual(q):
        t = fk(model, q)
        err_r = target_r.T @ t[:3, :3]
        rot = 0.5 * np.array([err_r[2, 1] - err_r[1, 2], err_r[0, 2] - err_r[2, 0], err_r[1, 0] - err_r[0, 1]])
        return np.concatenate([t[:3, 3] - target_p, scale * rot])

    lo = np.array([j.min for j in model.joints])
    hi = np.array([j.max for j in model.joints])
    rng = np.random.default_rng(0)
    starts = [np.clip(np.asarray(current, float), lo, hi)] + [rng.uniform(lo, hi) for _ in range(12)]
    best = None
    for q0 in starts:
        res = least_squares(residual, q0, bounds=(lo, hi), xtol=1e-14, ftol=1e-14, gtol=1e-14)
        pos_err = float(np.linalg.norm(res.fun[:3]))
        if best is None or res.cost < best[0]:
            best = (res.cost, res.x, pos_err, float(np.linalg.norm(res.fun[3:]) / scale))
        if pos_err < POSITION_TOLERANCE_MM and best[3] < 1e-8:
            return [float(x) for x in res.x]
    assert best is not None  # starts is never empty
    _, q, pos_err, rot_err = best
    raise IKError(f"no joint angles within the limits reach the pose (best: {pos_err:.3g} mm and "
                  f"{math.degrees(rot_err):.3g} degrees off)")
