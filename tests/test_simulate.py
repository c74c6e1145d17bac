"""The simulator's stick/slip friction, DC motors and smooth Coulomb friction, against hand
formulas: a block on a slope (sticks when m g sin(alpha) <= mu_s m g cos(alpha), else slides
with a = g (sin(alpha) - mu_k cos(alpha))), a DC motor's steady state.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from symkin import load_robot
from symkin.derive import Model, derive
from symkin.errors import ParameterError
from symkin.runtime.modules import generated_numpy_module
from symkin.solve.simulate import simulate

G = 9.81
MASS = 2.0


def block_on_slope(tmp_path: Path, alpha: float, mu_s: float, mu_k: float) -> Model:
    """A prismatic joint along the slope (its z axis): gravity's component along it is
    ``-g sin(alpha)``; the normal force ``m g cos(alpha)`` sets the friction levels."""
    normal = MASS * G * math.cos(alpha)
    path = tmp_path / "block.toml"
    path.write_text(
        f'name = "block"\ngravity = [{G * math.cos(alpha)!r}, 0, {-G * math.sin(alpha)!r}]\n'
        '[[joints]]\ntype = "prismatic"\n[joints.link]\n'
        f"mass = {MASS}\nfriction = {{ coulomb = {mu_k * normal!r}, "
        f"stiction = {mu_s * normal!r} }}\n"
    )
    return derive(load_robot(path))


def test_block_pushed_up_a_gentle_slope_stops_and_sticks(tmp_path: Path) -> None:
    alpha, mu_s, mu_k, v0 = 0.4, 0.5, 0.3, 2.0
    assert math.tan(alpha) <= mu_s  # static friction can hold it
    run = simulate(block_on_slope(tmp_path, alpha, mu_s, mu_k), 1.5, [0.0], [v0], samples=31)
    deceleration = G * (math.sin(alpha) + mu_k * math.cos(alpha))
    stop = v0 / deceleration
    t = np.minimum(run.t, stop)
    np.testing.assert_allclose(run.q[:, 0], v0 * t - deceleration * t**2 / 2, atol=1e-9)
    np.testing.assert_array_equal(run.stuck[:, 0], run.t > stop)


def test_block_on_a_steep_slope_slides_down_from_rest(tmp_path: Path) -> None:
    alpha, mu_s, mu_k = 0.6, 0.5, 0.3
    assert math.tan(alpha) > mu_s
    run = simulate(block_on_slope(tmp_path, alpha, mu_s, mu_k), 1.0, [0.0], [0.0], samples=11)
    acceleration = G * (math.sin(alpha) - mu_k * math.cos(alpha))
    np.testing.assert_allclose(run.q[:, 0], -acceleration * run.t**2 / 2, atol=1e-9)
    assert not run.stuck.any()


def test_block_at_rest_on_a_gentle_slope_stays(tmp_path: Path) -> None:
    run = simulate(block_on_slope(tmp_path, 0.4, 0.5, 0.3), 1.0, [0.1], [0.0], samples=5)
    np.testing.assert_array_equal(run.q[:, 0], 0.1)
    assert run.stuck.all()


MOTOR = {"G": 10.0, "kt": 0.05, "ke": 0.05, "R": 1.2, "b": 0.1}


def motor_arm(tmp_path: Path, inductance: str) -> Model:
    """One joint about the vertical (no gravity torque), viscous friction b, a geared DC motor."""
    path = tmp_path / "motor.toml"
    path.write_text(
        'name = "motor"\n[[joints]]\ntype = "revolute"\n[joints.link]\nmass = 1\n'
        "inertia = { ixx = 0.05, iyy = 0.05, izz = 0.05 }\n"
        f"friction = {{ viscous = {MOTOR['b']} }}\n"
        f"drive = {{ gear_ratio = {MOTOR['G']}, rotor_inertia = 1e-4, torque_constant = "
        f"{MOTOR['kt']}, back_emf_constant = {MOTOR['ke']}, resistance = {MOTOR['R']}"
        f"{inductance} }}\n"
    )
    return derive(load_robot(path))


@pytest.mark.parametrize("inductance", ["", ", inductance = 2e-3"])
def test_dc_motor_reaches_the_hand_steady_state(tmp_path: Path, inductance: str) -> None:
    g, kt, ke, r, b = MOTOR.values()
    voltage = 12.0
    # Steady state: G kt i = b w and i = (U - ke G w) / R.
    speed = g * kt * voltage / (r * b + g**2 * kt * ke)
    current = b * speed / (g * kt)
    model = motor_arm(tmp_path, inductance)
    run = simulate(model, 4.0, [0.0], [0.0], voltage=lambda t: [voltage], samples=3)
    assert run.dq[-1, 0] == pytest.approx(speed, rel=1e-6)
    if inductance:
        assert run.current[-1, 0] == pytest.approx(current, rel=1e-6)
    with pytest.raises(ParameterError, match="voltage"):
        simulate(model, 1.0, [0.0], [0.0])


def test_smooth_coulomb_friction_is_tanh_of_speed_over_width(tmp_path: Path) -> None:
    path = tmp_path / "smooth.toml"
    path.write_text(
        'name = "smooth"\n[[joints]]\ntype = "revolute"\n[joints.link]\nmass = 1\n'
        "friction = { coulomb = 0.7, viscous = 0.2, smoothing = 0.05 }\n"
    )
    module = generated_numpy_module(derive(load_robot(path)))
    for speed in (-0.2, -0.01, 0.0, 0.03, 1.0):
        torque = module.inverse_dynamics([0.3], [speed], [0.0])[0]
        assert torque == pytest.approx(0.7 * math.tanh(speed / 0.05) + 0.2 * speed, abs=1e-12)


@pytest.mark.parametrize("inductance", ["", ", inductance = 2e-3"])
def test_casadi_motor_dynamics_rest_at_the_hand_steady_state(
    tmp_path: Path, inductance: str
) -> None:
    from symkin.solve.drives import motor_dynamics_function

    g, kt, ke, r, b = MOTOR.values()
    voltage = 12.0
    speed = g * kt * voltage / (r * b + g**2 * kt * ke)
    current = b * speed / (g * kt)
    function = motor_dynamics_function(motor_arm(tmp_path, inductance))
    ddq, di = function([0.4], [speed], [current], [voltage])
    assert float(ddq) == pytest.approx(0.0, abs=1e-9)
    assert float(di) == pytest.approx(0.0, abs=1e-9)
    ddq, _ = function([0.4], [0.0], [current], [voltage])
    assert float(ddq) > 1.0  # from rest the motor accelerates the joint
