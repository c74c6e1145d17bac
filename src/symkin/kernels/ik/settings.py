"""Settings of the damped-least-squares IK, read by both solvers: the NumPy batch solver
(:mod:`symkin.solve.ik.batch`) and the C one (``templates/c/lib/symkin_dls.c``), to which the
generated ``<robot>_ik.c`` hands them (``templates/c/ik.c.j2``).

The algorithm is stated in :mod:`symkin.solve.ik.batch`; these numbers are its constants.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from symkin.errors import ParameterError

# An attempt has stalled when E is above STALL_FACTOR times its value STALL_WINDOW steps ago.
STALL_WINDOW = 5
STALL_FACTOR = 0.5
# Restart range of a joint without a limit: its width for revolute and prismatic joints.
REVOLUTE_SPAN = 2 * math.pi
PRISMATIC_SPAN = 2.0
# A target rotation further than this from orthonormal (|R^T R - I|, entry by entry) is
# rejected as invalid input by the C solver; single precision rounds a rotation to about 1e-7.
ORTHONORMAL_TOLERANCE = {"double": 1e-6, "float": 1e-4}
# xorshift64 must not start from 0 (it would stay 0); seed 0 means this state instead.
FALLBACK_SEED = 0x9E3779B97F4A7C15


@dataclass(frozen=True)
class DampedLeastSquares:
    """Settings of the damped-least-squares solver (C: ``<robot>_ik_options``).

    The defaults are those of the double-precision C code; :data:`FLOAT_SETTINGS` holds the
    single-precision ones.
    """

    max_iterations: int = 100
    max_restarts: int = 50
    position_tolerance: float = 1e-10
    rotation_tolerance: float = 1e-10
    damping: float = 1e-9
    error_damping: float = 0.1
    seed: int = 1

    def __post_init__(self) -> None:
        if self.max_iterations < 0 or self.max_restarts < 0:
            raise ParameterError(
                "{max_iterations} and {max_restarts} must be >= 0, got "
                f"{self.max_iterations} and {self.max_restarts}"
            )
        if not (self.position_tolerance > 0 and self.rotation_tolerance > 0):
            raise ParameterError(
                "{position_tolerance} and {rotation_tolerance} must be positive, got "
                f"{self.position_tolerance} and {self.rotation_tolerance}"
            )
        if not (0 <= self.damping < math.inf and 0 <= self.error_damping < math.inf):
            raise ParameterError(
                f"{{damping}} and {{error_damping}} must be finite and >= 0, got {self.damping} "
                f"and {self.error_damping}"
            )
        if not 0 <= self.seed < 2**64:
            raise ParameterError(
                f"the {{seed}} must be an unsigned 64-bit integer, got {self.seed}"
            )


FLOAT_SETTINGS = DampedLeastSquares(position_tolerance=1e-5, rotation_tolerance=1e-5, damping=1e-6)
