"""The DH extraction as a LaTeX document for a lecture (``symkin dh --latex FILE``).

For each pair of successive axes (the last paired with the tool's z axis): which case they
are (skew, parallel, intersecting, coincident), how the x axis and origin are chosen, and the
resulting ``a``, ``alpha``, ``d``, ``theta``; then the table, the constant base and tool
transforms and the proof of equal forward kinematics.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from symkin.derive.dh_extraction import AxisStep, DhExtraction
from symkin.derive.dh_lines import SNAP_TOLERANCE
from symkin.derive.dh_proof import FkProof
from symkin.emit.latex.document import escape_text
from symkin.emit.render import render

CASE_TEXT = {
    "skew": (
        "The axes are skew: they have exactly one common normal. $x$ lies along it, the new "
        "origin where it meets the axis it points to, and $a$ is its length."
    ),
    "parallel": (
        "The axes are parallel: every perpendicular between them is a common normal. The usual "
        "choice takes the one through the previous origin, so $d = 0$; $a$ is the distance "
        "between the axes and $\\alpha \\in \\{0, \\pi\\}$."
    ),
    "intersecting": (
        "The axes intersect: the common normal has length zero, so $a = 0$; $x$ is "
        "$\\pm z_{\\mathrm{prev}} \\times z_{\\mathrm{next}}$ and the origin is the "
        "intersection point."
    ),
    "coincident": (
        "The axes coincide: any direction perpendicular to them is a common normal, so $a = 0$ "
        "and $\\alpha \\in \\{0, \\pi\\}$; $x$ is taken along the previous $x$ axis (along the "
        "tool's $x$ axis for the last frame)."
    ),
}


def vector_tex(vector: np.ndarray) -> str:
    entries = " & ".join(f"{v:.6g}" if abs(v) > SNAP_TOLERANCE else "0" for v in vector)
    return rf"\begin{{pmatrix}} {entries} \end{{pmatrix}}^{{\!\top}}"


def value_tex(value: sp.Expr) -> str:
    return sp.latex(value) if value.has(sp.pi) or value == 0 else f"{float(value):.10g}"


def offset_tex(variable: str, moves: bool, value: sp.Expr) -> str:
    """``q_i + offset`` for the joint's variable, ``q_i`` alone for a zero offset."""
    if not moves:
        return value_tex(value)
    return variable if value == 0 else f"{variable} + {value_tex(value)}"


def step_context(step: AxisStep, extraction: DhExtraction) -> dict[str, str]:
    """Heading, case and values of one pair of axes.  Standard: the pair (axis i, axis i+1)
    fixes row i whole.  Modified: it fixes ``x_i``, so ``a_i, alpha_i`` (row i+1, or the
    tool transform after the last joint) and, with ``x_{i-1}``, ``d_i, theta_i`` (row i)."""
    robot = extraction.robot
    i = step.index
    joint = robot.joints[i - 1]
    target = "the tool's $z$ axis" if i == robot.dof else f"axis {i + 1}"
    theta, d, a, alpha = step.row
    variable = f"q_{{{i}}}"
    values = [
        rf"d_{{{i}}} = {offset_tex(variable, joint.type == 'prismatic', d)}",
        rf"\theta_{{{i}}} = {offset_tex(variable, joint.type == 'revolute', theta)}",
    ]
    if robot.convention == "standard":
        values = [rf"a_{{{i}}} = {value_tex(a)}", rf"\alpha_{{{i}}} = {value_tex(alpha)}", *values]
    elif i < robot.dof:
        following = extraction.steps[i].row
        values += [
            rf"a_{{{i}}} = {value_tex(following[2])}",
            rf"\alpha_{{{i}}} = {value_tex(following[3])}",
        ]
    return {
        "heading": f"Axis {i} and {target}: {step.case}",
        "case_text": CASE_TEXT[step.case],
        "formula": r", \quad ".join(values),
    }


def dh_derivation_tex(extraction: DhExtraction, proof: FkProof) -> str:
    """The document text (compiles with pdflatex; amsmath and booktabs only)."""
    robot = extraction.robot
    names = [f"{i + 1}" for i in range(robot.dof)] + ["tool $z$"]
    rows = []
    for step, joint in zip(extraction.steps, robot.joints, strict=True):
        context = step_context(step, extraction)
        theta, d, a, alpha = step.row
        rows.append(
            {
                "index": step.index,
                "theta": offset_tex(f"q_{{{step.index}}}", joint.type == "revolute", theta),
                "d": offset_tex(f"q_{{{step.index}}}", joint.type == "prismatic", d),
                "a": value_tex(a),
                "alpha": value_tex(alpha),
                "context": context,
            }
        )
    modified = robot.convention == "modified"
    return render(
        "latex/dh_derivation.tex.j2",
        header=[f"DH extraction of {robot.name} ({robot.convention} convention), by symkin dh"],
        title=escape_text(f"{robot.title or robot.name}"),
        intro=(
            f"The {robot.convention} Denavit--Hartenberg table of {escape_text(robot.name)}, "
            "found by the frame-assignment procedure: $z$ along each joint axis, in the "
            "direction its variable grows, and $x$ along the common normal of successive axes. "
            f"Values within {SNAP_TOLERANCE:g} of a multiple of $15^\\circ$ (angles) or of $0$ "
            "(lengths) are taken as exact."
        ),
        lines=[
            {"name": name, "point": vector_tex(line.point), "direction": vector_tex(line.direction)}
            for name, line in zip(names, extraction.lines, strict=True)
        ],
        steps=[row["context"] for row in rows],
        rows=rows,
        index_shift="{i-1}" if modified else "i",
        convention_text=(
            r"Modified convention: "
            r"$A_i = R_x(\alpha_{i-1})\,T_x(a_{i-1})\,R_z(\theta_i)\,T_z(d_i)$."
            if modified
            else r"Standard convention: $A_i = R_z(\theta_i)\,T_z(d_i)\,T_x(a_i)\,R_x(\alpha_i)$."
        ),
        base=matrix_tex(robot.base),
        tool=matrix_tex(robot.tool),
        proof=escape_text(proof.summary()),
    )


def matrix_tex(matrix: sp.MatrixBase) -> str:
    """A constant transform, entries to 6 significant digits (a 4x4 of full floats is wider
    than the page)."""

    def entry(value: sp.Expr) -> str:
        return sp.latex(value) if value.is_Integer else f"{float(value):.6g}"

    rows = [" & ".join(entry(v) for v in matrix.row(i)) for i in range(matrix.rows)]
    return r"\begin{pmatrix} " + r" \\ ".join(rows) + r" \end{pmatrix}"
