"""Generated closed-form IK in C: ``c/<robot>_ik_closed.h`` and ``c/<robot>_ik_closed.c``.

Only for robots with a closed form (``symkin.kernels.ik.plan.has_closed_form``).  The robot's
plan (:func:`symkin.kernels.ik.plan.closed_form_plan`) decides everything here: which family
template (``templates/c/ik_closed_{planar,wrist,parallel}.c.j2``, for a wrist also
``ik_closed_arm_<arm>.c.j2``) lays out the per-pose formulas of the Python solver, which
functions of the C library's closed-form part (``templates/c/lib/symkin_closed_form.{h,c}``,
pasted into the file) it calls, and the constants, computed from ``p`` through the
``closed_form_constants`` kernel.  Every candidate is checked by the generated ``<robot>_fk``,
as ``closed_form_ik`` checks it in Python.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from symkin.emit.c import c_kernel_layout, c_literal
from symkin.emit.c_library import library_files
from symkin.emit.ik_c import _limit_literals
from symkin.emit.render import preamble_lines, render
from symkin.kernels import Kernel
from symkin.kernels.ik.closed_form_constants import constants_kernel
from symkin.kernels.ik.closed_form_spec import Shape
from symkin.kernels.ik.closed_form_steps import REACH_TOL, WRIST_SINGULAR
from symkin.kernels.ik.plan import DUPLICATE_TOL, RIGID_TOL, VERIFY_TOL, closed_form_plan
from symkin.robot import Robot

#: ``branch`` bit of each flag value (the same on every robot) and its meaning.
BRANCH_BITS: dict[tuple[str, str], tuple[int, str]] = {
    ("shoulder", "right"): (0x001, "shoulder offset right of the reach direction, seen from above"),
    ("shoulder", "left"): (0x002, "shoulder offset left of the reach direction"),
    ("elbow", "up"): (0x004, "elbow above the line shoulder-wrist (planar: counterclockwise)"),
    ("elbow", "down"): (0x008, "elbow below that line (planar: clockwise)"),
    ("extension", "forward"): (0x010, "positive root of the prismatic reach"),
    ("extension", "backward"): (0x020, "negative root of the prismatic reach"),
    ("wrist", "no_flip"): (0x040, "sin(alpha_4) sin(theta_5) < 0"),
    ("wrist", "flip"): (0x080, "the other wrist branch"),
    ("wrist", "singular"): (0x100, "sin(theta_5) = 0: one solution, with {free} = 0"),
}

#: Tolerances of the checks.  ``double``: those of ``symkin.solve.ik.closed_form``; ``float``
#: rounds a 1 m arm's pose to about 1e-7, a stretched elbow's cosine to about 1e-6.
TOLERANCES = {
    "double": {
        "verify": VERIFY_TOL,
        "joint": DUPLICATE_TOL,
        "reach": REACH_TOL,
        "rigid": RIGID_TOL,
        "wrist_singular": WRIST_SINGULAR,
    },
    "float": {
        "verify": 1e-4,
        "joint": 1e-5,
        "reach": 1e-5,
        "rigid": 1e-4,
        "wrist_singular": WRIST_SINGULAR,
    },
}

#: What the target components mean for each family (header comment).
TASK_TEXT = {
    "pose": "the whole pose",
    "xy": "x, y of the tool point in the frame after the base transform",
    "xyz": "x, y, z of the tool point in the frame after the base transform",
    "xy+heading": "x, y of the tool point and the heading atan2(r21, r11) of the last joint "
    "frame, in the frame after the base transform",
    "xyz+heading": "x, y, z of the tool point and the heading atan2(r21, r11) of the last joint "
    "frame, in the frame after the base transform",
}


#: The closed-form part of the C library, pasted after the real type.
CLOSED_FORM_LIBRARY = ("symkin_closed_form.h", "symkin_closed_form.c")
#: Functions of ``templates/c/lib/symkin_closed_form.h`` each kind of arm calls.
_ELBOW = ("TWO_LINK", "ELBOW_UP")
_SHOULDER = ("CLAMPED_SQRT", "SHOULDER", "SHOULDER_RIGHT", "UNROTATE")
STEPS = {
    "planar": ("TWO_LINK",),
    "articulated": (*_ELBOW, *_SHOULDER),
    "spherical": _SHOULDER,
    "cylindrical": ("CLAMPED_SQRT", "UNROTATE"),
    "parallel": (*_ELBOW, *_SHOULDER),
}


def _family(shape: Shape) -> dict[str, object]:
    """What the family templates lay out: which template, which library functions, the twist
    signs as ``(macro, +-1)``, and for a planar arm its joints and task rows."""
    context: dict[str, object] = {
        "family_template": f"c/ik_closed_{shape.family}.c.j2",
        "arm_template": f"c/ik_closed_arm_{shape.arm}.c.j2",
        "steps": STEPS[shape.arm],
        "wrist": shape.family != "planar",
        "pose_residual": shape.task == "pose",
        "twists": [
            (name.upper(), value)
            for name, value in shape.structure
            if name.startswith("twist") and value != 0
        ],
    }
    if shape.family == "planar":
        rows = 3 if "z" in shape.task else 2
        context["planar"] = {
            "revolute": shape["revolute"],
            "prismatic": shape["prismatic"],
            "heading": "heading" in shape.task,
            "rows": rows,
            "components": " ".join("xyz"[:rows]),
        }
    return context


def _flags(shape: Shape, macro: str) -> list[tuple[str, str, str]]:
    """``(macro name, hex value, meaning)`` of every flag value the robot's family sets."""
    return [
        (
            f"{macro}_IK_CLOSED_{flag.upper()}_{value.upper()}",
            f"0x{bit:03x}",
            meaning.format(free="q6" if shape.family == "parallel" else "q4"),
        )
        for (flag, value), (bit, meaning) in BRANCH_BITS.items()
        if flag in shape.flags
    ]


