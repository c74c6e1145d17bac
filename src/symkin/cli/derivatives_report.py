"""``symkin eval --derivatives``: the derivatives of the dynamics and the Jacobian as JSON
keys and text lines (row = output index; see :class:`~symkin.solve.derivatives.
DynamicsDerivatives`)."""

from __future__ import annotations

import numpy as np

from symkin.solve.derivatives import DynamicsDerivatives

# The DynamicsDerivatives fields shown, in print order; each is its own JSON key.
KEYS = (
    "dtau_dq",
    "dtau_ddq",
    "dddq_dq",
    "dddq_ddq",
    "dddq_dtau",
    "jacobian_dot",
    "jacobian_dot_dq",
)


def derivatives_json(derivatives: DynamicsDerivatives | None) -> dict:
    if derivatives is None:
        return {}
    return {key: np.asarray(getattr(derivatives, key)).tolist() for key in KEYS}


def derivatives_text(derivatives: DynamicsDerivatives | None) -> str:
    if derivatives is None:
        return ""
    lines = [""]
    for key in KEYS:
        values = np.asarray(getattr(derivatives, key)) + 0.0  # -0.0 prints as 0.0
        lines += [f"{key} =", np.array2string(values, precision=6, suppress_small=True)]
    return "\n".join(lines)
