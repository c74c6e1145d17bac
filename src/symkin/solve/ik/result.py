"""The result of the numeric IK solvers (:func:`symkin.solve.ik.numeric.solve_ik`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class IKResult:
    """The outcome of :func:`solve_ik`.

    ``q`` is the best configuration found (the solution when ``success``, otherwise the closest
    pose reached), ``pose`` its forward kinematics.  ``position_error`` (m) and
    ``rotation_error`` (rad) are the norms of the selected linear and angular error components
    at ``q``; ``residual`` is the larger of the two.  ``iterations`` counts every iteration of
    every attempt, ``restarts`` the attempts after the first.  ``backend`` names the
    implementation that ran (:mod:`symkin.solve.ik.backends`: ``"c"``, ``"numpy"``,
    ``"python"``; ``"casadi"`` for :func:`~symkin.solve.ik.casadi_ik.solve_ik_casadi`).
    """

    q: np.ndarray
    success: bool
    position_error: float
    rotation_error: float
    iterations: int
    restarts: int
    pose: np.ndarray
    rows: tuple[str, ...]
    method: str
    backend: str = "python"

    @property
    def residual(self) -> float:
        return max(self.position_error, self.rotation_error)
