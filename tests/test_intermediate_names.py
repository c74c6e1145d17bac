"""A parameter may be named like the numbered intermediates of a derivation step.

The Newton–Euler recursions, the regressor, the elastic motor side, the point motion, the
Lagrange CSE, the tangent sweeps of the derivatives and the kernels' CSE name their
intermediates ``<prefix><k>`` (``s0, s1, ...``); a robot parameter named ``s1`` once became
an intermediate of the same name (same SymPy symbol) and ``derive`` died with an internal
error.  Each prefix below is one the code base uses (``Recorder("...")`` in ``derive/``, the
prefixes of ``derive/derivatives.py``, ``kernels/derivatives.py``, ``derive/lagrange.py``,
``kernels/spec.py``).  The expected numbers are those of the same arm with the parameter
named ``L``, and the hand-derived position of the arm.
"""

from __future__ import annotations

import functools
import math
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

from codegen_helpers import import_path, write_tree
from symkin.errors import RobotError
from symkin.generate import files_for_robot
from symkin.io import robot_from_toml

LINK = """
[joints.link]
mass = 2.0
com = [0.1, 0.0, 0.0]
inertia = {{ ixx = 0.01, iyy = 0.02, izz = 0.03 }}
motor_inertia = 0.1
friction = {{ coulomb = 0.2, viscous = 0.3 }}
{extra}
"""

# Recorder prefixes (b, y, s, r, m, dts, ddts), Lagrange's CSE (l), the kernels' CSE (t),
# the derivative sweeps (sq<j>_, sv<j>_, jd), each with the index of an intermediate.
NAMES = ["b1", "y1", "s0", "s1", "s2", "s12", "r1", "m0", "dts1", "ddts0", "l1", "t1",
         "sq0_1", "sv0_0", "sv1_2", "jd1"]  # fmt: skip

STATE = {
    "q": np.array([0.4, -1.1, 0.25]),
    "dq": np.array([0.7, 0.3, -0.2]),
    "ddq": np.array([-0.5, 1.2, 0.9]),
    "tau": np.array([1.0, -2.0, 3.0]),
    "wrench": np.array([1.0, 2.0, 3.0, 0.1, 0.2, 0.3]),
    "d3q": np.array([0.2, -0.4, 0.6]),
    "d4q": np.array([-0.3, 0.5, 0.1]),
}
KERNELS = {
    "fk": ("q",), "jacobian": ("q",), "mass_matrix": ("q",), "gravity": ("q",),
    "coriolis": ("q", "dq"), "coriolis_matrix": ("q", "dq"), "mass_matrix_bias": ("q", "dq"),
    "inverse_dynamics": ("q", "dq", "ddq"), "wrench_torque": ("q", "wrench"),
    "energy": ("q", "dq"), "inverse_dynamics_derivatives": ("q", "dq", "ddq"),
    "jacobian_derivative": ("q", "dq"), "point1": ("q", "dq", "ddq"),
    "regressor": ("q", "dq", "ddq"), "base_regressor": ("q", "dq", "ddq"),
    "mass_matrix_barycentric": ("q",), "inverse_dynamics_barycentric": ("q", "dq", "ddq"),
    "forward_dynamics": ("q", "dq", "tau"),
    "elastic_inverse_dynamics": ("q", "dq", "ddq", "d3q", "d4q"),
}  # fmt: skip


def rrp_arm(name: str) -> str:
    """A 3-joint RRP arm (standard DH) whose first link length is the parameter ``name``;
    the second joint is elastic, so the motor-side derivation runs too."""
    text = f'name = "rrp"\nangles = "rad"\n[parameters]\n{name} = 0.7\n'
    rows = [("revolute", f'a = "{name}"', ""), ("revolute", "a = 0.3", "stiffness = 100")]
    rows.append(("prismatic", "alpha = 1.0", ""))
    for kind, row, extra in rows:
        text += f'[[joints]]\ntype = "{kind}"\n{row}\n' + LINK.format(extra=extra)
    return text


@functools.cache
def arm_module(name: str, directory: str) -> ModuleType:
    robot = robot_from_toml(rrp_arm(name), f"{name}.toml")
    files = files_for_robot(
        robot, ("numpy",), points=[(3, (0.1, 0.0, 0.0))], derivatives=True, regressor=True
    )
    root = f"{directory}/{name}"
    write_tree(Path(root), files)
    return import_path(f"rrp_{name}", Path(root, "numpy/rrp_kinematics.py"))


def outputs(module: ModuleType, kernel: str) -> list[np.ndarray]:
    # The barycentric kernels take the parameter vector delta (38 values for this arm).
    delta = {"delta": np.linspace(0.1, 1.0, 38)} if kernel.endswith("_barycentric") else {}
    result = getattr(module, kernel)(*(STATE[a] for a in KERNELS[kernel]), **delta)
    return [np.asarray(r) for r in (result if isinstance(result, tuple) else (result,))]


@pytest.mark.parametrize("name", NAMES)
def test_a_parameter_named_like_an_intermediate_gives_the_numbers_of_the_arm_with_l(
    name, tmp_path_factory
) -> None:
    directory = str(tmp_path_factory.getbasetemp())
    module, reference = arm_module(name, directory), arm_module("L", directory)
    q = STATE["q"]
    # Hand derivation: x = a1 cos q1 + a2 cos(q1 + q2), y likewise with sin, z = d3 = q3.
    position = [
        0.7 * math.cos(q[0]) + 0.3 * math.cos(q[0] + q[1]),
        0.7 * math.sin(q[0]) + 0.3 * math.sin(q[0] + q[1]),
        q[2],
    ]
    np.testing.assert_allclose(module.fk(q)[:3, 3], position, atol=1e-12)
    for kernel in KERNELS:
        for got, expected in zip(outputs(module, kernel), outputs(reference, kernel), strict=True):
            np.testing.assert_allclose(got, expected, rtol=1e-10, atol=1e-12, err_msg=kernel)


@pytest.mark.parametrize(("name", "link"), [("m1", 1), ("xx2", 2), ("mz3", 3), ("fv2", 2)])
def test_a_parameter_named_like_a_regressor_column_is_a_robot_error(name, link) -> None:
    """The identification kernels name their columns xx<i> .. m<i>, ia<i>, fv<i>, fc<i>: a
    parameter of that name was a NameError inside the derivation (an internal error)."""
    robot = robot_from_toml(rrp_arm(name), "arm.toml")
    with pytest.raises(RobotError, match=rf"arm.toml: parameter '{name}' .* of link {link}"):
        files_for_robot(robot, ("numpy",), regressor=True)


def test_a_name_with_a_leading_zero_is_not_a_regressor_column() -> None:
    """``m01`` is no column's name (the columns are m1, m2, ...): it derives."""
    robot = robot_from_toml(rrp_arm("m01"), "arm.toml")
    files = files_for_robot(robot, ("numpy",), regressor=True)
    assert any(path.endswith(".py") for path in files)
