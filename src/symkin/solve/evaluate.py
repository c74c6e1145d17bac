"""Numeric evaluation of a model at given states: pose, Jacobian measures, point motion,
dynamics.

Parameters take their file values unless overridden.  The numbers come from the generated
NumPy kernels (:mod:`symkin.runtime.modules`), built once per robot and process; the test
suite checks them against numeric DH products, finite differences and other toolboxes.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from symkin.derive import Model
from symkin.derive.jacobians import rows_from_names
from symkin.errors import ParameterError, SymkinError
from symkin.kernels import inertial_symbols
from symkin.runtime.modules import generated_numpy_module, generated_point_module
from symkin.solve.ik.joints import parameter_vector
from symkin.spatial import euler_zyx_from_rotation


@dataclass(frozen=True)
class PointState:
    """A point fixed in a link: its coordinates in that link's frame and its base-frame motion.

    ``velocity`` needs joint velocities and ``acceleration`` joint accelerations too;
    either is ``None`` when they were not given.
    """

    link: int
    point: tuple[float, float, float]
    position: np.ndarray
    velocity: np.ndarray | None
    acceleration: np.ndarray | None


@dataclass(frozen=True)
class KinematicState:
    """Numeric kinematics at one configuration (SI units, radians, base frame).

    ``determinant``, ``manipulability``, ``condition_number`` and ``smallest_singular_value``
    are those of the task Jacobian (rows ``task_rows``); see :func:`singular_value_measures`.
    """

    transform: np.ndarray
    position: np.ndarray
    euler_zyx: np.ndarray
    euler_zyx_singular: bool
    jacobian: np.ndarray
    task_rows: tuple[str, ...]
    determinant: float | None
    manipulability: float
    points: tuple[PointState, ...]
    condition_number: float
    smallest_singular_value: float


def singular_value_measures(jacobian: np.ndarray) -> tuple[float, float]:
    """``(smallest singular value, condition number)`` of an m x n Jacobian.

    The smallest of its ``min(m, n)`` singular values, and the ratio of the largest to it; the
    condition number is ``inf`` when the matrix is rank deficient by NumPy's ``matrix_rank``
    test (smallest ``<= max(m, n) * eps * largest``), i.e. at a singular configuration.  Both
    depend on units when the rows mix positions (metres) and angles (radians): they are
    computed on the rows given, as they are.
    """
    values = np.linalg.svd(np.asarray(jacobian, dtype=float), compute_uv=False)
    if values.size == 0:
        return 0.0, math.inf
    largest, smallest = float(values[0]), float(values[-1])
    if smallest <= max(jacobian.shape) * np.finfo(float).eps * largest:
        return smallest, math.inf
    return smallest, largest / smallest


def _check_lengths(model: Model, *states: Sequence[float] | None) -> None:
    """``q``, ``dq``, ``ddq`` (those given) hold one value per joint."""
    n = model.robot.dof
    for name, values in zip(("q", "dq", "ddq"), states, strict=False):
        if values is not None and len(values) != n:
            raise ParameterError(f"{{{name}}} needs {n} values (one per joint), got {len(values)}")


def kinematic_state(
    model: Model,
    q: Sequence[float],
    dq: Sequence[float] | None = None,
    ddq: Sequence[float] | None = None,
    overrides: Mapping[str, float] | None = None,
    points: Sequence[tuple[int, Sequence[float]]] = (),
    rows: Sequence[str] | None = None,
) -> KinematicState:
    """Pose, Jacobian, determinant, manipulability and point motion at one state.

    The determinant, manipulability, condition number and smallest singular value are those
    of the task Jacobian (``rows``, or the model's default task rows), computed numerically.
    Everything comes from the generated NumPy kernels of the model's product form, built once
    per robot (and point set) and process: no readable form, determinant or singular set is
    derived, and a repeated call costs the kernels' arithmetic, not a rebuild.
    """
    _check_lengths(model, q, dq, ddq)
    rows = tuple(rows or model.task_rows)
    parameters = parameter_vector(model, overrides)
    with np.errstate(all="ignore"):
        transform, jacobian = generated_numpy_module(model, "kinematics").fk_jacobian(q, parameters)
    _require_finite(model, parameters, "kinematics", transform, jacobian)
    euler = euler_zyx_from_rotation(transform[:3, :3])
    task = jacobian[list(rows_from_names(rows)), :]
    if task.shape[0] == task.shape[1]:
        # Square: |det J| exactly, not sqrt(det(J J^T)), which rounds 0 up to ~1e-8.
        determinant = float(np.linalg.det(task))
        manipulability = abs(determinant)
    else:
        determinant = None
        manipulability = float(np.sqrt(max(np.linalg.det(task @ task.T), 0.0)))
    smallest, condition = singular_value_measures(task)
    return KinematicState(
        transform=transform,
        position=transform[:3, 3].copy(),
        euler_zyx=np.array([euler.psi, euler.theta, euler.phi], dtype=float),
        euler_zyx_singular=bool(euler.singular),
        jacobian=jacobian,
        task_rows=rows,
        determinant=determinant,
        manipulability=manipulability,
        points=_point_states(model, points, parameters, q, dq, ddq),
        condition_number=condition,
        smallest_singular_value=smallest,
    )


def _point_states(
    model: Model,
    points: Sequence[tuple[int, Sequence[float]]],
    parameters: np.ndarray,
    q: Sequence[float],
    dq: Sequence[float] | None,
    ddq: Sequence[float] | None,
) -> tuple[PointState, ...]:
    """Motion of each point from the generated point kernels (velocity needs ``dq``,
    acceleration ``dq`` and ``ddq``)."""
    if not points:
        return ()
    key = tuple((int(link), tuple(float(c) for c in point)) for link, point in points)
    module = generated_point_module(model, key)
    zeros = np.zeros(model.robot.dof)
    rates = (zeros if dq is None else dq, zeros if ddq is None else ddq)
    states = []
    for k, (link, point) in enumerate(key, start=1):
        position, velocity, acceleration = getattr(module, f"point{k}")(q, *rates, parameters)
        states.append(
            PointState(
                link=link,
                point=point,
                position=position,
                velocity=None if dq is None else velocity,
                acceleration=None if dq is None or ddq is None else acceleration,
            )
        )
    return tuple(states)


@dataclass(frozen=True)
class DynamicState:
    """Numeric equations of motion at one state: ``tau = M ddq + c + G + F - J^T w``.

    ``c`` needs joint velocities and ``tau`` velocities and accelerations; either is ``None``
    when they were not given.  With a wrench ``w`` on the tool (docs/conventions.md, External
    wrench), ``wrench_torque = -J^T w`` (included in ``tau``) and the statics
    ``static_torque = G - J^T w``; without one both are ``None``.  The energies
    ``T = 1/2 dq^T M dq``, ``V = -sum m g^T p_c`` and ``L = T - V`` (``T`` and ``L`` need
    ``dq``).
    """

    mass_matrix: np.ndarray
    gravity: np.ndarray
    coriolis: np.ndarray | None
    torque: np.ndarray | None
    wrench_torque: np.ndarray | None = None
    static_torque: np.ndarray | None = None
    kinetic_energy: float | None = None
    potential_energy: float | None = None
    lagrangian: float | None = None


def dynamics_arguments(
    model: Model, overrides: Mapping[str, float] | None = None
) -> dict[str, np.ndarray]:
    """``{"p": ..., "pi": ...}``: the parameter vector and, when the robot file leaves inertial
    data out, the inertial values, in the order of the generated dynamics' inputs.

    ``overrides`` may name robot parameters and the inertial symbols of links the robot file
    leaves without data (``m1``, ``cx1``, ..., ``iyz1``); every such symbol needs a value.
    """
    overrides = dict(overrides or {})
    inertial_names = [s.name for s in inertial_symbols(model)]
    inertial = {k: overrides.pop(k) for k in list(overrides) if k in inertial_names}
    missing = [name for name in inertial_names if name not in inertial]
    if missing:
        robot = model.robot
        where = f"{robot.file}: " if robot.file else ""
        raise ParameterError(
            f"{where}{robot.name} has no inertial data for {', '.join(missing)}; give them in "
            "the robot file ([joints.link], or each link's <inertial> in a URDF) or with "
            "{overrides}"
        )
    values = model.robot.parameter_values(overrides)
    arguments = {"p": np.array([values[name] for name, _ in model.robot.parameters])}
    if inertial_names:
        arguments["pi"] = np.array([inertial[name] for name in inertial_names])
    return arguments


def dynamic_state(
    model: Model,
    q: Sequence[float],
    dq: Sequence[float] | None = None,
    ddq: Sequence[float] | None = None,
    overrides: Mapping[str, float] | None = None,
    wrench: Sequence[float] | None = None,
) -> DynamicState:
    """``M``, ``G``, ``c``, ``tau``, the energies and, given ``wrench = (fx, fy, fz, nx, ny,
    nz)`` on the tool (base frame, at the tool point), ``-J^T w`` and ``G - J^T w``, from the
    Newton–Euler kernels.

    ``overrides`` may name robot parameters and the inertial symbols of links the robot file
    leaves without data (``m1``, ``cx1``, ..., ``iyz1``); every such symbol needs a value.
    """
    _check_lengths(model, q, dq, ddq)
    _check_wrench(wrench)
    shared = dynamics_arguments(model, overrides)
    module = generated_numpy_module(model)
    with np.errstate(all="ignore"):
        external = None if wrench is None else module.wrench_torque(q, wrench, shared["p"])
        torque = None
        if dq is not None and ddq is not None:
            torque = module.inverse_dynamics(q, dq, ddq, **shared)
            torque = torque if external is None else torque + external
        kinetic, potential, lagrangian = module.energy(
            q, np.zeros(len(q)) if dq is None else dq, **shared
        )
        state = DynamicState(
            mass_matrix=module.mass_matrix(q, **shared),
            gravity=module.gravity(q, **shared),
            coriolis=None if dq is None else module.coriolis(q, dq, **shared),
            torque=torque,
            wrench_torque=external,
            static_torque=None if wrench is None else module.static_torque(q, wrench, **shared),
            kinetic_energy=None if dq is None else float(kinetic),
            potential_energy=float(potential),
            lagrangian=None if dq is None else float(lagrangian),
        )
    values = (state.mass_matrix, state.gravity, state.coriolis, state.torque, potential, kinetic)
    _require_finite(model, shared["p"], "dynamics", *(v for v in values if v is not None))
    return state


def _check_wrench(wrench: Sequence[float] | None) -> None:
    """Six finite numbers, or ``None``."""
    if wrench is None:
        return
    values = np.asarray(wrench, dtype=float).ravel()
    if values.size != 6 or not np.all(np.isfinite(values)):
        raise ParameterError(
            f"{{wrench}} needs six finite numbers (fx, fy, fz, nx, ny, nz), got {list(wrench)}"
        )


def _require_finite(
    model: Model, parameters: np.ndarray, quantity: str, *values: np.ndarray
) -> None:
    """A :class:`ParameterError` where a generated kernel returned inf or NaN: with finite
    joint values only the parameters can do that (a length like ``1/(2 L1 - 1)`` at its
    pole), so the message names their values."""
    if all(np.all(np.isfinite(v)) for v in values):
        return
    names = [name for name, _ in model.robot.parameters]
    given = ", ".join(
        f"{n} = {float(v):g}" for n, v in zip(names, np.ravel(parameters), strict=False)
    )
    raise ParameterError(
        f"{model.robot.name}: the {quantity} are not finite at the parameter values "
        f"({given or 'none'}): a formula divides by zero there; choose other values with "
        "{overrides}"
    )


def operational_space_inertia(
    model: Model,
    q: Sequence[float],
    rows: Sequence[str] | None = None,
    overrides: Mapping[str, float] | None = None,
) -> np.ndarray:
    """Khatib's operational-space inertia ``Lambda(q) = (J M^-1 J^T)^-1`` of the task rows.

    ``J`` is the task Jacobian (``rows`` of the base-frame geometric Jacobian, or the model's
    default task rows) and ``M`` the joint-space mass matrix of the generated NumPy dynamics;
    ``overrides`` as for :func:`dynamic_state`.  ``Lambda`` maps task accelerations to task
    forces (``F = Lambda dv/dt`` without velocity and gravity terms); mixed position and
    orientation rows give a matrix whose blocks carry different units.

    Raises :class:`SymkinError` where ``J M^-1 J^T`` is singular, i.e. where the task
    Jacobian loses rank (the :func:`singular_value_measures` test: condition number ``inf``)
    or has more rows than the robot has joints.
    """
    _check_lengths(model, q)
    rows = tuple(rows or model.task_rows)
    parameter_names = {name for name, _ in model.robot.parameters}
    kinematic_overrides = {k: v for k, v in (overrides or {}).items() if k in parameter_names}
    state = kinematic_state(model, q, overrides=kinematic_overrides, rows=rows)
    task = state.jacobian[list(rows_from_names(rows)), :]
    if math.isinf(state.condition_number) or task.shape[0] > task.shape[1]:
        raise SymkinError(
            f"{model.robot.name}: the task Jacobian (rows {', '.join(rows)}) loses rank at this "
            f"configuration (smallest singular value {state.smallest_singular_value:.3g}), so "
            "the operational-space inertia (J M^-1 J^T)^-1 does not exist"
        )
    mass = dynamic_state(model, q, overrides=overrides).mass_matrix
    mobility = task @ np.linalg.solve(mass, task.T)
    inertia = np.linalg.inv(mobility)
    return (inertia + inertia.T) / 2
