"""Equations of motion: Lagrange vs Newton–Euler, structure, friction, hand derivations, energy.

Expected values never come from the method under test alone: the other method, a hand
derivation with DH matrices written out here, finite differences, or a simulation's energy.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

import symkin
from codegen_helpers import import_path, write_tree
from numeric_dh import without_inertials
from symkin.derive import Model
from symkin.derive.dynamics import Dynamics, link_inertial_data
from symkin.derive.newton_euler import newton_euler_dynamics
from symkin.errors import RobotWarning
from symkin.generate import files_for_robot
from symkin.io import robot_from_toml
from symkin.kernels import inertial_symbols

SMALL = ("planar_2r", "rpr", "scara", "planar_3r")
LARGE = ("puma560", "stanford", "ur5", "panda")

# A spatial RRR in modified DH (Craig), with a prismatic-free but non-planar geometry and
# symbolic inertial data (no [joints.link]).
MODIFIED_RRR = """
name = "mdh_rrr"
convention = "modified"
[parameters]
a1 = 0.3
d2 = 0.1
a2 = 0.5
[[joints]]
type = "revolute"
[[joints]]
type = "revolute"
alpha = 90
d = "d2"
a = "a1"
[[joints]]
type = "revolute"
alpha = -90
a = "a2"
"""

# A modified-DH arm with a prismatic joint (RP R), again with symbolic inertial data.
MODIFIED_RPR = """
name = "mdh_rpr"
convention = "modified"
gravity = [0, -9.81, 0]
[parameters]
L = 0.4
[[joints]]
type = "revolute"
[[joints]]
type = "prismatic"
alpha = -90
a = "L"
[[joints]]
type = "revolute"
alpha = 90
"""


def load(name: str) -> symkin.Robot:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RobotWarning)  # Corke's PUMA data (documented)
        return symkin.load_robot(name)


def robot_of(name: str) -> symkin.Robot:
    texts = {"mdh_rrr": MODIFIED_RRR, "mdh_rpr": MODIFIED_RPR}
    return robot_from_toml(texts[name], f"{name}.toml") if name in texts else load(name)


def symbolic_robot_of(name: str) -> symkin.Robot:
    """``robot_of`` with symbolic inertial parameters (m1, cx1, ...) in place of the file's
    numbers, so that two derivations can be compared as identities, free of float round-off."""
    if name in ("mdh_rrr", "mdh_rpr"):
        return robot_of(name)
    return robot_from_toml(without_inertials(name), f"{name}.toml")


# ------------------------------------------------------------------------- numeric helpers


def random_inertials(model: Model, seed: int) -> dict[sp.Symbol, float]:
    """Positive masses, COMs within 0.2 m and physical (PSD, triangle) tensors for every
    inertial symbol the file leaves out."""
    rng = np.random.default_rng(seed)
    values: dict[sp.Symbol, float] = {}
    for i, joint in enumerate(model.robot.joints):
        if joint.link is not None:
            continue
        link = link_inertial_data(model.robot, i)
        second = rng.uniform(0.01, 0.2, 3)  # ∫x² dm, ∫y² dm, ∫z² dm in principal axes
        principal = np.array([second[1] + second[2], second[0] + second[2], second[0] + second[1]])
        rotation, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        tensor = rotation @ np.diag(principal) @ rotation.T
        numbers = [tensor[0, 0], tensor[1, 1], tensor[2, 2], tensor[0, 1], tensor[0, 2]]
        numbers.append(tensor[1, 2])
        values[link.mass] = float(rng.uniform(0.5, 5.0))
        values.update(zip(link.com, rng.uniform(-0.2, 0.2, 3).tolist(), strict=True))
        values.update(zip(link.inertia, map(float, numbers), strict=True))
    return values


def substitutions(model: Model, seed: int = 0) -> dict[sp.Symbol, float]:
    values = {s: model.robot.parameter_values()[s.name] for s in model.robot.parameter_symbols}
    return values | random_inertials(model, seed)


def numeric(model: Model, dynamics: Dynamics, exprs: Sequence[sp.MatrixBase], values):
    """``f(q, dq, ddq) -> [arrays]`` evaluating the named intermediates in order (no expansion)."""
    assignments = [(s, sp.sympify(e).xreplace(values)) for s, e in dynamics.assignments]
    outputs = [sp.Matrix(m).xreplace(values) for m in exprs]
    function = sp.lambdify(
        [model.q, model.dq, model.ddq],
        outputs,
        modules="numpy",
        cse=lambda e: (assignments, e),
    )
    return lambda q, dq, ddq: [np.array(a, dtype=float) for a in function(q, dq, ddq)]


def states(robot: symkin.Robot, count: int, seed: int):
    rng = np.random.default_rng(seed)
    spans = np.array([np.pi if j.type == "revolute" else 0.5 for j in robot.joints])
    shape = (count, robot.dof)
    return (
        rng.uniform(-1, 1, shape) * spans,
        rng.uniform(-1.5, 1.5, shape),
        rng.uniform(-3, 3, shape),
    )


def close(actual, expected, tolerance: float, what: str) -> None:
    actual, expected = np.asarray(actual, float), np.asarray(expected, float)
    scale = max(1.0, float(np.max(np.abs(expected))))
    error = float(np.max(np.abs(actual - expected)))
    assert error <= tolerance * scale, f"{what}: error {error:.3g} > {tolerance * scale:.3g}"


# ------------------------------------------------------------------------- symbolic identity


def canonical(expr: sp.Expr, q: Sequence[sp.Symbol]) -> sp.Expr:
    """A canonical polynomial form: trig expanded, sin/cos of each q replaced by s, c, and
    reduced modulo ``c² + s² − 1`` (so it is 0 exactly when ``expr`` is identically 0)."""
    expr = sp.expand(sp.expand_trig(sp.expand(expr)))
    sines = [sp.Dummy(f"s{i}") for i in range(len(q))]
    cosines = [sp.Dummy(f"c{i}") for i in range(len(q))]
    mapping = {sp.sin(v): s for v, s in zip(q, sines, strict=True)}
    mapping |= {sp.cos(v): c for v, c in zip(q, cosines, strict=True)}
    expr = expr.xreplace(mapping)
    assert not expr.atoms(sp.sin, sp.cos), f"trig left after expansion: {expr}"
    for s, c in zip(sines, cosines, strict=True):
        expr = sp.rem(sp.expand(expr), c**2 + s**2 - 1, c)
    return sp.expand(expr)


def test_canonical_form_detects_differences():
    q1, q2 = sp.symbols("q1 q2", real=True)
    assert canonical(sp.sin(q1 + q2) ** 2 + sp.cos(q1 + q2) ** 2 - 1, [q1, q2]) == 0
    assert canonical(sp.cos(2 * q1) - 1 + 2 * sp.sin(q1) ** 2, [q1]) == 0
    assert canonical(sp.sin(q1 + q2) - sp.sin(q1) * sp.cos(q2), [q1, q2]) != 0
    assert canonical(sp.Symbol("m1") * sp.cos(q1) ** 2, [q1]) != 0


@pytest.mark.slow
@pytest.mark.parametrize("name", [*SMALL, "mdh_rrr", "mdh_rpr"])
def test_lagrange_equals_newton_euler_symbolically(name):
    model = symkin.derive(symbolic_robot_of(name))
    lagrange, ne = model.lagrange, model.newton_euler
    assert lagrange.coriolis_matrix is not None and ne.coriolis_matrix is not None
    for what in ("mass_matrix", "gravity_vector", "coriolis_vector", "coriolis_matrix"):
        difference = getattr(lagrange, what) - ne.expanded(getattr(ne, what))
        for index, entry in enumerate(difference):
            assert canonical(entry, model.q) == 0, f"{name}: {what}[{index}] differs"
    # c = C dq in both.
    for dynamics in (lagrange, ne):
        check = dynamics.coriolis_matrix * sp.Matrix(model.dq) - dynamics.coriolis_vector
        assert all(canonical(e, model.q) == 0 for e in ne.expanded(check))


# ------------------------------------------------------------------------- hand derivations


def dh_standard(theta, d, a, alpha) -> sp.Matrix:
    """Spong's A_i, written out here (not symkin's)."""
    ct, st, ca, sa = sp.cos(theta), sp.sin(theta), sp.cos(alpha), sp.sin(alpha)
    return sp.Matrix(
        [
            [ct, -st * ca, st * sa, a * ct],
            [st, ct * ca, -ct * sa, a * st],
            [0, sa, ca, d],
            [0, 0, 0, 1],
        ]
    )


def hand_gravity(model: Model, rows, gravity) -> sp.Matrix:
    """G = dP/dq with P = -sum m_i g^T p_ci, from DH matrices written out by hand."""
    transform = sp.eye(4)
    potential = sp.Integer(0)
    for i, row in enumerate(rows):
        transform = transform * dh_standard(*row)
        link = link_inertial_data(model.robot, i)
        com = transform * sp.Matrix([*link.com, 1])
        potential -= link.mass * (sp.Matrix(gravity).T * com[:3, 0])[0, 0]
    return sp.Matrix([sp.diff(potential, v) for v in model.q])


PLANAR_2R_VERTICAL = """
name = "planar_2r_vertical"
gravity = [0, -9.81, 0]
[parameters]
L1 = 1.0
L2 = 0.7
[[joints]]
type = "revolute"
a = "L1"
[[joints]]
type = "revolute"
a = "L2"
"""


def test_gravity_of_a_vertical_planar_2r_by_hand():
    model = symkin.derive(robot_from_toml(PLANAR_2R_VERTICAL, "v.toml"))
    q1, q2 = model.q
    L1, L2 = sp.symbols("L1 L2", real=True)
    g = sp.Float(9.81)
    m1, m2, cx1, cy1, cx2, cy2 = sp.symbols("m1 m2 cx1 cy1 cx2 cy2", real=True)
    # Heights of the COMs (frame i's x axis along link i): y = ...
    y1 = L1 * sp.sin(q1) + cx1 * sp.sin(q1) + cy1 * sp.cos(q1)
    y2 = L1 * sp.sin(q1) + (L2 + cx2) * sp.sin(q1 + q2) + cy2 * sp.cos(q1 + q2)
    potential = g * (m1 * y1 + m2 * y2)
    expected = sp.Matrix([sp.diff(potential, v) for v in (q1, q2)])
    actual = model.newton_euler.expanded(model.newton_euler.gravity_vector)
    names = {s.name: s for s in actual.free_symbols}
    expected = expected.xreplace({s: names.get(s.name, s) for s in expected.free_symbols})
    for a, e in zip(actual, expected, strict=True):
        assert canonical(a - e, model.q) == 0
    # And from DH matrices written out here.
    rows = [(q1, 0, L1, 0), (q2, 0, L2, 0)]
    by_dh = hand_gravity(model, rows, model.robot.gravity)
    by_dh = by_dh.xreplace({s: names.get(s.name, s) for s in by_dh.free_symbols})
    for a, e in zip(actual, by_dh, strict=True):
        assert canonical(a - e, model.q) == 0


EXACT_2R = """
name = "exact_2r"
[parameters]
L1 = 1
L2 = 1
[[joints]]
type = "revolute"
a = "L1"
[joints.link]
mass = 1
com = ["-L1/2", 0, 0]
[[joints]]
type = "revolute"
a = "L2"
[joints.link]
mass = 1
com = ["-L2/2", 0, 0]
"""


def _planar_2r_coriolis(h: sp.Expr, dq1: sp.Symbol, dq2: sp.Symbol) -> sp.Matrix:
    """Spong et al. (7.87) for the planar elbow arm: C = [[h dq2, h (dq1 + dq2)], [-h dq1, 0]]
    with h = -m2 l1 lc2 sin(q2) (lc2: joint 2 to the centre of mass of link 2)."""
    return sp.Matrix([[h * dq2, h * (dq1 + dq2)], [-h * dq1, 0]])


def test_readable_lagrange_of_decimal_data_has_no_rounding_remainders():
    """The catalogue 2R's rods (3.393 kg, centre 0.5 m behind frame i): C is Spong's, with no
    1e-16 terms in q1 left over from sin^2 + cos^2 = 1 in floating point."""
    model = symkin.derive(load("planar_2r"))
    q1, q2 = model.q
    L1, L2 = model.robot.parameter_symbols
    h = -3.393 * L1 * (L2 - 0.5) * sp.sin(q2)
    expected = _planar_2r_coriolis(h, *model.dq)
    for actual, wanted in zip(model.lagrange.coriolis_matrix, expected, strict=True):
        assert q1 not in actual.free_symbols
        assert all(abs(f) > 1e-6 for f in actual.atoms(sp.Float)), actual
        assert abs(sp.expand(actual - wanted).xreplace({L1: 0.7, L2: 0.4, q2: 0.3})) < 1e-12


def test_readable_lagrange_of_exact_data_keeps_fractions():
    """A robot given in exact numbers prints exact coefficients (``/2``), not ``0.5``."""
    model = symkin.derive(robot_from_toml(EXACT_2R, "exact_2r.toml"))
    L1, L2 = model.robot.parameter_symbols
    expected = _planar_2r_coriolis(-L1 * L2 / 2 * sp.sin(model.q[1]), *model.dq)
    assert not model.lagrange.coriolis_matrix.atoms(sp.Float)
    assert sp.expand(model.lagrange.coriolis_matrix - expected) == sp.zeros(2, 2)


def test_catalogue_planar_2r_moves_in_a_horizontal_plane():
    model = symkin.derive(load("planar_2r"))
    assert model.newton_euler.expanded(model.newton_euler.gravity_vector) == sp.zeros(2, 1)


def test_gravity_of_rpr_by_hand_dh():
    model = symkin.derive(load("rpr"))
    q1, q2, q3 = model.q
    L3 = sp.Symbol("L3", real=True)
    half = sp.pi / 2
    rows = [(q1, 0, 0, half), (half, q2, 0, half), (q3, 0, L3, 0)]
    expected = hand_gravity(model, rows, model.robot.gravity)
    actual = model.newton_euler.expanded(model.newton_euler.gravity_vector)
    names = {s.name: s for s in actual.free_symbols}
    expected = expected.xreplace({s: names.get(s.name, s) for s in expected.free_symbols})
    for a, e in zip(actual, expected, strict=True):
        assert canonical(a - e, model.q) == 0
    assert any(canonical(a, model.q) != 0 for a in actual)  # gravity does act on this arm


# ------------------------------------------------------------------------- large robots


def numeric_lagrange(model: Model, values):
    """An independent numeric Lagrange: M from link Jacobians built from symkin's frames
    (z axes and origins), G and c by central finite differences of the energies."""
    robot = model.robot
    frames = sp.lambdify([model.q], [m.xreplace(values) for m in model.frame_transforms[1:]])
    base = np.array(model.frame_transforms[0].xreplace(values), dtype=float)
    links = [link_inertial_data(robot, i) for i in range(robot.dof)]
    data = [
        (
            float(sp.sympify(link.mass).xreplace(values)),
            np.array(sp.Matrix(link.com).xreplace(values), dtype=float).ravel(),
            np.array(link.inertia_matrix.xreplace(values), dtype=float),
            float(sp.sympify(link.motor_inertia).xreplace(values)),
        )
        for link in links
    ]
    gravity = np.array([float(g) for g in robot.gravity])
    revolute = [j.type == "revolute" for j in robot.joints]

    def geometry(q):
        transforms = [base] + [np.array(t, dtype=float) for t in frames(q)]
        # joint i acts about z of frame i-1 (standard) or of frame i (modified)
        axis_frames = transforms[:-1] if robot.convention == "standard" else transforms[1:]
        return transforms, axis_frames

    def mass_matrix(q):
        transforms, axis_frames = geometry(q)
        n = robot.dof
        result = np.zeros((n, n))
        for i, (mass, com, inertia, rotor) in enumerate(data):
            frame = transforms[i + 1]
            point = frame[:3, :3] @ com + frame[:3, 3]
            linear, angular = np.zeros((3, n)), np.zeros((3, n))
            for j in range(i + 1):
                z, o = axis_frames[j][:3, 2], axis_frames[j][:3, 3]
                if revolute[j]:
                    linear[:, j], angular[:, j] = np.cross(z, point - o), z
                else:
                    linear[:, j] = z
            world = frame[:3, :3] @ inertia @ frame[:3, :3].T
            result += mass * linear.T @ linear + angular.T @ world @ angular
            result[i, i] += rotor
        return result

    def potential(q):
        transforms, _ = geometry(q)
        return -sum(
            m * gravity @ (t[:3, :3] @ c + t[:3, 3])
            for (m, c, _, _), t in zip(data, transforms[1:], strict=True)
        )

    def gravity_vector(q, h=1e-6):
        eye = np.eye(len(q))
        return np.array([(potential(q + h * e) - potential(q - h * e)) / (2 * h) for e in eye])

    def coriolis(q, dq, h=1e-6):
        # c = dM/dt dq - 1/2 d/dq (dq^T M dq)
        dm_dt = (mass_matrix(q + h * dq) - mass_matrix(q - h * dq)) / (2 * h)
        grad = np.array(
            [
                dq @ (mass_matrix(q + h * e) - mass_matrix(q - h * e)) @ dq / (4 * h)
                for e in np.eye(len(q))
            ]
        )
        return dm_dt @ dq - grad

    return mass_matrix, gravity_vector, coriolis


@pytest.fixture(scope="module", params=LARGE)
def large(request):
    model = symkin.derive(load(request.param))
    values = substitutions(model, seed=LARGE.index(request.param))
    ne = newton_euler_dynamics(model.robot, model.kinematics, model.dq, model.ddq, False)
    evaluate = numeric(model, ne, [ne.mass_matrix, ne.gravity_vector, ne.coriolis_vector], values)
    return model, values, evaluate


def test_newton_euler_matches_independent_numeric_lagrange(large):
    model, values, evaluate = large
    mass_matrix, gravity_vector, coriolis = numeric_lagrange(model, values)
    q, dq, _ = states(model.robot, 4, seed=7)
    zero = np.zeros(model.robot.dof)
    for state, rate in zip(q, dq, strict=True):
        m, g, c = evaluate(state, rate, zero)
        close(m, mass_matrix(state), 1e-12, "M")
        close(g.ravel(), gravity_vector(state), 1e-7, "G")
        close(c.ravel(), coriolis(state, rate), 1e-6, "c")


@pytest.mark.slow
@pytest.mark.parametrize("name", ["puma560", "panda"])
def test_lagrange_equals_newton_euler_numerically(name):
    """symkin's own Lagrange (energies, Christoffel symbols) against its Newton–Euler."""
    model = symkin.derive(load(name))
    values = substitutions(model, seed=5)
    matrices = ("mass_matrix", "gravity_vector", "coriolis_vector", "coriolis_matrix")
    lagrange, ne = model.lagrange, model.newton_euler
    assert lagrange.assignments, "large robots keep Lagrange's shared subexpressions named"
    by_lagrange = numeric(model, lagrange, [getattr(lagrange, m) for m in matrices], values)
    by_ne = numeric(model, ne, [getattr(ne, m) for m in matrices], values)
    q, dq, _ = states(model.robot, 3, seed=13)
    zero = np.zeros(model.robot.dof)
    for state, rate in zip(q, dq, strict=True):
        for what, got, want in zip(
            matrices, by_lagrange(state, rate, zero), by_ne(state, rate, zero), strict=True
        ):
            close(got, want, 1e-9, what)


