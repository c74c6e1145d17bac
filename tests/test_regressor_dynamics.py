"""The dynamics of barycentric parameters: ``mass_matrix_barycentric`` and
``inverse_dynamics_barycentric`` (``symkin derive --regressor``), inputs the regressor's
parameter vector ``delta``.

Expected values come from outside these kernels: the generated file-form dynamics (the robot
file's mass, centre of mass and inertia about it) with the file's data converted here by the
parallel-axis theorem (its tau is a separate recursion; its M uses the same
composite-rigid-body algorithm, so ``tests/test_mass_matrix_methods.py`` checks that M against
Lagrange's); the generated regressor (``tau = Y delta`` for any ``delta``); finite differences
of ``tau`` in ``ddq`` (``M``); Robotics Toolbox's ``inertia`` and ``rne`` (tests marked
``oracle``); and the operation count SymPyBotics' mass matrix has for the PUMA 560
(``bench/inertial_parameters.py`` runs it). Every backend (NumPy, C through gcc and ctypes,
CasADi, the CPython extension) must give the same numbers.
"""

from __future__ import annotations

import ctypes
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

import symkin
from codegen_helpers import CC, CONVERSION, SHARED, STRICT, import_path, run_parallel, write_tree
from symkin.cli import main
from symkin.derive.regressor import parameter_symbols
from symkin.derive.regressor_base import base_regressor
from symkin.emit.numpy import emit_numpy
from symkin.kernels import dynamics_kernels
from symkin.kernels.regressor import barycentric_kernels
from symkin.runtime.extension import load_extension
from symkin.runtime.modules import generated_numpy_module
from symkin.solve.identify import identify
from test_regressor import FRICTION_ARM, I1, I2, L1, LC1, LC2, M1, M2, planar_torques

ROOT = Path(__file__).resolve().parents[1]
# SymPyBotics' mass matrix of the PUMA 560 with symbolic (barycentric) inertia and numeric
# geometry, its own incremental CSE counted with symkin's counter (docs/benchmarks.md).
SYMPYBOTICS_PUMA_M = 780
TOLERANCE = 1e-10
TENSOR_ENTRIES = {
    "xx": (0, 0),
    "xy": (0, 1),
    "xz": (0, 2),
    "yy": (1, 1),
    "yz": (1, 2),
    "zz": (2, 2),
}


def link_values(i: int, m: float, c: np.ndarray, inertia: np.ndarray) -> dict[str, float]:
    """Link ``i``'s barycentric parameters by the parallel-axis theorem written out here
    (Khalil & Dombre eq. 9.4, ``I_o = I_c + m (c.c E - c c^T)``), first moments ``m c``, mass."""
    about_origin = inertia + m * (c @ c * np.eye(3) - np.outer(c, c))
    values = {f"{name}{i}": about_origin[entry] for name, entry in TENSOR_ENTRIES.items()}
    return values | {f"mx{i}": m * c[0], f"my{i}": m * c[1], f"mz{i}": m * c[2], f"m{i}": m}


def file_delta(robot: symkin.Robot) -> np.ndarray:
    """The robot file's data as ``delta``: per link :func:`link_values`, then the drive
    parameters the file gives (rotor inertia, viscous, Coulomb)."""
    values = {}
    for i, joint in enumerate(robot.joints, start=1):
        link = joint.link
        m, c = float(link.mass), np.array([float(x) for x in link.com])
        values |= link_values(i, m, c, np.array(link.inertia_matrix, dtype=float))
        values[f"ia{i}"] = float(link.motor_inertia)
        values[f"fv{i}"] = float(link.viscous)
        values[f"fc{i}"] = values[f"fcp{i}"] = float(link.coulomb)
        if link.coulomb_negative is not None:
            values[f"fcn{i}"] = float(link.coulomb_negative)
    return np.array([values[s.name] for s in parameter_symbols(robot)])


