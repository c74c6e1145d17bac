"""Inverse kinematics: numeric solvers, the path-following scheme and closed forms."""
