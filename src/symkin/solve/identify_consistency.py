"""Physical consistency of identified base parameters: is there a set of link parameters with
non-negative masses and physically valid inertias (and non-negative rotor inertias and
friction coefficients) whose base parameters are the estimate?

A link's ten parameters are physically consistent exactly when its pseudo-inertia matrix
``J = [[Sigma, h], [h^T, m]]``, ``Sigma = tr(I_o)/2 E - I_o``, is positive semidefinite
(Wensing, Kim and Slotine, "Linear matrix inequalities for physically consistent inertial
parameter identification", IEEE RA-L 3(1), 2018): it implies ``m >= 0`` and the triangle
inequalities of the inertia about the centre of mass.  Writing ``J = F F^T`` (F any 4x4
matrix) and each drive parameter as a square makes every candidate consistent; the nearest
one to the estimate is found by ``scipy.optimize.least_squares`` on ``(beta(pi) - beta_hat) /
tolerance``, with a tolerance per base parameter of three standard deviations (at least
``RELATIVE_FLOOR`` of the largest estimate).  The estimate is consistent when the nearest set
meets every base parameter within its tolerance.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from symkin.derive.regressor_base import BaseRegressor

RELATIVE_FLOOR = 1e-6
STARTS = 3
# Solver steps per start: the residual is quadratic in the variables, a few dozen suffice.
EVALUATIONS = 60
LINK_NAMES = ("xx", "xy", "xz", "yy", "yz", "zz", "mx", "my", "mz", "m")


@dataclass(frozen=True)
class Consistency:
    """``consistent``; the base parameters the nearest consistent set misses (name, estimate,
    nearest value, tolerance) and the links whose pseudo-inertia is singular there (their
    mass or an inertia triangle inequality is at its limit)."""

    consistent: bool
    misses: tuple[tuple[str, float, float, float], ...]
    boundary_links: tuple[int, ...]
    nearest: np.ndarray


def _link_parameters(factor: np.ndarray) -> dict[str, float]:
    """Barycentric parameters of ``J = F F^T`` (module docstring): ``I_o = tr(Sigma) E - Sigma``."""
    J = factor @ factor.T
    sigma, h, m = J[:3, :3], J[:3, 3], J[3, 3]
    inertia = np.trace(sigma) * np.eye(3) - sigma
    return {
        "xx": inertia[0, 0],
        "xy": inertia[0, 1],
        "xz": inertia[0, 2],
        "yy": inertia[1, 1],
        "yz": inertia[1, 2],
        "zz": inertia[2, 2],
        "mx": h[0],
        "my": h[1],
        "mz": h[2],
        "m": m,
    }


def _pseudo_inertia(values: dict[str, float]) -> np.ndarray:
    v = values
    inertia = np.array(
        [[v["xx"], v["xy"], v["xz"]], [v["xy"], v["yy"], v["yz"]], [v["xz"], v["yz"], v["zz"]]]
    )
    J = np.zeros((4, 4))
    J[:3, :3] = np.trace(inertia) / 2 * np.eye(3) - inertia
    J[:3, 3] = J[3, :3] = [v["mx"], v["my"], v["mz"]]
    J[3, 3] = v["m"]
    return J


class _Candidate:
    """Full parameters ``pi`` (in the regressor's column order) from free variables."""

    def __init__(self, base: BaseRegressor):
        self.full = base.full
        self.dof = max(base.full.links) + 1
        self.drive = [
            k for k, s in enumerate(base.full.names) if s.rstrip("0123456789") not in LINK_NAMES
        ]

    def size(self) -> int:
        return 16 * self.dof + len(self.drive)

    def pi(self, x: np.ndarray) -> np.ndarray:
        links = [_link_parameters(x[16 * i : 16 * i + 16].reshape(4, 4)) for i in range(self.dof)]
        pi = np.zeros(len(self.full.names))
        for k, (name, link) in enumerate(zip(self.full.names, self.full.links, strict=True)):
            stem = name.rstrip("0123456789")
            if stem in LINK_NAMES:
                pi[k] = links[link][stem]
        pi[self.drive] = x[16 * self.dof :] ** 2
        return pi

    def start(self, pi: np.ndarray) -> np.ndarray:
        """Variables whose ``pi`` is near ``pi`` (each ``J`` clipped to semidefinite)."""
        x = []
        for i in range(self.dof):
            values = {
                name.rstrip("0123456789"): pi[k]
                for k, (name, link) in enumerate(zip(self.full.names, self.full.links, strict=True))
                if link == i
            }
            eigenvalues, vectors = np.linalg.eigh(_pseudo_inertia(values))
            x.append((vectors * np.sqrt(np.maximum(eigenvalues, 0.0))).ravel())
        x.append(np.sqrt(np.abs(pi[self.drive])))
        return np.concatenate(x)


def physical_consistency(
    base: BaseRegressor, estimate: np.ndarray, std: np.ndarray, seed: int = 0
) -> Consistency:
    """Whether a consistent set of link parameters gives ``estimate`` (module docstring)."""
    from scipy.optimize import least_squares  # scipy: only identification needs it

    candidate = _Candidate(base)
    tolerance = np.maximum(3.0 * std, RELATIVE_FLOOR * np.max(np.abs(estimate)))

    def residual(x: np.ndarray) -> np.ndarray:
        return (base.beta(candidate.pi(x)) - estimate) / tolerance

    rng = np.random.default_rng(seed)
    starts = [candidate.start(np.array(base.full.values))] if base.full.values else []
    starts += [rng.normal(0.0, 0.3, candidate.size()) for _ in range(STARTS - len(starts))]
    best = min(
        (least_squares(residual, x0, method="trf", max_nfev=EVALUATIONS) for x0 in starts),
        key=lambda result: np.max(np.abs(result.fun)),
    )
    nearest = candidate.pi(best.x)
    beta = base.beta(nearest)
    misses = tuple(
        (name, float(e), float(b), float(t))
        for name, e, b, t in zip(base.names, estimate, beta, tolerance, strict=True)
        if abs(b - e) > t
    )
    boundary = tuple(
        i + 1
        for i in range(candidate.dof)
        if np.linalg.eigvalsh(
            best.x[16 * i : 16 * i + 16].reshape(4, 4)
            @ best.x[16 * i : 16 * i + 16].reshape(4, 4).T
        )[0]
        <= 1e-9 * max(1.0, np.max(np.abs(nearest)))
    )
    return Consistency(not misses, misses, boundary, nearest)
