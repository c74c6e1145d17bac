"""symkin: Denavit–Hartenberg tables to closed-form kinematics and verified code.

The public API::

    robot = symkin.load_robot("scara")        # catalogue name or path to a .toml file
    model = symkin.derive(robot)               # closed-form kinematics (SymPy)
    model.forward_kinematics, model.geometric_jacobian, model.determinant()
    state = symkin.kinematic_state(model, q=[0.1, 0.2, 0.0])   # numbers
    d = symkin.dynamics_derivatives(model, q, dq, ddq)   # dtau/dq, dddq/dq, dJ/dt, ...
    result = symkin.solve_ik(model, symkin.pose_from_target([0.5, 0.2, 0.1]))  # inverse
    motion = symkin.optimal_trajectory(model, symkin.TrajectoryProblem(start=..., goal=...,
                                       final_time=2.0))   # optimal control (CasADi + IPOPT)
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

# Bound at import: the subpackage symkin.derive has the function's name, and importing any of
# its modules would otherwise leave the module where the function belongs.
from symkin.derive import DerivationError, Model, PointMotion, derive
from symkin.emit.latex import jupyter as _jupyter  # noqa: F401  registers Model._repr_latex_

if TYPE_CHECKING:
    from symkin.derive.numeric import numeric_function
    from symkin.derive.regressor import Regressor, regressor
    from symkin.derive.regressor_base import BaseRegressor, base_regressor
    from symkin.errors import RobotError, SymkinError
    from symkin.io import catalogue_names, load_robot, robot_from_toml
    from symkin.output_folder import write_folder
    from symkin.robot import Drive, Joint, Link, Robot
    from symkin.solve.derivatives import DynamicsDerivatives, dynamics_derivatives
    from symkin.solve.draw import arm_figure, draw_arm
    from symkin.solve.elastic_state import MotorSideState, motor_side_state
    from symkin.solve.ellipsoid import Ellipsoids, ellipsoids_at
    from symkin.solve.evaluate import (
        KinematicState,
        PointState,
        kinematic_state,
        operational_space_inertia,
    )
    from symkin.solve.identify import Identification, identify
    from symkin.solve.identify_consistency import Consistency, physical_consistency
    from symkin.solve.identify_excite import Excitation, exciting_trajectory
    from symkin.solve.ik import IKResult, pose_from_target, solve_ik
    from symkin.solve.trajopt import (
        InfeasibleTrajectoryError,
        Trajectory,
        TrajectoryProblem,
        optimal_trajectory,
    )
    from symkin.solve.workspace import Workspace, sample_workspace
    from symkin.spatial import (
        adjoint_from_transform,
        quaternion_product,
        quaternion_slerp,
        rotation_from_rotation_vector,
        rotation_vector_from_rotation,
        transform_from_twist,
        twist_from_transform,
    )
    from symkin.spatial.inertia import (
        RigidBody,
        box_inertia,
        composite_body,
        cylinder_inertia,
        hollow_cylinder_inertia,
        inertia_about_com,
        inertia_about_point,
        rotated_inertia,
        sphere_inertia,
    )
    from symkin.symbols import joint_symbols

# The rest is imported on first use (PEP 562): `symkin` commands that need no SciPy, CasADi or
# plotting do not pay for importing them.
_MODULE_OF = {
    "numeric_function": "symkin.derive.numeric",
    "Regressor": "symkin.derive.regressor",
    "regressor": "symkin.derive.regressor",
    "BaseRegressor": "symkin.derive.regressor_base",
    "base_regressor": "symkin.derive.regressor_base",
    "RobotError": "symkin.errors",
    "SymkinError": "symkin.errors",
    "catalogue_names": "symkin.io",
    "load_robot": "symkin.io",
    "robot_from_toml": "symkin.io",
    "write_folder": "symkin.output_folder",
    "Drive": "symkin.robot",
    "Joint": "symkin.robot",
    "Link": "symkin.robot",
    "Robot": "symkin.robot",
    "DynamicsDerivatives": "symkin.solve.derivatives",
    "dynamics_derivatives": "symkin.solve.derivatives",
    "arm_figure": "symkin.solve.draw",
    "draw_arm": "symkin.solve.draw",
    "MotorSideState": "symkin.solve.elastic_state",
    "motor_side_state": "symkin.solve.elastic_state",
    "Ellipsoids": "symkin.solve.ellipsoid",
    "ellipsoids_at": "symkin.solve.ellipsoid",
    "KinematicState": "symkin.solve.evaluate",
    "PointState": "symkin.solve.evaluate",
    "kinematic_state": "symkin.solve.evaluate",
    "operational_space_inertia": "symkin.solve.evaluate",
    "Identification": "symkin.solve.identify",
    "identify": "symkin.solve.identify",
    "Consistency": "symkin.solve.identify_consistency",
    "physical_consistency": "symkin.solve.identify_consistency",
    "Excitation": "symkin.solve.identify_excite",
    "exciting_trajectory": "symkin.solve.identify_excite",
    "IKResult": "symkin.solve.ik",
    "pose_from_target": "symkin.solve.ik",
    "solve_ik": "symkin.solve.ik",
    "InfeasibleTrajectoryError": "symkin.solve.trajopt",
    "Trajectory": "symkin.solve.trajopt",
    "TrajectoryProblem": "symkin.solve.trajopt",
    "optimal_trajectory": "symkin.solve.trajopt",
    "Workspace": "symkin.solve.workspace",
    "sample_workspace": "symkin.solve.workspace",
    "adjoint_from_transform": "symkin.spatial",
    "quaternion_product": "symkin.spatial",
    "quaternion_slerp": "symkin.spatial",
    "rotation_from_rotation_vector": "symkin.spatial",
    "rotation_vector_from_rotation": "symkin.spatial",
    "transform_from_twist": "symkin.spatial",
    "twist_from_transform": "symkin.spatial",
    "RigidBody": "symkin.spatial.inertia",
    "box_inertia": "symkin.spatial.inertia",
    "composite_body": "symkin.spatial.inertia",
    "cylinder_inertia": "symkin.spatial.inertia",
    "hollow_cylinder_inertia": "symkin.spatial.inertia",
    "inertia_about_com": "symkin.spatial.inertia",
    "inertia_about_point": "symkin.spatial.inertia",
    "rotated_inertia": "symkin.spatial.inertia",
    "sphere_inertia": "symkin.spatial.inertia",
    "joint_symbols": "symkin.symbols",
}


def __getattr__(name: str) -> Any:
    module = _MODULE_OF.get(name)
    if module is None:
        raise AttributeError(f"module 'symkin' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_MODULE_OF))


__all__ = [
    "BaseRegressor",
    "Consistency",
    "DerivationError",
    "Drive",
    "DynamicsDerivatives",
    "Ellipsoids",
    "Excitation",
    "IKResult",
    "Identification",
    "InfeasibleTrajectoryError",
    "Joint",
    "KinematicState",
    "Link",
    "Model",
    "MotorSideState",
    "PointMotion",
    "PointState",
    "Regressor",
    "RigidBody",
    "Robot",
    "RobotError",
    "SymkinError",
    "Trajectory",
    "TrajectoryProblem",
    "Workspace",
    "adjoint_from_transform",
    "arm_figure",
    "base_regressor",
    "box_inertia",
    "catalogue_names",
    "composite_body",
    "cylinder_inertia",
    "derive",
    "draw_arm",
    "dynamics_derivatives",
    "ellipsoids_at",
    "exciting_trajectory",
    "hollow_cylinder_inertia",
    "identify",
    "inertia_about_com",
    "inertia_about_point",
    "joint_symbols",
    "kinematic_state",
    "load_robot",
    "motor_side_state",
    "numeric_function",
    "operational_space_inertia",
    "optimal_trajectory",
    "physical_consistency",
    "pose_from_target",
    "quaternion_product",
    "quaternion_slerp",
    "regressor",
    "robot_from_toml",
    "rotated_inertia",
    "rotation_from_rotation_vector",
    "rotation_vector_from_rotation",
    "sample_workspace",
    "solve_ik",
    "sphere_inertia",
    "transform_from_twist",
    "twist_from_transform",
    "write_folder",
]
