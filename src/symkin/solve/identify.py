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

from collections.abc import Callable, Sequence
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


def base_regressor_function(model: Model) -> Callable[..., np.ndarray]:
    """``(q, dq, ddq) -> Y_b`` at every sample (arrays N x n in, N x n x b out), from the
    generated NumPy kernel at the robot file's parameter values; look it up once, then call
    it often (the lookup hashes the robot)."""
    kernel = generated_numpy_module(model, "identification").base_regressor
    p = [float(v) for v in base_regressor(model.robot, model.kinematics).parameter_values]
    n = model.robot.dof

    def stacked(q: np.ndarray, dq: np.ndarray, ddq: np.ndarray) -> np.ndarray:
        parts = [
            kernel(q[s : s + CHUNK], dq[s : s + CHUNK], ddq[s : s + CHUNK], p)
            for s in range(0, len(q), CHUNK)
        ]
        return np.concatenate(parts).reshape(len(q), n, -1)

    return stacked


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
    Y = base_regressor_function(model)(q, dq, ddq)
    if isinstance(weights, str):
        first = _fit(Y, tau, np.ones(n), base)
        w = 1.0 / np.maximum(first.residual_rms**2, np.finfo(float).tiny)
    else:
        w = np.ones(n) if weights is None else np.asarray(weights, dtype=float)
    return _fit(Y, tau, w, base)


def condition_number(A: np.ndarray) -> float:
    """``sigma_max / sigma_min`` of a tall matrix, from the eigenvalues of ``A^T A`` (b x b):
    cheap for many rows, and accurate while the condition number is well below 1e8."""
    eigenvalues = np.linalg.eigvalsh(np.einsum("ij,ik->jk", A, A))
    return float(np.sqrt(eigenvalues[-1] / max(eigenvalues[0], np.finfo(float).tiny)))


def _check_rank(singular: np.ndarray, vt: np.ndarray, names: Sequence[str]) -> None:
    """Rank-deficient data (a joint never moves, too little excitation): name the base
    parameters the data cannot tell apart (the largest entries of the null-space vectors)."""
    deficient = singular < RANK_TOLERANCE * singular[0]
    if not deficient.any():
        return
    null = np.abs(vt[deficient]).max(axis=0)
    worst = [names[k] for k in np.argsort(-null)[: max(2, int(deficient.sum()) + 1)]]
    raise ParameterError(
        f"rank-deficient data: the stacked base regressor has rank "
        f"{len(singular) - int(deficient.sum())} < {len(singular)} base parameters; the "
        f"motion does not separate {', '.join(worst)} (excite every joint, e.g. with "
        "'symkin identify ROBOT --excite')"
    )


def _triangular_factor(A: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``R`` of the QR factorisation of ``[A y]``, a block of rows at a time (the stacked
    regressor of 10^5 samples never needs a second copy): ``R[:b, :b]`` is A's factor,
    ``R[:b, b] = Q^T y``."""
    factor = np.zeros((0, A.shape[1] + 1))
    for start in range(0, len(A), CHUNK):
        block = np.column_stack([A[start : start + CHUNK], y[start : start + CHUNK]])
        factor = np.linalg.qr(np.vstack([factor, block]), mode="r")
    return factor


def _fit(Y: np.ndarray, tau: np.ndarray, w: np.ndarray, base: BaseRegressor) -> Identification:
    """Weighted least squares on the stacked system (module docstring): the QR factor of
    the weighted regressor, then an SVD of its column-scaled ``b x b`` triangle (the columns
    span kg to kg m^2) for the solution, the rank and ``(A^T A)^-1``."""
    N, n, b = Y.shape
    root = np.sqrt(w)
    A = (Y * root[None, :, None]).reshape(-1, b)
    y = (tau * root[None, :]).reshape(-1)
    factor = _triangular_factor(A, y)
    triangle = factor[:b, :b]
    scale = np.maximum(np.linalg.norm(triangle, axis=0), np.finfo(float).tiny)
    u, singular, vt = np.linalg.svd(triangle / scale)
    _check_rank(singular, vt, base.names)
    estimate = (vt.T @ ((u.T @ factor[:b, b]) / singular)) / scale
    residual = tau - np.einsum("snb,b->sn", Y, estimate)
    weighted = (residual * root[None, :]).reshape(-1)
    variance = weighted @ weighted / max(N * n - b, 1)
    # (A^T A)^-1 = V S^-2 V^T of the scaled columns, undone per parameter.
    std = np.sqrt(variance * np.sum((vt.T / singular) ** 2, axis=1)) / scale
    unscaled = np.linalg.svd(triangle, compute_uv=False)
    return Identification(
        names=base.names,
        definitions=tuple(str(d) for d in base.definitions),
        estimate=estimate,
        std=std,
        condition_number=float(unscaled[0] / unscaled[-1]),
        residual_rms=np.sqrt(np.mean(residual**2, axis=0)),
        samples=N,
        weights=w,
    )