def test_mass_matrix_is_symmetric_positive_definite(large):
    model, _, evaluate = large
    q, _, _ = states(model.robot, 10, seed=8)
    zero = np.zeros(model.robot.dof)
    for state in q:
        m = evaluate(state, zero, zero)[0]
        np.testing.assert_array_equal(m, m.T)
        assert np.linalg.eigvalsh(m)[0] > 0


# ------------------------------------------------------------------------- dM/dt - 2C


@pytest.mark.parametrize("name", ["planar_3r", "rpr", "scara", "mdh_rrr", "puma560"])
def test_mass_matrix_derivative_minus_twice_coriolis_is_skew(name):
    model = symkin.derive(robot_of(name))
    ne = model.newton_euler
    values = substitutions(model, seed=3)
    evaluate = numeric(model, ne, [ne.mass_matrix, ne.coriolis_matrix], values)
    q, dq, _ = states(model.robot, 5, seed=11)
    zero = np.zeros(model.robot.dof)
    h = 1e-6
    for state, rate in zip(q, dq, strict=True):
        m_plus = evaluate(state + h * rate, zero, zero)[0]
        m_minus = evaluate(state - h * rate, zero, zero)[0]
        dm_dt = (m_plus - m_minus) / (2 * h)
        c = evaluate(state, rate, zero)[1]
        n = dm_dt - 2 * c
        close(n + n.T, np.zeros_like(n), 1e-7, "N + N^T")
        # ... and C is not itself skew, so the test would notice a missing factor of 2.
        assert np.max(np.abs(dm_dt - c + (dm_dt - c).T)) > 1e-6 or not np.any(rate)


