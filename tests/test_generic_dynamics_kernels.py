"""The dynamics kernels of an arm without a readable form (their CSE is SymEngine's, see
``symkin.kernels.catalogue.cse_engine``) against independent relations: Christoffel ``C``
from central finite differences of the ``mass_matrix`` kernel, ``c = C dq``, ``tau = M ddq +
c + G`` and ``bias = c + G``; catalogue robots keep SymPy's CSE."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import sympy as sp

import symkin
from symkin.derive import Model
from symkin.kernels import dynamics_kernels
from symkin.kernels.catalogue import cse_engine

TILTED = Path(__file__).parent / "data" / "dh_tilted_arm.toml"


def _compiled(kernel):
    """The kernel as a NumPy function of its inputs, its intermediates evaluated in order."""
    return sp.lambdify(
        [i.symbols for i in kernel.inputs],
        [o.matrix for o in kernel.outputs],
        modules="numpy",
        cse=lambda outputs: (list(kernel.assignments), outputs),
    )


def _mass_derivatives(mass_matrix, q: np.ndarray, p: list[float], h: float = 1e-6) -> np.ndarray:
    """``dM/dq_i`` for every ``i`` by central differences of the mass-matrix kernel."""
    steps = np.eye(len(q)) * h
    return np.array(
        [(mass_matrix(q + s, p)[0] - mass_matrix(q - s, p)[0]) / (2 * h) for s in steps]
    )


def test_catalogue_robots_keep_sympys_cse() -> None:
    assert cse_engine(Model(symkin.load_robot("puma560"))) == "sympy"


def test_dynamics_kernels_without_readable_form_keep_christoffel_and_sums() -> None:
    rob = symkin.robot_from_toml(TILTED.read_text(), TILTED.name)
    model = Model(rob, simplified=False)  # no readable form: SymEngine's CSE
    assert cse_engine(model) == "symengine"
    kernels = {k.name: _compiled(k) for k in dynamics_kernels(model)}
    p = [value for _, value in rob.parameter_values().items()]
    n = rob.dof
    rng = np.random.default_rng(15)
    for q, dq, ddq in rng.uniform(-1.5, 1.5, size=(3, 3, n)):
        (mass,) = kernels["mass_matrix"](q, p)

        d = _mass_derivatives(kernels["mass_matrix"], q, p)  # d[i, r, c] = dM_rc / dq_i
        christoffel = 0.5 * (
            np.einsum("ikj,i->kj", d, dq)
            + np.einsum("jki,i->kj", d, dq)
            - np.einsum("kij,i->kj", d, dq)
        )
        (coriolis_matrix,) = kernels["coriolis_matrix"](q, dq, p)
        np.testing.assert_allclose(coriolis_matrix, christoffel, rtol=0, atol=1e-7)
        (coriolis,) = kernels["coriolis"](q, dq, p)
        np.testing.assert_allclose(np.ravel(coriolis), coriolis_matrix @ dq, rtol=0, atol=1e-12)
        (gravity,) = kernels["gravity"](q, p)
        (tau,) = kernels["inverse_dynamics"](q, dq, ddq, p)
        expected = mass @ ddq + np.ravel(coriolis) + np.ravel(gravity)
        np.testing.assert_allclose(np.ravel(tau), expected, rtol=0, atol=1e-12)
        both, bias = kernels["mass_matrix_bias"](q, dq, p)
        np.testing.assert_allclose(both, mass, rtol=0, atol=1e-12)
        np.testing.assert_allclose(np.ravel(bias), np.ravel(coriolis + gravity), rtol=0, atol=1e-12)
