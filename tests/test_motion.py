"""Position, velocity and acceleration of points fixed in links, against finite differences.

The reference is ``tests/numeric_dh.py``: the point's base-frame position along a smooth joint
trajectory ``q(t) = q0 + dq0 t + ddq0 t^2 / 2``, differentiated numerically in time (central
differences), and the numerical Jacobian of the tool pose for ``v = J dq``.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from numeric_dh import function, model, overrides, random_q, reference, robot
from symkin.errors import SymkinError

# (robot, link, point in that link's frame).  Prismatic joints: scara 3, rpr 2, stanford 3,
# cylindrical 2-3, hand_modified 3; modified DH: hand_modified; base and tool: the hand robots.
CASES = (
    ("planar_2r", 1, (0.3, 0.1, 0.0)),
    ("planar_2r", 2, (0.2, -0.4, 0.5)),
    ("scara", 3, (0.05, 0.02, -0.1)),
    ("rpr", 2, (0.1, -0.2, 0.3)),
    ("rpr", 3, (-0.3, 0.2, 0.1)),
    ("stanford", 3, (0.02, 0.03, -0.05)),
    ("stanford", 4, (0.1, -0.1, 0.2)),
    ("cylindrical_rtt_wrist", 4, (0.1, 0.2, -0.3)),
    ("cylindrical_rtt_wrist", 6, (0.01, -0.02, 0.05)),
    ("puma560", 2, (-0.2, 0.05, 0.1)),
    ("hand_modified", 3, (0.1, -0.2, 0.3)),
    ("hand_standard", 3, (-0.1, 0.2, 0.15)),
)
VELOCITY_TOL = 1e-6  # central difference, h = 1e-6
ACCELERATION_TOL = 1e-6  # second central difference, h = 1e-4: error ~1e-8


def _motion_function(name: str, link: int, point: tuple[float, float, float], form: str):
    """``[p v a]`` as a function of ``(q, dq, ddq)``: the closed forms (U-matrix method) or
    the link-by-link recursion with its named intermediates (what code generation prints)."""
    m = model(name)
    motion = m.point_motion(link, point)
    if form == "closed":
        return function(
            name,
            sp.Matrix.hstack(motion.position, motion.velocity, motion.acceleration),
            m.dq,
            m.ddq,
        )
    values = {
        sp.Symbol(key, real=True): sp.Float(value)
        for key, value in robot(name).parameter_values(overrides(name)).items()
    }
    assigned = [(symbol, expr.xreplace(values)) for symbol, expr in motion.assignments]
    matrix = sp.Matrix.hstack(*motion.outputs).xreplace(values)
    evaluate = sp.lambdify(
        [list(m.q), list(m.dq), list(m.ddq)], matrix, "numpy", cse=lambda e: (assigned, e)
    )
    return lambda q, dq, ddq: np.array(evaluate(list(q), list(dq), list(ddq)), dtype=float)


def _states(name: str, seed: int, count: int = 3):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        n = robot(name).dof
        yield random_q(name, rng), rng.uniform(-1.0, 1.0, n), rng.uniform(-1.0, 1.0, n)


@pytest.mark.parametrize("form", ["closed", "recursive"])
@pytest.mark.parametrize(("name", "link", "point"), CASES)
def test_point_motion_matches_time_differences(
    name: str, link: int, point: tuple[float, float, float], form: str
) -> None:
    evaluate = _motion_function(name, link, point, form)
    for q0, dq0, ddq0 in _states(name, 30 + link):

        def position(t: float, q0=q0, dq0=dq0, ddq0=ddq0) -> np.ndarray:
            return reference(name).point(q0 + dq0 * t + 0.5 * ddq0 * t * t, link, point)

        result = evaluate(q0, dq0, ddq0)
        h = 1e-6
        velocity = (position(h) - position(-h)) / (2 * h)
        h = 1e-4
        acceleration = (position(h) - 2 * position(0.0) + position(-h)) / (h * h)
        np.testing.assert_allclose(result[:, 0], position(0.0), rtol=0, atol=1e-12)
        np.testing.assert_allclose(result[:, 1], velocity, rtol=0, atol=VELOCITY_TOL)
        np.testing.assert_allclose(result[:, 2], acceleration, rtol=0, atol=ACCELERATION_TOL)


@pytest.mark.slow
@pytest.mark.parametrize(
    "name", ["planar_2r", "planar_3r", "scara", "rpr", "stanford", "ur5", "hand_modified"]
)
def test_tool_point_velocity_is_jacobian_times_rates(name: str) -> None:
    m = model(name)
    n = robot(name).dof
    tool_point = tuple(float(x) for x in reference(name).tool[:3, 3])
    motion = m.point_motion(n, tool_point)
    velocity = function(name, motion.velocity, m.dq)
    position = function(name, motion.position)
    jacobian = function(name, m.geometric_jacobian)
    for q, dq, _ in _states(name, 40, 2):
        expected = reference(name).jacobian(q, method="complex")[:3] @ dq
        np.testing.assert_allclose(velocity(q, dq).reshape(3), expected, rtol=0, atol=1e-10)
        np.testing.assert_allclose(
            velocity(q, dq).reshape(3), jacobian(q)[:3] @ dq, rtol=0, atol=1e-10
        )
        np.testing.assert_allclose(
            position(q).reshape(3), reference(name).fk(q)[:3, 3], rtol=0, atol=1e-12
        )


@pytest.mark.parametrize("name", ["scara", "hand_standard", "hand_modified"])
def test_point_on_the_base_does_not_move(name: str) -> None:
    point = (0.3, -0.1, 0.2)
    m = model(name)
    motion = m.point_motion(0, point)
    assert motion.velocity == sp.zeros(3, 1)
    assert motion.acceleration == sp.zeros(3, 1)
    expected = (reference(name).base @ np.array([*point, 1.0]))[:3]
    position = function(name, motion.position)
    np.testing.assert_allclose(position(np.zeros(robot(name).dof)).reshape(3), expected, atol=1e-12)


def test_velocity_is_linear_in_rates_and_acceleration_uses_ddq() -> None:
    m = model("rpr")
    motion = m.point_motion(3, (0.1, 0.2, 0.3))
    assert not motion.velocity.free_symbols & set(m.ddq)
    for entry in motion.velocity:
        assert sp.Poly(entry, *m.dq).total_degree() <= 1
    assert motion.acceleration.free_symbols & set(m.ddq)


@pytest.mark.parametrize("link", [-1, 4, 10])
def test_bad_link_index_is_rejected(link: int) -> None:
    with pytest.raises(SymkinError, match="link"):
        model("scara").point_motion(link, (0.0, 0.0, 0.0))


@pytest.mark.parametrize("point", [(), (1.0, 2.0), (1.0, 2.0, 3.0, 1.0)])
def test_point_needs_three_coordinates(point: tuple[float, ...]) -> None:
    with pytest.raises(SymkinError, match="3 coordinates"):
        model("scara").point_motion(2, point)