@pytest.fixture(scope="module")
def arm(tmp_path_factory):
    """The friction arm (modified DH, a prismatic joint, rotor inertia, viscous and
    direction-dependent Coulomb friction) through ``symkin derive --regressor``, every backend,
    and its C file compiled on its own with gcc."""
    root = tmp_path_factory.mktemp("barycentric_arm")
    path = root / "friction_arm.toml"
    path.write_text(FRICTION_ARM, encoding="utf-8")
    out = root / "out"
    assert main(["derive", str(path), "--out", str(out), "--regressor"]) == 0
    command = [CC, *STRICT, *CONVERSION, *SHARED, "-o", "libarm.so", "c/friction_arm.c", "-lm"]
    run_parallel({"so": command}, cwd=out)["so"].check()
    robot = symkin.robot_from_toml(FRICTION_ARM, "friction_arm.toml")
    return SimpleNamespace(
        robot=robot,
        numpy=import_path("barycentric_arm_numpy", out / "numpy" / "friction_arm_kinematics.py"),
        casadi=import_path("barycentric_arm_casadi", out / "casadi" / "friction_arm_casadi.py"),
        extension=load_extension(next((out / "python").glob("friction_arm_ext*.so"))),
        lib=ctypes.CDLL(str(out / "libarm.so")),
        delta=file_delta(robot),
    )


def states(seed: int, count: int, dof: int) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    return [rng.uniform(-2.0, 2.0, (count, dof)) for _ in range(3)]


def close(actual, expected, what: str, tolerance: float = TOLERANCE) -> None:
    actual, expected = np.asarray(actual, dtype=float), np.asarray(expected, dtype=float)
    assert actual.shape == expected.shape, f"{what}: {actual.shape} != {expected.shape}"
    scale = max(1.0, float(np.max(np.abs(expected))))
    error = float(np.max(np.abs(actual - expected)))
    assert error <= tolerance * scale, f"{what}: error {error:.3g} (scale {scale:.3g})"


def test_file_parameters_give_the_file_form_dynamics(arm):
    q, dq, ddq = states(1, 8, 3)
    numpy = arm.numpy
    close(numpy.mass_matrix_barycentric(q, delta=arm.delta), numpy.mass_matrix(q), "M")
    close(
        numpy.inverse_dynamics_barycentric(q, dq, ddq, delta=arm.delta),
        numpy.inverse_dynamics(q, dq, ddq),
        "tau",
    )


def test_tau_is_regressor_times_delta_and_m_its_ddq_derivative(arm):
    """Any ``delta`` (physical or not): ``tau = Y delta`` with the generated regressor, and
    each column of ``M`` the central difference of ``tau`` along that acceleration."""
    delta = np.random.default_rng(2).uniform(-1.0, 1.0, arm.delta.size)
    h = 1e-3  # tau is linear in ddq: the difference is exact up to rounding
    for q, dq, ddq in zip(*states(3, 4, 3), strict=True):
        tau = arm.numpy.inverse_dynamics_barycentric(q, dq, ddq, delta=delta)
        close(tau, arm.numpy.regressor(q, dq, ddq) @ delta, "tau vs Y delta")
        columns = [
            (
                arm.numpy.inverse_dynamics_barycentric(q, dq, ddq + h * e, delta=delta)
                - arm.numpy.inverse_dynamics_barycentric(q, dq, ddq - h * e, delta=delta)
            )
            / (2 * h)
            for e in np.eye(3)
        ]
        close(
            arm.numpy.mass_matrix_barycentric(q, delta=delta), np.column_stack(columns), "M", 1e-9
        )


def call_c(lib, name: str, arrays: list[np.ndarray], size: int) -> np.ndarray:
    """``friction_arm_<name>(inputs..., out)`` on one state (the arm has no parameters
    ``p``), with guard entries after the output."""
    arrays = [np.ascontiguousarray(a, dtype=float) for a in arrays]
    out = np.full(size + 4, np.nan)
    function = getattr(lib, f"friction_arm_{name}")
    function.restype = None
    function.argtypes = [ctypes.c_void_p] * (len(arrays) + 1)
    function(*[a.ctypes.data_as(ctypes.c_void_p) for a in arrays], out.ctypes.data)
    assert np.all(np.isnan(out[size:])), f"{name} wrote past its output"
    return out[:size]


