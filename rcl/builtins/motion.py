"""Motion built-ins: thin adapters over the session's robot backend (rcl.robots)."""
from __future__ import annotations

import math
from typing import Annotated

from ..context import Context
from ..errors import BuiltinError
from ..frame import Frame, FrameError
from ..robots import RobotError
from ..robots.base import checked_speed
from ..types import RealArray, Var
from ..values import Array

BaseToT5 = Annotated[Frame, "base -> t5"]


def _robot(ctx: Context):
    if ctx.robot is None:
        raise BuiltinError("this session has no robot")
    return ctx.robot


def _do(action, *args):
    try:
        return action(*args)
    except RobotError as e:
        raise BuiltinError(str(e)) from None


def _target(name: str, t5: Frame):
    """The frame's matrix; BuiltinError if a product overflowed into inf or NaN on the way."""
    m = t5.matrix
    if not math.isfinite(float(m.sum())):
        p = ", ".join(f"{x:g}" for x in m[:3, 3])
        raise BuiltinError(f"{name}: the frame holds a number that is not finite (position ({p})): "
                           f"a product of frames overflowed")
    return m


def move(ctx: Context, t5: BaseToT5) -> None:
    """MOVE(T5^): joint-interpolated move of the manipulator end to T5^ (robot base coordinates)."""
    _do(_robot(ctx).move, _target("MOVE", t5))


def moves(ctx: Context, t5: BaseToT5) -> None:
    """MOVES(T5^): straight-line move of the manipulator end to T5^."""
    _do(_robot(ctx).moves, _target("MOVES", t5))


def speed(ctx: Context, percent: float) -> None:
    """SPEED(percent): the speed of later motions, 1 to 100 percent of the maximum."""
    robot = _robot(ctx)
    _do(lambda: robot.speed(checked_speed(percent)))  # checked here too: for any backend


def open_(ctx: Context) -> None:
    """OPEN: open the gripper."""
    _do(_robot(ctx).open)


def close(ctx: Context) -> None:
    """CLOSE: close the gripper."""
    _do(_robot(ctx).close)


def home(ctx: Context) -> None:
    """HOME: move to the home position."""
    _do(_robot(ctx).home)


def here(ctx: Context) -> BaseToT5:
    """HERE^(): the current pose of T5 (robot base coordinates)."""
    try:
        return Frame(_do(_robot(ctx).here))
    except FrameError as e:
        raise BuiltinError(f"the robot reported a pose that is not a frame: {e}") from None


def delay(ctx: Context, seconds: float) -> None:
    """DELAY(seconds): wait (simulated time on a simulator)."""
    if not (seconds >= 0.0 and math.isfinite(seconds)):
        raise BuiltinError(f"DELAY takes a finite number of seconds >= 0, not {seconds:g}")
    _do(_robot(ctx).delay, seconds)


def jmove(ctx: Context, q: RealArray) -> None:
    """JMOVE(q): move to joint angles (degrees), one array element per axis."""
    _do(_robot(ctx).jmove, list(q.items))


def joints(ctx: Context, q: Var[RealArray]) -> None:
    """JOINTS(VAR q): read the joint angles (degrees) into q, one element per axis."""
    values = _do(_robot(ctx).joints)
    target: Array = q.get()
    if len(target.items) != len(values):
        raise BuiltinError(f"JOINTS needs an array of {len(values)} REALs for this arm, "
                           f"not {len(target.items)}")
    target.items[:] = [float(v) for v in values]


BUILTINS = {
    "MOVE": move, "MOVES": moves, "SPEED": speed, "OPEN": open_, "CLOSE": close,
    "HOME": home, "HERE^": here, "DELAY": delay, "JMOVE": jmove, "JOINTS": joints,
}
