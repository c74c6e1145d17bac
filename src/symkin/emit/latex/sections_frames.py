"""The frame sections of the LaTeX derivation laid out: the transform graph and the point
kinematics (content from :mod:`symkin.kernels.document_frames`).

The transform graph is a chain of frames joined by arrows labelled with their transforms
(``\\xrightarrow`` of amsmath: no extra package), then the composition rules.  The point
kinematics state the U-matrix method (Paul, "Robot Manipulators", ch. 6) and show this
robot's twist matrices ``D_j`` and, for short chains, the tool point's velocity and
acceleration.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from symkin.emit.latex.layout import align, entry_name, gather, vector_name
from symkin.emit.latex.sections import Quantity, Section, number_words
from symkin.kernels.document import Shown
from symkin.kernels.document_frames import GraphContent, PointsContent

ARROWS_PER_LINE = 4
XYZ = ("x", "y", "z")


def _frame(name: str) -> str:
    return rf"\mathcal{{F}}_{{{name}}}"


def _edge_label(kind: str, joint: int) -> str:
    if kind == "base":
        return r"T_{\mathrm{base}}"
    if kind == "tool":
        return r"T_{\mathrm{tool}}"
    return rf"A_{{{joint}}}(q_{{{joint}}})"


def graph_chain(graph: GraphContent) -> str:
    """The chain ``F_W -> F_0 -> ... -> F_E`` as gathered lines of a few arrows each."""
    lines, current, joint = [], _frame(graph.frames[0]), 0
    for count, (kind, target) in enumerate(zip(graph.edges, graph.frames[1:], strict=True), 1):
        joint += kind == "joint"
        current += rf" \xrightarrow{{{_edge_label(kind, joint)}}} {_frame(target)}"
        if count % ARROWS_PER_LINE == 0 and count < len(graph.edges):
            lines.append(current)
            current = _frame(target)  # the next line starts where this one ends
    lines.append(current)
    return gather(lines)


def section_graph(graph: GraphContent, t: Mapping[str, str]) -> Section:
    """Heading, chain and composition rules of the transform graph."""
    n = len(graph.joint_types)
    total = "".join(
        (r"T_{\mathrm{base}}\, " if "base" in graph.edges else "")
        + rf"{{}}^{{0}}T_{{{n}}}"
        + (r"\, T_{\mathrm{tool}}" if "tool" in graph.edges else "")
    )
    rules = align(
        [
            r"{}^{0}T_{0} &= I, \qquad {}^{0}T_{i} = {}^{0}T_{i-1}\, A_{i}(q_{i})"
            rf" \quad (i = 1, \ldots, {n})",
            r"{}^{i}T_{k} &= {}^{i}T_{j}\, {}^{j}T_{k}, \qquad {}^{j}T_{i} = "
            r"\left({}^{i}T_{j}\right)^{-1} = \begin{bmatrix} R^{\mathsf{T}} & -R^{\mathsf{T}} p"
            r" \\ 0 & 1 \end{bmatrix} \text{ for } {}^{i}T_{j} = \begin{bmatrix} R & p \\ 0 & 1"
            r" \end{bmatrix}",
            rf"T &= {total}",
        ]
    )
    quantities = (
        Quantity(
            "transform-graph", "TransformGraph", "the frames and transforms", graph_chain(graph)
        ),
        Quantity(
            "transform-rules",
            "TransformRules",
            "how the transforms compose",
            rules,
            t["graph_rules"],
        ),
    )
    return Section("graph", t["graph"], t["graph_intro"], quantities)


def section_points(writer: Any, points: PointsContent) -> Section:
    """The U-matrix method, this robot's twist matrices and the tool point's motion."""
    t = writer.t
    method = align(
        [
            r"U_{ij} &= \frac{\partial\, {}^{0}T_{i}}{\partial q_{j}} = D_{j}\, {}^{0}T_{i}"
            r" \quad (j \le i), \qquad U_{ij} = 0 \quad (j > i), \qquad"
            r" D_{j} = Z_{j}\, Q_{j}\, Z_{j}^{-1}",
            r"v &= \sum_{j=1}^{i} U_{ij}\, \dot{q}_{j}\, r, \qquad"
            r" a = \sum_{j=1}^{i} U_{ij}\, \ddot{q}_{j}\, r + \sum_{j=1}^{i} \sum_{k=1}^{i}"
            r" U_{ijk}\, \dot{q}_{j}\, \dot{q}_{k}\, r, \qquad"
            r" U_{ijk} = D_{\min(j,k)}\, D_{\max(j,k)}\, {}^{0}T_{i}",
        ]
    )
    quantities = [
        Quantity(
            "u-matrix-method", "UMatrixMethod", "the U-matrix method", method, t["points_method"]
        )
    ]
    for j, twist in enumerate(points.twists, start=1):
        body = writer.display(rf"D_{{{j}}}", Shown(twist, None), entry_name("d", f"^{{({j})}}"))
        quantities.append(
            Quantity(f"twist-matrix-{j}", f"TwistMatrix{number_words(j)}", f"D_{j}", body)
        )
    if points.velocity is None:
        quantities.append(
            Quantity("tool-point-motion", "ToolPointMotion", "", "", t["points_long"])
        )
    else:
        for key, symbol, vector in (
            ("velocity", "v", points.velocity),
            ("acceleration", "a", points.acceleration),
        ):
            body = writer.display(
                rf"{symbol}_{{E}}", Shown(vector, None), vector_name(symbol, XYZ, "E")
            )
            quantities.append(
                Quantity(
                    f"tool-point-{key}",
                    f"ToolPoint{key.capitalize()}",
                    f"the tool point's {key}",
                    body,
                    t[f"points_{key}"],
                )
            )
    return Section("points", t["points"], t["points_intro"], tuple(quantities))
