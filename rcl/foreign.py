"""Routine names from other robot languages (ABB RAPID, KUKA KRL, Universal Robots' URScript) and
what does the same in RCL: the checker names it when a program calls one of them."""
from __future__ import annotations

# lower-case name -> (what it is called there, what RCL writes)
FOREIGN = {
    "movel": ("RAPID's MoveL (URScript's movel)", "MOVES(T5^)"),
    "lin": ("KRL's LIN", "MOVES(T5^)"),
    "movej": ("RAPID's MoveJ (URScript's movej)", "MOVE(T5^)"),
    "ptp": ("KRL's PTP", "MOVE(T5^)"),
    "moveabsj": ("RAPID's MoveAbsJ", "JMOVE(q)"),
    "waittime": ("RAPID's WaitTime", "DELAY(seconds)"),
    "wait": ("KRL's WAIT SEC", "DELAY(seconds)"),
    "sleep": ("URScript's sleep", "DELAY(seconds)"),
    "tpwrite": ("RAPID's TPWrite", "WRITELN(...)"),
    "textmsg": ("URScript's textmsg", "WRITELN(...)"),
    "velset": ("RAPID's VelSet", "SPEED(percent)"),
    "crobt": ("RAPID's CRobT", "HERE^()"),
    "get_actual_tcp_pose": ("URScript's get_actual_tcp_pose", "HERE^()"),
    "cjointt": ("RAPID's CJointT", "JOINTS()"),
    "get_actual_joint_positions": ("URScript's get_actual_joint_positions", "JOINTS()"),
    "offs": ("RAPID's Offs", "TRANS(x, y, z) * P^ (an offset in the base frame)"),
    "reltool": ("RAPID's RelTool", "P^ * TRANS(x, y, z) (an offset in the tool frame)"),
    "pose_trans": ("URScript's pose_trans", "A^ * B^"),
    "pose_inv": ("URScript's pose_inv", "INV(P^)"),
}


def hint(key: str) -> str:
    """'; RAPID's MoveL (...) is MOVES(T5^) in RCL' for a foreign routine's name, else ''."""
    known = FOREIGN.get(key)
    return f"; {known[0]} is {known[1]} in RCL" if known else ""