@pytest.mark.needs_cc
def test_c_casadi_and_extension_agree_with_numpy(arm):
    delta = np.random.default_rng(4).uniform(-1.0, 1.0, arm.delta.size)
    q, dq, ddq = states(5, 6, 3)
    mass = arm.numpy.mass_matrix_barycentric(q, delta=delta)
    tau = arm.numpy.inverse_dynamics_barycentric(q, dq, ddq, delta=delta)
    mass_function = arm.casadi.mass_matrix_barycentric_function()
    tau_function = arm.casadi.inverse_dynamics_barycentric_function()
    for k in range(len(q)):
        c_mass = call_c(arm.lib, "mass_matrix_barycentric", [q[k], delta], 9)
        close(c_mass.reshape(3, 3), mass[k], "C M")
        c_tau = call_c(arm.lib, "inverse_dynamics_barycentric", [q[k], dq[k], ddq[k], delta], 3)
        close(c_tau, tau[k], "C tau")
        close(np.array(mass_function(q[k], [], delta).full()), mass[k], "CasADi M")
        close(
            np.array(tau_function(q[k], dq[k], ddq[k], [], delta).full()).ravel(),
            tau[k],
            "CasADi tau",
        )
    close(arm.extension.mass_matrix_barycentric(q, delta=delta), mass, "extension M (batch)")
    close(arm.extension.inverse_dynamics_barycentric(q, dq, ddq, None, delta), tau, "extension tau")
    close(
        arm.extension.inverse_dynamics_barycentric(q[0], dq[0], ddq[0], delta=delta),
        tau[0],
        "extension",
    )


@pytest.mark.needs_cc
def test_missing_or_wrong_delta_is_one_clear_error(arm):
    q, dq, ddq = (s[0] for s in states(6, 1, 3))
    size = arm.delta.size
    with pytest.raises(ValueError, match=rf"^delta: give the {size} barycentric parameters$"):
        arm.numpy.inverse_dynamics_barycentric(q, dq, ddq)
    with pytest.raises(ValueError, match=rf"give the {size} barycentric parameters delta$"):
        arm.extension.mass_matrix_barycentric(q)
    with pytest.raises(ValueError, match=rf"delta must hold {size} numbers \(got {size - 1}\)"):
        arm.extension.mass_matrix_barycentric(q, delta=arm.delta[:-1])
    with pytest.raises(TypeError, match=r"mass_matrix_barycentric\(q, p=None, delta=None\)"):
        arm.extension.mass_matrix_barycentric(q, pi=arm.delta)


def test_puma_mass_matrix_at_or_below_sympybotics_operation_count():
    """Symbolic inertia, numeric geometry (the setting of SymPyBotics' count): the
    barycentric M takes no more operations than SymPyBotics' and fewer than the file form's."""
    sys.path.insert(0, str(ROOT / "bench"))
    from dynamics_speed import robot_variant

    robot = robot_variant("puma560", "symbolic", "numeric")
    model = symkin.derive(robot)
    counts = {k.name: k.operation_counts["total"] for k in barycentric_kernels(model)}
    file_form = {k.name: k.operation_counts["total"] for k in dynamics_kernels(model, False)}
    assert counts["mass_matrix_barycentric"] <= SYMPYBOTICS_PUMA_M
    assert counts["mass_matrix_barycentric"] < file_form["mass_matrix"]
    assert counts["inverse_dynamics_barycentric"] < file_form["inverse_dynamics"]


def _toolbox(name: str):
    import roboticstoolbox as rtb

    if name == "puma560":  # Corke's data; the file has no friction, so neither may the toolbox
        return rtb.models.DH.Puma560().nofriction(coulomb=True, viscous=True)
    return rtb.models.DH.Panda()


