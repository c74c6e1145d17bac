"""Parameter and robot names against what generated code and SymPy already use.

The fuzzing that found ``[parameters] M = 0.7`` printing ``M = [[0.0]]`` (the mass-matrix
output overwrote the parameter) is turned into three checks: every name the kernels generate
is in ``symkin.names``'s reserved sets (so the list cannot fall behind the kernels), reserved
names are rejected with one message, and unusual names that are allowed give the numbers of
the hand-derived formula in NumPy, CasADi and strict C.
"""

from __future__ import annotations

import math
import subprocess

import numpy as np
import pytest

import symkin
from codegen_helpers import CC, STRICT, import_path, write_tree
from symkin.derive import derive
from symkin.errors import RobotError
from symkin.generate import files_for_robot, robot_kernels
from symkin.io import robot_from_toml
from symkin.kernels import point_kernels
from symkin.names import reserved_reason, robot_name_reason


@pytest.mark.parametrize("name", ["scara", "puma560", "planar_2r"])
def test_every_name_the_kernels_generate_is_reserved(name: str) -> None:
    model = derive(symkin.load_robot(name))
    kernels = robot_kernels(model) + point_kernels(model, [(1, (0.1, 0.2, 0.3))])
    generated = {k.name for k in kernels}
    generated |= {i.name for k in kernels for i in k.inputs}
    generated |= {o.name for k in kernels for o in k.outputs}
    unreserved = sorted(n for n in generated if reserved_reason(n) is None)
    assert not unreserved, f"kernel names a parameter could shadow: {unreserved}"


def two_link(first: str, second: str, values: tuple[float, float] = (0.5, 0.3)) -> str:
    return f"""
name = "two_link"
[parameters]
{first} = {values[0]}
{second} = {values[1]}
[[joints]]
type = "revolute"
a = "{first}"
[[joints]]
type = "revolute"
a = "{second}"
"""


@pytest.mark.parametrize(
    "name",
    ["M", "mu", "tau", "NAN", "INFINITY", "fabs", "hypot", "sum", "int", "C", "point1", "_x",
     "batch", "count", "numpy", "size_t", "pi", "q3"],
)  # fmt: skip
def test_reserved_parameter_names_are_rejected_with_the_reason(name: str) -> None:
    with pytest.raises(RobotError, match=rf"'parameters\.{name}'.*reserved"):
        robot_from_toml(two_link(name, "L2"), "arm.toml")


@pytest.mark.parametrize("name", ["math", "stdio", "string", "int"])
def test_robot_names_that_would_hide_a_c_header_are_rejected(name: str) -> None:
    assert robot_name_reason(name) is not None
    text = two_link("L1", "L2").replace('name = "two_link"', f'name = "{name}"')
    with pytest.raises(RobotError, match="reserved"):
        robot_from_toml(text, "arm.toml")


# Allowed names that look like what code uses nearby (single letters, words of the templates'
# prose, case variants of outputs): each pair must give the hand-derived forward kinematics.
ALLOWED_PAIRS = [("h", "w"), ("x", "y"), ("theta", "value"), ("m", "Mu"), ("Tau", "L")]


@pytest.mark.needs_cc
@pytest.mark.parametrize(("first", "second"), ALLOWED_PAIRS)
def test_allowed_unusual_names_give_the_hand_derived_numbers(tmp_path, first, second) -> None:
    robot = robot_from_toml(two_link(first, second), "arm.toml")
    files = files_for_robot(robot, ("numpy", "casadi", "c"))
    write_tree(tmp_path, files)
    q = np.array([0.4, -1.1])
    # x = a1 cos q1 + a2 cos(q1 + q2), y likewise with sin (the planar 2R arm).
    expected = [
        0.5 * math.cos(q[0]) + 0.3 * math.cos(q[0] + q[1]),
        0.5 * math.sin(q[0]) + 0.3 * math.sin(q[0] + q[1]),
    ]
    numpy_module = import_path("two_link_np", tmp_path / "numpy" / "two_link_kinematics.py")
    np.testing.assert_allclose(numpy_module.fk(q)[:2, 3], expected, atol=1e-12)
    casadi_module = import_path("two_link_ca", tmp_path / "casadi" / "two_link_casadi.py")
    T = np.array(casadi_module.fk_function()(q, numpy_module.DEFAULT_PARAMETERS))
    np.testing.assert_allclose(T[:2, 3], expected, atol=1e-12)
    compiled = subprocess.run(
        [CC, *STRICT, "-c", "two_link.c", "-o", "two_link.o"],
        cwd=tmp_path / "c",
        capture_output=True,
        text=True,
        check=False,
    )
    assert compiled.returncode == 0, compiled.stderr


def test_an_exception_inside_a_derivation_names_the_robot_and_the_quantity(monkeypatch):
    from symkin.derive import jacobians

    def broken(*_args, **_kwargs):
        raise TypeError("cannot determine truth value of Relational")

    monkeypatch.setattr(jacobians, "determinant_matrix", broken)
    robot = robot_from_toml(two_link("L1", "L2"), "arm.toml")
    with pytest.raises(symkin.DerivationError, match=r"two_link: cannot derive the Jacobian "
                       r"determinant: TypeError: cannot determine truth value"):  # fmt: skip
        symkin.derive(robot).determinant()


def test_a_robot_named_example_is_rejected_its_source_would_be_the_demo():
    text = two_link("L1", "L2").replace('name = "two_link"', 'name = "example"')
    with pytest.raises(RobotError, match=r"example\.c"):
        robot_from_toml(text, "arm.toml")


@pytest.mark.parametrize("name", ["symkin", "symkin_dls"])
def test_robot_names_in_the_c_library_namespace_are_rejected(name: str):
    # Generated C pastes templates/c/lib, whose names are symkin_*: a robot called symkin
    # would declare symkin_fk_jacobian twice (found by the CLI fuzzer).
    text = two_link("L1", "L2").replace('name = "two_link"', f'name = "{name}"')
    with pytest.raises(RobotError, match=r"symkin_\*"):
        robot_from_toml(text, "arm.toml")


@pytest.mark.parametrize("name", ["real_t", "REAL", "SYMKIN_RESTRICT", "symkin_xorshift64"])
def test_parameter_names_of_the_pasted_c_library_are_rejected(name: str):
    text = two_link("L1", name)
    with pytest.raises(RobotError, match="C library pasted"):
        robot_from_toml(text, "arm.toml")


def test_nested_powers_are_held_to_the_exponent_cap():
    text = two_link("L1", "L2").replace('a = "L1"', 'a = "((((L1 + L2)/2)**4)**4)**4"')
    with pytest.raises(RobotError, match=r"power 64, outside \[-4, 4\]"):
        robot_from_toml(text, "arm.toml")
