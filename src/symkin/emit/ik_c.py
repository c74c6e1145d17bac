"""Generated numeric IK in C: ``c/<robot>_ik.h`` and ``c/<robot>_ik.c`` beside the kernels.

The solver (damped least squares on the generated ``fk_jacobian`` kernel, restarts, limits) is
the one :mod:`symkin.solve.ik.batch` runs in NumPy; both read their settings from
:mod:`symkin.kernels.ik.settings`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import asdict

from symkin.emit.c import c_literal
from symkin.emit.c_library import library_files
from symkin.emit.render import preamble_lines, render
from symkin.kernels import Kernel
from symkin.kernels.ik.settings import (
    FALLBACK_SEED,
    FLOAT_SETTINGS,
    ORTHONORMAL_TOLERANCE,
    PRISMATIC_SPAN,
    REVOLUTE_SPAN,
    STALL_FACTOR,
    STALL_WINDOW,
    DampedLeastSquares,
)
from symkin.robot import Robot


def _settings(precision: str) -> DampedLeastSquares:
    return FLOAT_SETTINGS if precision == "float" else DampedLeastSquares()


def _limit_literals(robot: Robot, precision: str) -> tuple[list[str], list[str]]:
    """Lower and upper limits as C literals, ``-INFINITY``/``INFINITY`` where none is given."""
    lower = [c_literal(j.limits[0], precision) if j.limits else "-INFINITY" for j in robot.joints]
    upper = [c_literal(j.limits[1], precision) if j.limits else "INFINITY" for j in robot.joints]
    return lower, upper


def emit_ik_c(
    robot: Robot, kernels: tuple[Kernel, ...], precision: str = "double", flags: Sequence[str] = ()
) -> dict[str, str]:
    """``c/<robot>_ik.h`` and ``c/<robot>_ik.c``; they call ``<robot>_fk_jacobian``."""
    settings = _settings(precision)
    literal = {
        key: c_literal(value, precision)
        for key, value in asdict(settings).items()
        if isinstance(value, float)
    }
    defaults = {
        **literal,
        "max_iterations": settings.max_iterations,
        "max_restarts": settings.max_restarts,
        "seed": f"UINT64_C({settings.seed})",
    }
    (fk_jacobian,) = [k for k in kernels if k.name == "fk_jacobian"]
    lower, upper = _limit_literals(robot, precision)
    header = f"{robot.name}_ik.h"
    context = {
        "prefix": robot.name,
        "macro": robot.name.upper(),
        "guard": f"{robot.name.upper()}_IK_H",
        "real": precision,
        "dof": robot.dof,
        "has_parameters": bool(robot.parameters),
        "header": f"{robot.name}.h",
        "ik_header": header,
        "library": library_files(precision, "xorshift", "pose_error", "cholesky", "dls"),
        "orthonormal_tolerance": c_literal(ORTHONORMAL_TOLERANCE[precision], precision),
        "stall_window": STALL_WINDOW,
        "stall_factor": STALL_FACTOR,
        "stall_factor_literal": c_literal(STALL_FACTOR, precision),
        "fallback_seed": f"UINT64_C({FALLBACK_SEED:#x})",
        "revolute": [int(j.type == "revolute") for j in robot.joints],
        "sample_span": [
            c_literal(REVOLUTE_SPAN if j.type == "revolute" else PRISMATIC_SPAN, precision)
            for j in robot.joints
        ],
        "lower": lower,
        "upper": upper,
        "defaults": defaults,
        "defaults_text": (
            f"{settings.max_iterations} iterations per attempt, {settings.max_restarts} "
            f"restarts, tolerances {settings.position_tolerance:g} m and "
            f"{settings.rotation_tolerance:g} rad, damping {settings.damping:g} + "
            f"{settings.error_damping:g} E, seed {settings.seed}"
        ),
        "preamble": preamble_lines(robot, (fk_jacobian,), f"C numeric IK ({precision})", flags),
    }
    return {
        f"c/{header}": render("c/ik.h.j2", **context),
        f"c/{robot.name}_ik.c": render("c/ik.c.j2", **context),
    }