@pytest.mark.oracle
@pytest.mark.slow
@pytest.mark.parametrize("name", ["puma560", "panda"])
def test_robotics_toolbox_inertia_and_rne(name, tmp_path):
    """The catalogue files carry the toolbox's data (Corke's PUMA 560 with its rotor
    inertias ``G^2 Jm``; Gaz et al.'s Panda): ``M`` and ``tau`` of the converted parameters
    are the toolbox's ``inertia(q)`` and ``rne(q, dq, ddq)``."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", symkin.errors.RobotWarning)
        robot = symkin.load_robot(name)
    write_tree(tmp_path, emit_numpy(robot, barycentric_kernels(symkin.derive(robot))))
    generated = import_path(f"barycentric_{name}", tmp_path / "numpy" / f"{name}_kinematics.py")
    toolbox, delta = _toolbox(name), file_delta(robot)
    q, dq, ddq = states(8, 6, robot.dof)
    tau = generated.inverse_dynamics_barycentric(q, dq, ddq, delta=delta)
    mass = generated.mass_matrix_barycentric(q, delta=delta)
    for k in range(len(q)):
        close(tau[k], toolbox.rne(q[k], dq[k], ddq[k]), f"{name} tau vs rne", 1e-9)
        close(mass[k], toolbox.inertia(q[k]), f"{name} M vs inertia", 1e-9)


SMOOTH_ELASTIC_ARM = """
name = "smooth_elastic_arm"
[[joints]]
type = "revolute"
alpha = 90
a = 0.2
[joints.link]
mass = 2.0
com = [-0.1, 0.0, 0.03]
inertia = {ixx = 0.02, iyy = 0.03, izz = 0.025}
stiffness = 300
motor_inertia = 0.4
friction = {viscous = 0.7, coulomb = 1.2, smoothing = 0.05}
[[joints]]
type = "revolute"
a = 0.3
[joints.link]
mass = 1.5
com = [-0.15, 0.01, 0.0]
inertia = {ixx = 0.01, iyy = 0.012, izz = 0.008}
motor_inertia = 0.05
friction = {coulomb_positive = 2.0, coulomb_negative = 1.5, smoothing = 0.1}
"""


def test_smoothed_coulomb_and_elastic_rotor_follow_the_file_form(tmp_path):
    """``friction.smoothing`` puts ``tanh(dq / w)`` in the Coulomb columns, and an elastic
    joint's rotor (motor side, not in the link torques) has no column: the barycentric tau of
    the file's data is the generated file-form tau, also near ``dq = 0``."""
    robot = symkin.robot_from_toml(SMOOTH_ELASTIC_ARM, "smooth_elastic_arm.toml")
    model = symkin.derive(robot)
    names = [s.name for s in parameter_symbols(robot)]
    assert "ia1" not in names and {"ia2", "fc1", "fcp2", "fcn2"} <= set(names)
    generated = generated_numpy_module(model)
    module = generated_numpy_module(model, "identification")
    q, dq, ddq = states(9, 6, 2)
    dq[:3] *= 0.02  # inside the smoothing width, where tanh and sign differ
    delta = file_delta(robot)
    tau = generated.inverse_dynamics(q, dq, ddq)
    close(module.regressor(q, dq, ddq) @ delta, tau, "Y delta")
    write_tree(tmp_path, emit_numpy(robot, barycentric_kernels(model)))
    barycentric = import_path("smooth_elastic", tmp_path / "numpy" / f"{robot.name}_kinematics.py")
    close(barycentric.inverse_dynamics_barycentric(q, dq, ddq, delta=delta), tau, "tau")
    close(barycentric.mass_matrix_barycentric(q, delta=delta), generated.mass_matrix(q), "M")


def test_symbolic_inertia_robot_takes_pi_and_delta_side_by_side(tmp_path):
    """A robot file without inertial data: the file-form kernels take ``pi`` (m, c, I about
    the COM), the barycentric ones ``delta``; the same bodies in both forms give the same
    ``M`` and ``tau``."""
    robot = symkin.robot_from_toml(SYMBOLIC_ARM, "symbolic_arm.toml")
    model = symkin.derive(robot)
    write_tree(tmp_path, emit_numpy(robot, dynamics_kernels(model) + barycentric_kernels(model)))
    generated = import_path("symbolic_arm", tmp_path / "numpy" / "symbolic_arm_kinematics.py")
    rng = np.random.default_rng(10)
    pi, values = [], {}
    for i in (1, 2):
        m, c = rng.uniform(0.5, 2.0), rng.uniform(-0.2, 0.2, 3)
        principal = rng.uniform(0.01, 0.05, 3)
        inertia = np.diag(principal) + 0.002 * (1 - np.eye(3))  # ixy = ixz = iyz = 0.002
        pi += [m, *c, *principal, 0.002, 0.002, 0.002]  # m cx cy cz ixx iyy izz ixy ixz iyz
        values |= link_values(i, m, c, inertia)
    delta = np.array([values[s.name] for s in parameter_symbols(robot)])
    q, dq, ddq = states(11, 5, 2)
    close(generated.mass_matrix_barycentric(q, delta=delta), generated.mass_matrix(q, pi=pi), "M")
    close(
        generated.inverse_dynamics_barycentric(q, dq, ddq, delta=delta),
        generated.inverse_dynamics(q, dq, ddq, pi=pi),
        "tau",
    )


