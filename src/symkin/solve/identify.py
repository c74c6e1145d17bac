"""Identification of the base parameters from logged states and torques by least squares.

Stacking ``tau = Y_b(q, dq, ddq) beta`` over N samples gives the overdetermined system
``W^(1/2) tau = W^(1/2) Y_b beta`` (W diagonal, one weight per joint), solved by least
squares (Gautier, "Dynamic identification of robots with power model", ICRA 1997; Swevers et
al., IEEE Trans. Robot. Autom. 13(5), 1997).  With ``r`` the weighted residual, ``N n`` rows
and ``b`` base parameters, the residual variance ``sigma^2 = |r|^2 / (N n - b)`` and
``cov(beta) = sigma^2 (Y_b^T W Y_b)^-1`` give each parameter's standard deviation.  Weights
"auto" are Gautier's: a first unweighted fit, then each joint weighted by the inverse variance
of its residual.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from symkin.derive import Model
from symkin.derive.regressor_base import BaseRegressor, base_regressor
from symkin.errors import ParameterError
from symkin.runtime.modules import generated_numpy_module

# Singular values below this fraction of the largest make the stacked regressor rank-deficient.
RANK_TOLERANCE = 1e-10
# Rows of the stacked regressor evaluated per call (bounds memory: N x n x b floats).
CHUNK = 20000


@dataclass(frozen=True)
class Identification:
    """The fit: per base parameter its name, definition, estimate and standard deviation;
    the condition number of the stacked (weighted) regressor and the residual RMS per joint."""

    names: tuple[str, ...]
    definitions: tuple[str, ...]
    estimate: np.ndarray
    std: np.ndarray
    condition_number: float
    residual_rms: np.ndarray
    samples: int
    weights: np.ndarray


def stacked_base_regressor(
    model: Model, q: np.ndarray, dq: np.ndarray, ddq: np.ndarray
) -> np.ndarray:
    """``Y_b`` at every sample, shape (N, n, b), from the generated NumPy kernel."""
    kernel = generated_numpy_module(model, "identification").base_regressor
    p = [float(v) for v in base_regressor(model.robot, model.kinematics).parameter_values]
    parts = [
        kernel(q[s : s + CHUNK], dq[s : s + CHUNK], ddq[s : s + CHUNK], p)
        for s in range(0, len(q), CHUNK)
    ]
    return np.concatenate(parts).reshape(len(q), model.robot.dof, -1)


def identify(
    model: Model,
    q: np.ndarray,
    dq: np.ndarray,
    ddq: np.ndarray,
    tau: np.ndarray,
    weights: Sequence[float] | str | None = None,
) -> Identification:
    """Least-squares base parameters from N samples (arrays N x n).

    ``weights``: None (ordinary least squares), one positive weight per joint (multiplying
    its squared residuals), or ``"auto"`` (module docstring).
    """
    base = base_regressor(model.robot, model.kinematics)
    n, b = model.robot.dof, len(base.names)
    if len(q) * n <= b:
        raise ParameterError(
            f"too few samples: {len(q)} samples give {len(q) * n} equations for {b} base "
            f"parameters; at least {b // n + 1} samples are needed"
        )
    Y = stacked_base_regressor(model, q, dq, ddq)
    _check_rank(Y.reshape(-1, b), base)
    if isinstance(weights, str):
        first = _fit(Y, tau, np.ones(n))
        w = 1.0 / np.maximum(first.residual_rms**2, np.finfo(float).tiny)
    else:
        w = np.ones(n) if weights is None else np.asarray(weights, dtype=float)
    return _fit(Y, tau, w, base)


def _check_rank(Y: np.ndarray, base: BaseRegressor) -> None:
    """Rank-deficient data (a joint never moves, too little excitation): name the base
    parameters the data cannot tell apart (the largest entries of the null-space vectors)."""
    _, singular, vt = np.linalg.svd(Y / np.maximum(np.linalg.norm(Y, axis=0), 1e-300), False)
    deficient = singular < RANK_TOLERANCE * singular[0]
    if not deficient.any():
        return
    null = np.abs(vt[deficient]).max(axis=0)
    names = [base.names[k] for k in np.argsort(-null)[: max(2, int(deficient.sum()) + 1)]]
    raise ParameterError(
        f"rank-deficient data: the stacked base regressor has rank "
        f"{len(singular) - int(deficient.sum())} < {len(singular)} base parameters; the "
        f"motion does not separate {', '.join(names)} (excite every joint, e.g. with "
        "'symkin identify ROBOT --excite')"
    )


def _fit(
    Y: np.ndarray, tau: np.ndarray, w: np.ndarray, base: BaseRegressor | None = None
) -> Identification:
    """Weighted least squares on the stacked system (module docstring)."""
    N, n, b = Y.shape
    root = np.sqrt(w)
    A = (Y * root[None, :, None]).reshape(-1, b)
    y = (tau * root[None, :]).reshape(-1)
    # Columns scaled to unit norm before the solve: their sizes span kg to kg m^2.
    scale = np.maximum(np.linalg.norm(A, axis=0), 1e-300)
    solution, *_ = np.linalg.lstsq(A / scale, y, rcond=None)
    estimate = solution / scale
    residual = tau - np.einsum("snb,b->sn", Y, estimate)
    weighted = (residual * root[None, :]).reshape(-1)
    variance = weighted @ weighted / max(N * n - b, 1)
    inverse = np.linalg.pinv((A / scale).T @ (A / scale))
    std = np.sqrt(np.maximum(variance * np.diag(inverse), 0.0)) / scale
    singular = np.linalg.svd(A, compute_uv=False)
    return Identification(
        names=base.names if base else (),
        definitions=tuple(str(d) for d in base.definitions) if base else (),
        estimate=estimate,
        std=std,
        condition_number=float(singular[0] / singular[-1]),
        residual_rms=np.sqrt(np.mean(residual**2, axis=0)),
        samples=N,
        weights=w,
    )
