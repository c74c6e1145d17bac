"""Steps shared by the numeric IK solvers: the rotation error and the Newton step.

``rotation_vector`` is the angular part of the pose error (docs/ik.md);
``newton_step`` and ``null_space_step`` are the lecture's Newton iteration and the
self-motion step of a redundant arm.
"""

from __future__ import annotations

import math

import numpy as np

from symkin.spatial import axis_angle_from_rotation

# Newton: a square Jacobian with a larger condition number counts as singular.
SINGULAR_CONDITION = 1e12


def rotation_vector(R: np.ndarray) -> np.ndarray:
    """Axis times angle of the rotation ``R`` (angle in ``[0, pi]``), never NaN.

    Below 90 degrees directly from the skew part: ``w = vee(R - R^T) = 2 sin(a) k`` and
    ``a = atan2(|w| / 2, (tr R - 1) / 2)``, so ``r = w a / (2 sin a)`` (``a / sin a -> 1`` at 0).
    Beyond, where ``sin a`` gets small again, :func:`symkin.spatial.axis_angle_from_rotation`.
    """
    w = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    c = 0.5 * (R[0, 0] + R[1, 1] + R[2, 2] - 1.0)
    if c <= 0.0:
        axis, angle, _ = axis_angle_from_rotation(R)
        return np.asarray(axis, dtype=float) * angle
    half_norm = 0.5 * math.sqrt(w @ w)
    if half_norm == 0.0:
        return 0.5 * w
    return w * (0.5 * math.atan2(half_norm, c) / half_norm)


def newton_step(J: np.ndarray, e: np.ndarray) -> np.ndarray:
    """``J^-1 e`` for a square, regular ``J``; otherwise ``J^+ e``, the least-squares step of
    least norm (by the normal equations while ``J`` has full rank, else by an SVD)."""
    rows, columns = J.shape
    try:
        if rows == columns:
            if np.linalg.cond(J) < SINGULAR_CONDITION:
                return np.linalg.solve(J, e)
        elif rows < columns:
            return J.T @ np.linalg.solve(J @ J.T, e)  # J^+ = J^T (J J^T)^-1
        else:
            return np.linalg.solve(J.T @ J, J.T @ e)  # J^+ = (J^T J)^-1 J^T
    except np.linalg.LinAlgError:
        pass  # rank-deficient: the SVD below
    return np.linalg.lstsq(J, e, rcond=None)[0]


def null_space_step(J: np.ndarray, z: np.ndarray) -> np.ndarray:
    """``(I - J^+ J) z``: the part of ``z`` that does not move the task to first order."""
    return z - newton_step(J, J @ z)