SYMBOLIC_ARM = """
name = "symbolic_arm"
[[joints]]
type = "revolute"
a = 0.5
alpha = 30
[[joints]]
type = "prismatic"
alpha = 90
theta = 20
"""


def test_identified_base_parameters_give_the_textbook_mass_matrix(tmp_path):
    """The natural use: fit ``beta`` to torques of the textbook planar elbow arm (Spong,
    Hutchinson, Vidyasagar, Sec. 7.4.1), put it into ``delta`` at the base regressor's columns
    (zero elsewhere: the folded parameters change no torque), and ``M`` of ``delta`` is the
    textbook ``D(q)``."""
    robot = symkin.load_robot("planar_2r")
    model = symkin.derive(robot)
    q, dq, ddq = states(12, 40, 2)
    fit = identify(model, q, dq, ddq, planar_torques(q, dq, ddq))
    delta = np.zeros(len(parameter_symbols(robot)))
    delta[list(base_regressor(robot, model.kinematics).folding.kept)] = fit.estimate
    write_tree(tmp_path, emit_numpy(robot, barycentric_kernels(model)))
    generated = import_path("identified_2r", tmp_path / "numpy" / "planar_2r_kinematics.py")
    q, dq, ddq = states(13, 5, 2)
    c2 = np.cos(q[:, 1])
    d11 = M1 * LC1**2 + M2 * (L1**2 + LC2**2 + 2 * L1 * LC2 * c2) + I1 + I2
    d12 = M2 * (LC2**2 + L1 * LC2 * c2) + I2
    d22 = np.full_like(c2, M2 * LC2**2 + I2)
    textbook = np.stack([np.stack([d11, d12], -1), np.stack([d12, d22], -1)], -2)
    close(generated.mass_matrix_barycentric(q, delta=delta), textbook, "M", 1e-9)
    tau = generated.inverse_dynamics_barycentric(q, dq, ddq, delta=delta)
    close(tau, planar_torques(q, dq, ddq), "tau", 1e-9)


@pytest.mark.parametrize("name", ["placed_arm", "dh_tilted_arm", "puma560_elastic"])
def test_other_conventions_give_the_file_form_dynamics(name, tmp_path):
    """URDF-like placed joints (tilted origins, axes along y and -z, a slanted prismatic) and
    DH edge cases (generic twists, offsets, a flipped joint; elastic joints, whose rotors
    are not in M): the composite-rigid-body ``M`` and the recursion's ``tau`` of the file's
    converted data are the generated file-form ``mass_matrix`` and ``inverse_dynamics``."""
    robot = symkin.load_robot(ROOT / "tests" / "data" / f"{name}.toml")
    model = symkin.derive(robot)
    write_tree(tmp_path, emit_numpy(robot, barycentric_kernels(model)))
    path = tmp_path / "numpy" / f"{robot.name}_kinematics.py"
    barycentric = import_path(f"barycentric_{name}", path)
    generated = generated_numpy_module(model)
    delta = file_delta(robot)
    q, dq, ddq = states(14, 6, robot.dof)
    close(barycentric.mass_matrix_barycentric(q, delta=delta), generated.mass_matrix(q), "M")
    close(
        barycentric.inverse_dynamics_barycentric(q, dq, ddq, delta=delta),
        generated.inverse_dynamics(q, dq, ddq),
        "tau",
    )
