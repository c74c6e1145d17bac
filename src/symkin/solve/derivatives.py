"""Numeric derivatives of the equations of motion and of the Jacobian at one state, from the
generated NumPy derivative kernels (:mod:`symkin.kernels.derivatives`), built once per robot
and process.

Every matrix has the output index as its row: ``dtau_dq[i, j] = d tau_i / d q_j``.  Names
follow the code's ``q, dq, ddq``: ``dtau_ddq`` is the derivative by the joint *velocities*
``dq`` and ``dtau_dq`` by the positions; the derivative by the accelerations is ``M``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from symkin.derive import Model
from symkin.errors import ParameterError
from symkin.runtime.modules import generated_numpy_module
from symkin.solve.evaluate import dynamics_arguments


@dataclass(frozen=True)
class DynamicsDerivatives:
    """Partial derivatives at ``(q, dq, ddq)``; ``tau`` is the inverse dynamics there, so the
    forward dynamics' derivatives are those at ``(q, dq, tau)`` with ``FD(q, dq, tau) = ddq``.

    ``dtau_dq``, ``dtau_ddq``: d tau / d q, d tau / d dq (n x n); ``mass_matrix`` is
    d tau / d ddq.  ``dddq_dq = -M^-1 dtau_dq``, ``dddq_ddq = -M^-1 dtau_ddq``,
    ``dddq_dtau = M^-1`` (n x n).  ``jacobian_dot``: dJ/dt of the base-frame geometric
    Jacobian (6 x n); ``jacobian_dot_dq``: dJ/dt dq, the tool's spatial acceleration (linear,
    angular) at ``ddq = 0`` (6).
    """

    torque: np.ndarray
    dtau_dq: np.ndarray
    dtau_ddq: np.ndarray
    mass_matrix: np.ndarray
    dddq_dq: np.ndarray
    dddq_ddq: np.ndarray
    dddq_dtau: np.ndarray
    jacobian_dot: np.ndarray
    jacobian_dot_dq: np.ndarray


def dynamics_derivatives(
    model: Model,
    q: Sequence[float],
    dq: Sequence[float],
    ddq: Sequence[float],
    overrides: Mapping[str, float] | None = None,
) -> DynamicsDerivatives:
    """The derivatives of ``tau(q, dq, ddq)``, of the forward dynamics and of ``J`` at one
    state (see :class:`DynamicsDerivatives`); ``overrides`` as for
    :func:`~symkin.solve.evaluate.dynamic_state`.

    Raises :class:`ParameterError` for a wrong number of values or a non-finite result (a
    mass matrix that is not positive definite: non-physical inertial data).
    """
    n = model.robot.dof
    states = [np.asarray(v, dtype=float) for v in (q, dq, ddq)]
    for name, values in zip(("q", "dq", "ddq"), states, strict=True):
        if values.shape != (n,):
            raise ParameterError(f"{{{name}}} needs {n} values (one per joint), got {values.size}")
    shared = dynamics_arguments(model, overrides)
    module = generated_numpy_module(model, "derivatives")
    with np.errstate(all="ignore"):
        tau, dtau_dq, dtau_ddq = module.inverse_dynamics_derivatives(*states, **shared)
        mass = module.mass_matrix(states[0], **shared)
        forward = module.forward_dynamics_derivatives(states[0], states[1], tau, **shared)
        jacobian_dot, bias = module.jacobian_derivative(states[0], states[1], shared["p"])
    result = DynamicsDerivatives(tau, dtau_dq, dtau_ddq, mass, *forward[1:], jacobian_dot, bias)
    if not all(np.all(np.isfinite(v)) for v in vars(result).values()):
        raise ParameterError(
            f"{model.robot.name}: the dynamics' derivatives are not finite at this state "
            "(a mass matrix that is not positive definite, or a formula that divides by zero "
            "at the parameter values); check the inertial data and {overrides}"
        )
    return result
