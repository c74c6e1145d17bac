"""The derivative kernels printed to every backend agree: the CPython extension (the C kernels,
double and float), CasADi (also against CasADi's own automatic derivative of its tau) and the
C library built with the strict flags of the generated Makefile, all against the NumPy module
(which tests/test_derivatives.py checks against finite differences).
"""

from __future__ import annotations

import importlib.util
import subprocess
from pathlib import Path

import numpy as np
import pytest

from numeric_dh import without_inertials
from symkin.cli import main
from symkin.runtime.extension import load_extension
from test_derivatives import PRISMATIC_ARM

pytestmark = [pytest.mark.needs_cc, pytest.mark.slow]

# rpr without its file's inertial data: every link's is the input pi; the arm: friction,
# rotor inertia, modified DH.
ROBOTS = ("rpr", "prismatic_arm")
OUTPUTS = ("ddq", "dddq_dq", "dddq_ddq", "dddq_dtau")


def _import_file(path: Path):
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _derive(name: str, out: Path, precision: str) -> None:
    texts = {"prismatic_arm": PRISMATIC_ARM, "rpr": without_inertials("rpr")}
    robot = str(out.parent / f"{name}.toml")
    Path(robot).write_text(texts[name], encoding="utf-8")
    arguments = ["derive", robot, "--out", str(out), "--derivatives", "--precision", precision]
    assert main(arguments) == 0


@pytest.fixture(scope="module", params=ROBOTS)
def built(request, tmp_path_factory):
    name = request.param
    root = tmp_path_factory.mktemp(name)
    _derive(name, root / "double", "double")
    _derive(name, root / "float", "float")
    modules = {
        "numpy": _import_file(root / "double" / "numpy" / f"{name}_kinematics.py"),
        "casadi": _import_file(root / "double" / "casadi" / f"{name}_casadi.py"),
        "double": load_extension(next((root / "double" / "python").glob("*_ext*.so"))),
        "float": load_extension(next((root / "float" / "python").glob("*_ext*.so"))),
    }
    return name, root, modules


def _arguments(name: str, dof: int) -> dict:
    """``pi`` for rpr: physical random inertial data (positive masses, diagonal inertias)."""
    if name != "rpr":
        return {}
    rng = np.random.default_rng(2)
    values = []
    for _ in range(dof):
        values += [rng.uniform(0.5, 2.0), *rng.uniform(-0.1, 0.1, 3)]
        values += [*rng.uniform(0.01, 0.1, 3), 0.0, 0.0, 0.0]
    return {"pi": np.array(values)}


def _states(dof: int, count: int = 6):
    return np.random.default_rng(9).uniform(-1.2, 1.2, size=(3, count, dof))


def test_extension_matches_numpy_in_double_and_float(built):
    name, _, modules = built
    reference = modules["numpy"]
    dof = reference.DOF
    extra = _arguments(name, dof)
    q, dq, ddq = _states(dof)
    p = reference.DEFAULT_PARAMETERS
    tau = reference.inverse_dynamics(q, dq, ddq, p, **extra)
    expected = reference.forward_dynamics_derivatives(q, dq, tau, p, **extra)
    derivatives = reference.inverse_dynamics_derivatives(q, dq, ddq, p, **extra)
    for precision, tolerance in (("double", 1e-9), ("float", 2e-3)):
        extension = modules[precision]
        actual = extension.forward_dynamics_derivatives(q, dq, tau, p, **extra)
        for name, a, e in zip(OUTPUTS, actual, expected, strict=True):
            scale = max(1.0, float(np.max(np.abs(e))))
            assert np.max(np.abs(a - e)) <= tolerance * scale, f"{precision} {name}"
        single = extension.inverse_dynamics_derivatives(q[0], dq[0], ddq[0], p, **extra)
        for a, e in zip(single, derivatives, strict=True):
            scale = max(1.0, float(np.max(np.abs(e[0]))))
            assert np.max(np.abs(a - e[0])) <= tolerance * scale, f"{precision} dtau"
        rate = extension.jacobian_derivative(q, dq, p)
        for a, e in zip(rate, reference.jacobian_derivative(q, dq, p), strict=True):
            assert np.max(np.abs(a - e)) <= tolerance * max(1.0, float(np.max(np.abs(e))))


def test_casadi_matches_numpy_and_its_own_automatic_derivative(built):
    import casadi

    name, _, modules = built
    reference, generated = modules["numpy"], modules["casadi"]
    dof = reference.DOF
    extra = _arguments(name, dof)
    q, dq, ddq = (s[0] for s in _states(dof))
    p = reference.DEFAULT_PARAMETERS
    pi = list(extra.values())
    tau = reference.inverse_dynamics(q, dq, ddq, p, **extra)
    forward = generated.forward_dynamics_derivatives_function()
    actual = [np.array(v) for v in forward(q, dq, tau, p, *pi)]
    expected = reference.forward_dynamics_derivatives(q, dq, tau, p, **extra)
    for name, a, e in zip(OUTPUTS, actual, expected, strict=True):
        np.testing.assert_allclose(a.reshape(e.shape), e, atol=1e-9, err_msg=name)
    # CasADi's automatic derivative of the generated tau, a method independent of the tangents.
    x = casadi.SX.sym("q", dof)
    v = casadi.SX.sym("dq", dof)
    inverse = generated.inverse_dynamics_function()
    torque = inverse(x, v, ddq, p, *pi)
    automatic = casadi.Function(
        "ad", [x, v], [casadi.jacobian(torque, x), casadi.jacobian(torque, v)]
    )
    by_q, by_dq = (np.array(m) for m in automatic(q, dq))
    _, dtau_dq, dtau_ddq = reference.inverse_dynamics_derivatives(q, dq, ddq, p, **extra)
    np.testing.assert_allclose(dtau_dq, by_q, atol=1e-9)
    np.testing.assert_allclose(dtau_ddq, by_dq, atol=1e-9)


def test_c_sources_build_with_the_strict_makefile(built):
    _, root, _ = built
    for precision in ("double", "float"):
        result = subprocess.run(
            ["make", "-C", str(root / precision / "c")],
            capture_output=True,
            text=True,
            timeout=300,
            check=False,
        )
        assert result.returncode == 0, result.stdout + result.stderr
