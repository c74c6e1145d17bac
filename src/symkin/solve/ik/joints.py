"""Joint ranges, configurations and the parameter vector the IK solvers share."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from symkin.derive import Model

# Random restarts draw unlimited prismatic joints from [-PRISMATIC_RANGE, PRISMATIC_RANGE] m.
PRISMATIC_RANGE = 1.0


def joint_bounds(model: Model) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper joint limits (``-inf``/``inf`` where the robot file gives none)."""
    joints = model.robot.joints
    lower = np.array([-np.inf if j.limits is None else j.limits[0] for j in joints])
    upper = np.array([np.inf if j.limits is None else j.limits[1] for j in joints])
    return lower, upper


def random_configuration(model: Model, rng: np.random.Generator) -> np.ndarray:
    """Uniform within the limits; without limits ``(-pi, pi]`` (revolute) or ``[-1, 1]`` m."""
    lower, upper = joint_bounds(model)
    revolute = np.array([j.type == "revolute" for j in model.robot.joints])
    default = np.where(revolute, np.pi, PRISMATIC_RANGE)
    low = np.where(np.isfinite(lower), lower, -default)
    high = np.where(np.isfinite(upper), upper, default)
    return rng.uniform(low, high)


def middle_configuration(model: Model) -> np.ndarray:
    """The middle of each joint's range (0 for a joint without limits)."""
    lower, upper = joint_bounds(model)
    limited = np.isfinite(lower) & np.isfinite(upper)
    middle = np.zeros(model.robot.dof)
    middle[limited] = (lower[limited] + upper[limited]) / 2
    return middle


def parameter_vector(model: Model, overrides: Mapping[str, float] | None = None) -> np.ndarray:
    """The parameter values in ``robot.parameters`` order (the generated code's ``p``)."""
    values = model.robot.parameter_values(overrides)
    return np.array([values[name] for name, _ in model.robot.parameters], dtype=float)
