"""Cell built-ins: the gripper's sensor and the stations of the work cell (rcl.cell).

GRIPPED asks the arm (a backend with a gripper sensor has gripped()); CRIMP,
TINNED, SHAKE and TRAYEMPTY ask the session's cell, which has the press, the
bath, the tray's vibrator and the load cell under the tray; WIRENO and FAILURE
give its number of the wire last taken and its words for what failed last, so a
program's output numbers and words things as the cell's pictures and report do.
"""
from __future__ import annotations

from ..context import Context
from ..errors import BuiltinError


def _cell(ctx: Context, name: str, what: str):
    if ctx.cell is None:
        raise BuiltinError(f"{name}: this session's cell has no {what} (run on a cell that has: "
                           f"the simulated one, `rcl run` without --robot or --camera)")
    return ctx.cell


def gripped(ctx: Context) -> bool:
    """GRIPPED(): TRUE when the closed fingers hold something (the gripper's sensor)."""
    sense = getattr(ctx.robot, "gripped", None)
    if sense is None:
        raise BuiltinError("GRIPPED: this arm's gripper has no sensor")
    return bool(sense())


def crimp(ctx: Context) -> bool:
    """CRIMP(): cycle the press; TRUE when the held wire's end was in the die and is crimped."""
    from ..cell import CellError

    try:
        return _cell(ctx, "CRIMP", "press").crimp()
    except CellError as e:
        raise BuiltinError(f"CRIMP: {e}") from None


def tinned(ctx: Context) -> bool:
    """TINNED(): TRUE when the held wire's end has been dipped in the solder bath deep and long enough."""
    cell = _cell(ctx, "TINNED", "solder bath")
    if cell.bath is None:
        raise BuiltinError("TINNED: this cell has no solder bath")
    return cell.held is not None and cell.held.tinned


def trayempty(ctx: Context) -> bool:
    """TRAYEMPTY(): TRUE when the tray's load cell finds no wire left on it."""
    return len(_cell(ctx, "TRAYEMPTY", "load cell under its tray").tray) == 0


def wireno(ctx: Context) -> int:
    """WIRENO(): the cell's number of the wire the fingers' last close on the tray took (0 when
    it took none): the number its pictures and report give that wire."""
    return _cell(ctx, "WIRENO", "numbered wires").last_taken or 0


def failure(ctx: Context) -> str:
    """FAILURE(): the cell's words for what failed last ('' when nothing has): the words its
    pictures and report use, e.g. 'pick failed: wire 6 slipped out of the fingers ...'."""
    return _cell(ctx, "FAILURE", "record of failures").last_failure


def shake(ctx: Context) -> None:
    """SHAKE(): vibrate the tray so the wires settle anew (when no end is free to take)."""
    _cell(ctx, "SHAKE", "tray vibrator").shake()


BUILTINS = {"GRIPPED": gripped, "CRIMP": crimp, "TINNED": tinned, "SHAKE": shake, "TRAYEMPTY": trayempty,
            "WIRENO": wireno, "FAILURE": failure}
