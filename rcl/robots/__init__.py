"""Robot backends behind one interface; plain numpy, no knowledge of RCL.

Poses are 4x4 homogeneous matrices of T5 (the manipulator end) in robot
base coordinates, millimetres; joint angles are in degrees.
"""
from .base import Robot, RobotError
from .kinematics import APPROACH_TOLERANCE_DEG, ArmModel, IKError, builtin_models, fk, load_model, solve
from .recorder import RecordingArm
from .sim import SimRobot

__all__ = ["Robot", "RobotError", "RecordingArm", "SimRobot", "ArmModel", "IKError", "load_model",
           "builtin_models", "fk", "solve", "APPROACH_TOLERANCE_DEG"]
