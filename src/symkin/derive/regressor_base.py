"""The base regressor ``Y_b``: the independent columns of ``Y``, and what they identify.

``Y pi = Y_b beta`` with ``beta = pi_kept + K pi_dropped`` (Gautier, "Numerical calculation
of the base inertial parameters of robots", J. Robotic Systems 8(4), 1991): the columns are
offered in the order of :func:`symkin.derive.regressor.regressor` (inner links first) and a
column dependent on the ones before it is dropped, its parameter folded into the kept ones
(:func:`symkin.derive.base_parameters.folding_from_samples`).  ``Y_b`` is a column subset of
``Y``, so it is exact for symbolic geometry too; the coefficients ``K`` are numbers found at
random states, for a geometry with parameters at the robot file's values (``K`` holds
products of lengths such as ``a2**2``, which then enter as numbers).

Names follow Khalil: the kept parameter in capitals, with ``R`` when others fold into it
(``ZZ2R``, ``MX3R``, ``IA1R``).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import sympy as sp

from symkin.derive.base_parameters import (
    NEGLIGIBLE,
    Folding,
    _shortest_decimal,
    folding_from_samples,
)
from symkin.derive.kinematics import Kinematics
from symkin.derive.regressor import Regressor, regressor, regressor_function
from symkin.errors import RobotError
from symkin.robot import Robot

SAMPLES = 15


@dataclass(frozen=True)
class BaseRegressor:
    """``Y_b`` (the kept columns of ``Y``), each base parameter's name and definition in the
    robot's inertial symbols, and the folding it came from (over ``Y``'s columns).

    ``values`` are the base parameters of the robot file's data (None when they hold
    symbols); ``parameter_values`` the geometry parameters ``K`` was found at (empty when the
    geometry is numeric).
    """

    full: Regressor
    folding: Folding
    symbols: tuple[sp.Symbol, ...]
    definitions: tuple[sp.Expr, ...]
    parameter_values: tuple[float, ...]

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.symbols)

    @property
    def matrix(self) -> sp.ImmutableMatrix:
        return self.full.matrix.extract(list(range(self.full.matrix.rows)), list(self.folding.kept))

    @property
    def values(self) -> tuple[float, ...] | None:
        if self.full.values is None:
            return None
        beta = self.folding.beta(np.array(self.full.values))
        return tuple(float(beta[k]) for k in self.folding.kept)

    def beta(self, pi: np.ndarray) -> np.ndarray:
        """Base parameters (kept entries) of full parameters ``pi``."""
        return self.folding.beta(np.asarray(pi, dtype=float))[list(self.folding.kept)]


def parameter_values(robot: Robot) -> tuple[float, ...]:
    """The robot file's values of its geometry parameters, in file order."""
    values = []
    for name, value in robot.parameters:
        if not sp.sympify(value).is_number:
            raise RobotError(f"parameter {name!r} needs a numeric value for the base parameters")
        values.append(float(value))
    return tuple(values)


@lru_cache(maxsize=16)
def base_regressor(robot: Robot, kinematics: Kinematics) -> BaseRegressor:
    """The base regressor of the robot at its file's parameter values (module docstring)."""
    full = regressor(robot, kinematics)
    evaluate = regressor_function(robot, kinematics)
    p = parameter_values(robot)

    def stacked(seed: int) -> np.ndarray:
        rng = np.random.default_rng(seed)
        return np.vstack(
            [evaluate(*rng.uniform(-2.0, 2.0, (3, robot.dof)), p) for _ in range(SAMPLES)]
        )

    folding = folding_from_samples(stacked(1), stacked(2))
    if folding is None:
        raise RobotError(
            f"{robot.name}: the base parameters failed their check at random states "
            "(the regressor's columns are too badly scaled to separate)"
        )
    symbols, definitions = _named_definitions(full, folding)
    return BaseRegressor(full, folding, symbols, definitions, p)


def _named_definitions(
    full: Regressor, folding: Folding
) -> tuple[tuple[sp.Symbol, ...], tuple[sp.Expr, ...]]:
    """Khalil's names and ``beta_k = pi_k + sum_d K_kd pi_d`` in the robot's inertial
    symbols; a coefficient is rounded relative to itself, one below 1e-12 of the largest is
    least-squares noise (as in :func:`symkin.derive.base_parameters.symbolic_base_parameters`)."""
    noise = 1e-12 * max((abs(c) for row in folding.matrix for c in row), default=1.0)
    symbols, definitions = [], []
    for row, k in zip(folding.matrix, folding.kept, strict=True):
        folded = [
            _exact(_shortest_decimal(c, 10 * NEGLIGIBLE * abs(c))) * full.definitions[d]
            for c, d in zip(row, folding.dropped, strict=True)
            if abs(c) > noise
        ]
        name = full.symbols[k].name
        stem = name.rstrip("0123456789")
        suffix = "R" if folded else ""
        symbols.append(sp.Symbol(f"{stem.upper()}{name[len(stem) :]}{suffix}", real=True))
        definitions.append(sp.expand(full.definitions[k] + sp.Add(*folded)))
    return tuple(symbols), tuple(definitions)


def _exact(value: float) -> sp.Number:
    """An integer where the coefficient is one (``2*mx1`` for a unit length), else a float."""
    return sp.Integer(int(value)) if value == int(value) else sp.Float(value)
