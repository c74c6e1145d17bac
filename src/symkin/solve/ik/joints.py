"""Joint ranges, configurations and the parameter vector the IK solvers share."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from symkin.derive import Model
from symkin.errors import ParameterError, SymkinError
from symkin.runtime.modules import remembered

# Random restarts draw unlimited prismatic joints from [-PRISMATIC_RANGE, PRISMATIC_RANGE] m.
PRISMATIC_RANGE = 1.0


def joint_bounds(model: Model) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper joint limits (``-inf``/``inf`` where the robot file gives none)."""
    joints = model.robot.joints
    lower = np.array([-np.inf if j.limits is None else j.limits[0] for j in joints])
    upper = np.array([np.inf if j.limits is None else j.limits[1] for j in joints])
    return lower, upper


@dataclass(frozen=True)
class JointData:
    """What the solvers read of a robot's joints on every call (read-only arrays): limits
    (``-inf``/``inf`` for none), which joints are revolute, which are revolute without limits
    (their angles count modulo 2 pi), the middle configuration, the parameter values."""

    lower: np.ndarray
    upper: np.ndarray
    revolute: np.ndarray
    unlimited: np.ndarray
    middle: np.ndarray
    parameters: np.ndarray | None  # None while a parameter has no value (overrides needed)
    has_limits: bool


def joint_data(model: Model) -> JointData:
    """The :class:`JointData` of ``model``, computed once per robot and process (looked up by
    the model's identity first: hashing a model is slow)."""
    return remembered(model, "joint_data", _joint_data)


@lru_cache(maxsize=64)
def _joint_data(model: Model) -> JointData:
    lower, upper = joint_bounds(model)
    revolute = np.array([j.type == "revolute" for j in model.robot.joints])
    try:
        parameters: np.ndarray | None = parameter_vector(model)
    except ParameterError:
        parameters = None
    data = JointData(
        lower=lower,
        upper=upper,
        revolute=revolute,
        unlimited=revolute & ~np.isfinite(lower) & ~np.isfinite(upper),
        middle=middle_configuration(model),
        parameters=parameters,
        has_limits=bool(np.isfinite(lower).any() or np.isfinite(upper).any()),
    )
    for array in (lower, upper, revolute, data.unlimited, data.middle, parameters):
        if array is not None:
            array.setflags(write=False)
    return data


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


def joint_vector(values: Sequence[float] | np.ndarray, n: int, what: str) -> np.ndarray:
    """``values`` as a flat array of ``n`` finite numbers; ``what`` names them in errors."""
    array = np.asarray(values, dtype=float).reshape(-1)
    if array.size != n:
        raise SymkinError(f"{what}: expected {n} values, got {array.size}")
    if not np.isfinite(array).all():
        raise SymkinError(f"{what}: expected finite numbers, got {array.tolist()}")
    return array


def wrap_angles(angles: np.ndarray) -> np.ndarray:
    """Angles mapped to ``(-pi, pi]``."""
    return np.pi - np.mod(np.pi - angles, 2 * np.pi)


def rest_configuration(
    model: Model, rest_posture: Sequence[float] | str | None
) -> np.ndarray | None:
    """The null-space preference: given joint values, the middle of the ranges, or none."""
    if rest_posture is None:
        return None
    if isinstance(rest_posture, str):
        if rest_posture != "middle":
            raise SymkinError(
                f"rest posture: expected {model.robot.dof} joint values or 'middle', "
                f"got {rest_posture!r}"
            )
        return joint_data(model).middle
    return joint_vector(rest_posture, model.robot.dof, "rest posture")
