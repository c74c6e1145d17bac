"""Jupyter's ``_repr_latex_`` of a model: ``T = base A_1 ... A_n tool`` as a LaTeX matrix.

Printed by the document's printer (joint variables as ``q_{1}``), the readable form when the
model has one.  Registered with :mod:`symkin.derive.display` on import.
"""

from __future__ import annotations

from symkin.derive import Model
from symkin.derive.display import register_display
from symkin.emit.latex.printer import KinematicsLatexPrinter


def model_latex(model: Model) -> str:
    """``$T^{0}_{n} = ...$`` for the model's robot."""
    printer = KinematicsLatexPrinter(model.q, model.dq, model.ddq)
    matrix = printer.doprint(model.forward_kinematics)
    return f"$T^{{0}}_{{{model.robot.dof}}} = {matrix}$"


register_display("latex", model_latex)
