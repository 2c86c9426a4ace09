"""Robot backends behind one interface; plain numpy, no knowledge of RCL.

Poses are 4x4 homogeneous matrices of T5 (the manipulator end) in robot
base coordinates, millimetres; joint angles are in degrees.
"""
from .base import Robot, RobotError
from .recorder import RecordingArm

__all__ = ["Robot", "RobotError", "RecordingArm"]
