"""Reading robot descriptions from files (TOML robot files; URDF later)."""

from symkin.io.robot_file import catalogue_names, load_robot, robot_from_toml

__all__ = ["catalogue_names", "load_robot", "robot_from_toml"]