# ------------------------------------------------------------------------- modified == standard


# Standard-DH spatial RRR (theta offset, d, a, alpha in rad) and link data in standard frame i.
SPATIAL = [(0.2, 0.3, 0.1, np.pi / 2), (-0.4, 0.05, 0.6, 0.0), (0.0, 0.1, 0.4, -np.pi / 2)]


def rx(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def link_toml(mass: float, com, tensor: np.ndarray) -> str:
    keys = {"ixx": (0, 0), "iyy": (1, 1), "izz": (2, 2), "ixy": (0, 1), "ixz": (0, 2)}
    keys["iyz"] = (1, 2)
    inertia = ", ".join(f"{k} = {float(tensor[i, j])!r}" for k, (i, j) in keys.items())
    com_text = ", ".join(repr(float(c)) for c in com)
    return f"[joints.link]\nmass = {float(mass)!r}\ncom = [{com_text}]\ninertia = {{ {inertia} }}\n"


def standard_and_modified(seed: int) -> tuple[str, str]:
    rng = np.random.default_rng(seed)
    standard = 'name = "std_rrr"\nangles = "rad"\nconvention = "standard"\n'
    modified = 'name = "mdh_rrr2"\nangles = "rad"\nconvention = "modified"\n'
    previous = (0.0, 0.0)  # (a, alpha) of the previous standard row
    for theta, d, a, alpha in SPATIAL:
        mass = float(rng.uniform(0.5, 3))
        com = rng.uniform(-0.2, 0.2, 3)
        second = rng.uniform(0.01, 0.1, 3)
        rotation, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        principal = [second[1] + second[2], second[0] + second[2], second[0] + second[1]]
        tensor = rotation @ np.diag(principal) @ rotation.T
        standard += f'[[joints]]\ntype = "revolute"\ntheta = {theta!r}\nd = {d!r}\n'
        standard += f"a = {a!r}\nalpha = {alpha!r}\n" + link_toml(mass, com, tensor)
        # Standard frame i = modified frame i * Tx(a_i) Rx(alpha_i).
        com_m = np.array([a, 0, 0]) + rx(alpha) @ com
        tensor_m = rx(alpha) @ tensor @ rx(alpha).T
        modified += f'[[joints]]\ntype = "revolute"\ntheta = {theta!r}\nd = {d!r}\n'
        modified += f"a = {float(previous[0])!r}\nalpha = {float(previous[1])!r}\n"
        modified += link_toml(mass, com_m, tensor_m)
        previous = (a, alpha)
    return standard, modified


def test_modified_dh_robot_equals_the_same_robot_in_standard_dh():
    standard_text, modified_text = standard_and_modified(seed=5)
    models = [
        symkin.derive(robot_from_toml(standard_text, "std.toml")),
        symkin.derive(robot_from_toml(modified_text, "mdh.toml")),
    ]
    torques = []
    for model in models:
        assignments, tau = model.inverse_dynamics_recursion
        dynamics = Dynamics("ne", model.q, model.dq, model.ddq, *[sp.ImmutableMatrix([0])] * 4,
                            assignments=assignments)  # fmt: skip
        torques.append(numeric(model, dynamics, [tau], {}))
    q, dq, ddq = states(models[0].robot, 8, seed=12)
    for state in zip(q, dq, ddq, strict=True):
        a, b = torques[0](*state)[0], torques[1](*state)[0]
        close(a, b, 1e-12, "tau standard vs modified")
        assert np.max(np.abs(a)) > 0.1


# ------------------------------------------------------------------------- friction, rotor


FRICTION_ROBOT = """
name = "friction_rr"
gravity = [0, -9.81, 0]
[[joints]]
type = "revolute"
a = 0.5
[joints.link]
mass = 1.5
com = [-0.2, 0.01, 0]
inertia = { ixx = 0.01, iyy = 0.02, izz = 0.025 }
{extra1}
[[joints]]
type = "prismatic"
alpha = 90
[joints.link]
mass = 0.8
com = [0, 0, -0.1]
inertia = { ixx = 0.004, iyy = 0.004, izz = 0.001 }
{extra2}
"""


def torque_function(text: str):
    model = symkin.derive(robot_from_toml(text, "f.toml"))
    assignments, tau = model.inverse_dynamics_recursion
    dynamics = Dynamics("ne", model.q, model.dq, model.ddq, *[sp.ImmutableMatrix([0])] * 4,
                        assignments=assignments)  # fmt: skip
    return numeric(model, dynamics, [tau], {})


def test_friction_and_rotor_inertia_are_added_as_documented():
    plain = torque_function(FRICTION_ROBOT.replace("{extra1}", "").replace("{extra2}", ""))
    extra1 = "motor_inertia = 0.3\nfriction = { coulomb = 0.7, viscous = 0.25 }"
    extra2 = (
        "motor_inertia = 0.05\n"
        "friction = { coulomb = 2.0, viscous = 0.5, stribeck = { static = 3.0, velocity = 0.1 } }"
    )
    full = torque_function(FRICTION_ROBOT.replace("{extra1}", extra1).replace("{extra2}", extra2))
    q, dq, ddq = states(
        robot_from_toml(FRICTION_ROBOT.replace("{extra1}", "").replace("{extra2}", ""), "f"), 10, 13
    )
    dq[0] = [0.0, -0.0]  # sign(0) = 0: no Coulomb friction at rest
    for state in zip(q, dq, ddq, strict=True):
        _, v, a = state
        first = 0.7 * np.sign(v[0]) + 0.25 * v[0] + 0.3 * a[0]
        coulomb = 2.0 + (3.0 - 2.0) * np.exp(-abs(v[1] / 0.1))
        second = coulomb * np.sign(v[1]) + 0.5 * v[1] + 0.05 * a[1]
        close(full(*state)[0].ravel() - plain(*state)[0].ravel(), [first, second], 1e-12, "F")


def test_friction_appears_in_dynamics_friction_vector_not_in_c():
    text = FRICTION_ROBOT.replace("{extra1}", "friction = { viscous = 2.0 }").replace(
        "{extra2}", ""
    )
    model = symkin.derive(robot_from_toml(text, "f.toml"))
    ne = model.newton_euler
    dq1 = model.dq[0]
    assert sp.simplify(ne.friction[0] - 2 * dq1) == 0
    assert ne.friction[1] == 0


# ------------------------------------------------------------------------- energy


def energy_robot(name: str) -> symkin.Robot:
    """The catalogue robot without its inertial data (random ones are drawn below)."""
    if name != "planar_3r_vertical":
        return robot_from_toml(without_inertials(name), f"{name}.toml")
    # The catalogue planar 3R moves in a horizontal plane; tilt gravity into its plane.
    text = without_inertials("planar_3r")
    text = text.replace('name = "planar_3r"', f'name = "{name}"')
    text = text.replace("[parameters]", "gravity = [0, -9.81, 0]\n\n[parameters]", 1)
    robot = robot_from_toml(text, f"{name}.toml")
    assert robot.gravity[1] != 0
    return robot


@pytest.mark.parametrize("name", ["rpr", "planar_3r_vertical"])
def test_energy_is_conserved_without_torque_or_friction(tmp_path, name):
    robot = energy_robot(name)
    model = symkin.derive(robot)
    write_tree(tmp_path, files_for_robot(robot, ("numpy",)))
    module = import_path(f"energy_{name}", tmp_path / "numpy" / f"{name}_kinematics.py")
    values = random_inertials(model, seed=21)
    pi = np.array([values[s] for s in inertial_symbols(model)])
    robot = model.robot
    n = robot.dof

    def rhs(_, x):
        q, dq = x[:n], x[n:]
        m = module.mass_matrix(q, pi=pi)
        rest = module.coriolis(q, dq, pi=pi) + module.gravity(q, pi=pi)
        return np.concatenate([dq, np.linalg.solve(m, -rest)])

    # Potential from symkin's frames (not from G): P = -sum m_i g^T p_ci.
    params = {s: robot.parameter_values()[s.name] for s in robot.parameter_symbols}
    frames = sp.lambdify([model.q], [t.xreplace(params) for t in model.frame_transforms[1:]])
    links = [link_inertial_data(robot, i) for i in range(n)]
    masses = [float(sp.sympify(k.mass).xreplace(values)) for k in links]
    coms = [np.array(sp.Matrix(k.com).xreplace(values), dtype=float).ravel() for k in links]
    gravity = np.array([float(g) for g in robot.gravity])

    def energy(x):
        q, dq = x[:n], x[n:]
        kinetic = 0.5 * dq @ module.mass_matrix(q, pi=pi) @ dq
        potential = -sum(
            m * gravity @ (np.array(t, float)[:3, :3] @ c + np.array(t, float)[:3, 3])
            for m, c, t in zip(masses, coms, frames(q), strict=True)
        )
        return kinetic + potential, kinetic

    x0 = np.concatenate([states(robot, 1, seed=30)[0][0] * 0.5, np.full(n, 0.8)])
    solution = solve_ivp(rhs, (0.0, 2.0), x0, method="DOP853", rtol=1e-12, atol=1e-12)
    assert solution.success
    energies = np.array([energy(x) for x in solution.y.T])
    total, kinetic = energies[:, 0], energies[:, 1]
    scale = np.max(np.abs(kinetic))
    assert np.ptp(kinetic) > 1e-2 * scale  # energy really flows between kinetic and potential
    drift = np.max(np.abs(total - total[0])) / scale
    assert drift < 1e-8, f"relative energy drift {drift:.3g}"
