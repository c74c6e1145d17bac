"""Symbolic quantities of a model as NumPy functions (``sympy.lambdify``), parameters bound.

The reference path: clear, not fast.  Parameters take their file values unless overridden.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import sympy as sp

from symkin.derive import Model
from symkin.errors import ParameterError


def parameter_substitution(
    model: Model, overrides: Mapping[str, float] | None = None
) -> dict[sp.Symbol, float]:
    """Parameter symbols mapped to their numbers (file values, ``overrides`` first)."""
    values = model.robot.parameter_values(overrides)
    return {s: values[s.name] for s in model.robot.parameter_symbols}


def numeric_function(
    model: Model,
    expr: sp.MatrixBase | sp.Expr,
    overrides: Mapping[str, float] | None = None,
):
    """``f(q, dq, ddq) -> ndarray`` for a symbolic quantity of ``model``."""
    values = parameter_substitution(model, overrides)
    substituted = sp.sympify(expr).xreplace(values)
    if substituted.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
        given = ", ".join(f"{s.name} = {v:g}" for s, v in values.items())
        raise ParameterError(
            f"{model.robot.name}: a formula divides by zero at the parameter values ({given}); "
            "choose other values with {overrides}"
        )
    function = sp.lambdify([model.q, model.dq, model.ddq], substituted, modules="numpy")

    def evaluate(q, dq=None, ddq=None) -> np.ndarray:
        zeros = np.zeros(model.robot.dof)
        dq = zeros if dq is None else dq
        ddq = zeros if ddq is None else ddq
        return np.asarray(function(q, dq, ddq), dtype=float)

    return evaluate
