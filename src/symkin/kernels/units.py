"""Units of kernel outputs: SI, angles in rad, a joint's unit rad (revolute) or m (prismatic).

The texts go into the comments of generated code.  Entries that mix joints of both types
(a Jacobian column per joint, a torque per joint, a mass-matrix entry per pair of joints)
name the unit per row, column or joint.
"""

from __future__ import annotations

from collections.abc import Sequence

from symkin.robot import Robot

POSE = "rotation (rows 0-2, columns 0-2) dimensionless, position (column 3) in m, last row 0 0 0 1"
POSITION = "m"
VELOCITY = "m/s"
ACCELERATION = "m/s^2"
INERTIAL = "m in kg, cx cy cz in m, ixx iyy izz ixy ixz iyz in kg m^2"
PARAMETERS = "SI units, angles in rad"


def _joints(robot: Robot, kind: str) -> list[str]:
    return [f"q{i}" for i, joint in enumerate(robot.joints, start=1) if joint.type == kind]


def per_joint(robot: Robot, revolute: str, prismatic: str) -> str:
    """``"N m"`` when every joint is revolute, else ``"N m for q1, q2; N for q3"``."""
    groups = [(revolute, _joints(robot, "revolute")), (prismatic, _joints(robot, "prismatic"))]
    groups = [(unit, names) for unit, names in groups if names]
    if len(groups) == 1:
        return groups[0][0]
    return "; ".join(f"{unit} for {', '.join(names)}" for unit, names in groups)


def joint_units(robot: Robot) -> str:
    """The unit of each joint coordinate: ``"rad"``, ``"m"`` or ``"rad for q1; m for q2"``."""
    return per_joint(robot, "rad", "m")


def jacobian(robot: Robot, angular: bool) -> str:
    """Rows x y z in m (and wx wy wz in rad) per unit of the column's joint."""
    rows = "rows x y z in m and rows wx wy wz in rad, each" if angular else "m"
    return f"{rows} per unit of the column's joint ({joint_units(robot)})"


def unit_product(exponents: dict[str, int]) -> str:
    """``{"m": 2, "rad": -2}`` as ``"m^2/rad^2"``; ``"dimensionless"`` when all are zero."""

    def power(unit: str, exponent: int) -> str:
        return unit if exponent == 1 else f"{unit}^{exponent}"

    above = " ".join(power(u, e) for u, e in exponents.items() if e > 0) or "1"
    below = " ".join(power(u, -e) for u, e in exponents.items() if e < 0)
    if above == "1" and not below:
        return "dimensionless"
    return f"{above}/{below}" if below else above


def determinant(robot: Robot, task_rows: Sequence[str]) -> str:
    """The unit of det J for the task rows: m per position row, rad per rotation row, divided
    by the unit of every joint."""
    positions = sum(1 for row in task_rows if not row.startswith("w"))
    return unit_product(
        {
            "m": positions - len(_joints(robot, "prismatic")),
            "rad": len(task_rows) - positions - len(_joints(robot, "revolute")),
        }
    )


def manipulability(robot: Robot, task_rows: Sequence[str]) -> str:
    """The unit of ``sqrt(det(J J^T))`` for a redundant arm (more joints than task rows): as
    det of a square task Jacobian when every joint has one type (each square minor then has
    that unit); mixed joint types give minors of different units."""
    kinds = {joint.type for joint in robot.joints}
    if len(kinds) > 1:
        return "mixed: the square minors of J J^T differ in unit (revolute and prismatic joints)"
    positions = sum(1 for row in task_rows if not row.startswith("w"))
    size = len(task_rows)
    moving = {
        "m": size if kinds == {"prismatic"} else 0,
        "rad": size if kinds == {"revolute"} else 0,
    }
    return unit_product({"m": positions - moving["m"], "rad": size - positions - moving["rad"]})


def generalized_force(robot: Robot) -> str:
    """Joint torques or forces: N m for a revolute joint, N for a prismatic one."""
    return per_joint(robot, "N m", "N")


def joint_acceleration(robot: Robot) -> str:
    return per_joint(robot, "rad/s^2", "m/s^2")


def _pairs(robot: Robot, units: tuple[str, str, str]) -> str:
    """Entry (i, j) relating joints i and j: ``units`` for two, one or no revolute joints."""
    kinds = {joint.type for joint in robot.joints}
    if kinds == {"revolute"}:
        return units[0]
    if kinds == {"prismatic"}:
        return units[2]
    return (
        f"entry (i, j): {units[0]}, {units[1]} or {units[2]} when two, one or none of joints "
        "i and j are revolute"
    )


def mass_matrix(robot: Robot) -> str:
    return _pairs(robot, ("kg m^2", "kg m", "kg"))


def coriolis_matrix(robot: Robot) -> str:
    return _pairs(robot, ("kg m^2/s", "kg m/s", "kg/s"))