def _shifts(robot: Robot) -> list[int]:
    """1 for a revolute joint whose limits do not hold all of ``(-pi, pi]``: a wrapped value
    outside them is moved by whole turns (``closed_form._joint_values``)."""
    return [
        int(
            j.type == "revolute"
            and j.limits is not None
            and not j.limits[0] <= -math.pi < math.pi <= j.limits[1]
        )
        for j in robot.joints
    ]


def emit_ik_closed_c(
    robot: Robot, kernels: tuple[Kernel, ...], precision: str = "double", flags: Sequence[str] = ()
) -> dict[str, str]:
    """``c/<robot>_ik_closed.h`` and ``.c``, which call ``<robot>_fk``; ``{}`` for a robot
    without a closed form."""
    plan = closed_form_plan(robot)
    if plan is None:
        return {}
    (fk,) = [k for k in kernels if k.name == "fk"]
    macro = robot.name.upper()
    header = f"{robot.name}_ik_closed.h"
    lower, upper = _limit_literals(robot, precision)
    literal = {
        **{name: c_literal(value, precision) for name, value in TOLERANCES[precision].items()},
        "pi": c_literal(math.pi, precision),
        "two_pi": c_literal(2 * math.pi, precision),
    }
    shape = plan.shape
    constants = constants_kernel(robot, plan)
    context = {
        "prefix": robot.name,
        "macro": macro,
        "flag": f"{macro}_IK_CLOSED_",
        "guard": f"{macro}_IK_CLOSED_H",
        "real": precision,
        "f": "f" if precision == "float" else "",
        "dof": robot.dof,
        "has_parameters": bool(robot.parameters),
        "header": f"{robot.name}.h",
        "closed_header": header,
        "family": shape.family,
        "family_name": shape.name,
        **_family(shape),
        "library": [*library_files(precision), *CLOSED_FORM_LIBRARY],
        "task_text": TASK_TEXT[shape.task],
        "max_solutions": shape.max_solutions,
        "flags": _flags(shape, macro),
        "constants": c_kernel_layout(constants, precision),
        "head": plan.has("head_inverse"),
        "tail": plan.has("tail_inverse"),
        "literal": literal,
        "text": {name: f"{value:g}" for name, value in TOLERANCES[precision].items()},
        "revolute": [int(j.type == "revolute") for j in robot.joints],
        "shift": _shifts(robot),
        "lower": lower,
        "upper": upper,
        "preamble": preamble_lines(
            robot, (fk, constants), f"C closed-form IK ({precision})", flags
        ),
    }
    return {
        f"c/{header}": render("c/ik_closed.h.j2", **context),
        f"c/{robot.name}_ik_closed.c": render("c/ik_closed.c.j2", **context),
    }
