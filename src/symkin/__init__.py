"""symkin: Denavit–Hartenberg tables to closed-form kinematics and verified code."""

from symkin.errors import RobotError, SymkinError
from symkin.robot import Joint, Link, Robot, joint_symbols

__all__ = ["Joint", "Link", "Robot", "RobotError", "SymkinError", "joint_symbols"]
