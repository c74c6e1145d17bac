"""The LaTeX document's transform graph and point kinematics (sections ``graph``, ``points``).

The point kinematics shown are checked against finite differences of a naive numeric DH
product (tests/numeric_dh.py): the tool point's velocity is d/dt p(q(t)) and its acceleration
d²/dt² p(q(t)) along q(t) = q + dq t + ddq t²/2; each twist matrix D_j times T_0_n is dT_0_n/dq_j.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from numeric_dh import NumericRobot
from symkin.derive import derive
from symkin.emit.latex import latex_files
from symkin.io import load_robot
from symkin.kernels.document_frames import graph_content, points_content
from symkin.runtime.latex_build import compile_pdf


def _values(model, q, dq, ddq) -> dict:
    values = {s: v for s, v in zip(model.q, q, strict=True)}
    values |= dict(zip(model.dq, dq, strict=True)) | dict(zip(model.ddq, ddq, strict=True))
    given = model.robot.parameter_values()
    values |= {s: given[s.name] for s in model.robot.parameter_symbols}
    return values


@pytest.mark.parametrize("name", ["rpr", "scara", "planar_2r", "cylindrical_rtt_wrist"])
def test_tool_point_motion_against_finite_differences(name: str) -> None:
    robot = load_robot(name)
    model = derive(robot)
    content = points_content(model)
    reference = NumericRobot.from_robot(robot)
    rng = np.random.default_rng(19)
    q, dq, ddq = (rng.uniform(-1, 1, robot.dof) for _ in range(3))
    values = _values(model, q, dq, ddq)

    def position(t: float) -> np.ndarray:
        return reference.frames(q + dq * t + ddq * t**2 / 2)[-1][:3, 3]

    h = 1e-4
    velocity = (position(h) - position(-h)) / (2 * h)
    acceleration = (position(h) - 2 * position(0) + position(-h)) / h**2
    if content.velocity is None:  # a long chain: no closed form shown
        assert robot.dof > 3
        return
    shown_v = np.array(content.velocity.xreplace(values), dtype=float).ravel()
    shown_a = np.array(content.acceleration.xreplace(values), dtype=float).ravel()
    np.testing.assert_allclose(shown_v, velocity, atol=1e-7)
    np.testing.assert_allclose(shown_a, acceleration, atol=1e-5)


def test_twist_matrices_are_derivatives_of_the_pose() -> None:
    robot = load_robot("stanford")
    model = derive(robot)
    twists = points_content(model).twists
    reference = NumericRobot.from_robot(robot)
    q = np.random.default_rng(4).uniform(-1, 1, robot.dof)
    values = _values(model, q, [0] * robot.dof, [0] * robot.dof)
    frame = reference.frames(q)[-1]  # T_0_n
    for j, twist in enumerate(twists):
        step = np.zeros(robot.dof)
        step[j] = 1e-6
        derivative = (reference.frames(q + step)[-1] - reference.frames(q - step)[-1]) / 2e-6
        D = np.array(sp.Matrix(twist).xreplace(values), dtype=float)
        np.testing.assert_allclose(D @ frame, derivative, atol=1e-7)


def test_graph_lists_every_frame_and_transform() -> None:
    model = derive(load_robot("puma560"), closed_forms=False)
    graph = graph_content(model)
    assert graph.frames == tuple(str(i) for i in range(7))  # no base or tool transform
    assert graph.edges == ("joint",) * 6
    document = latex_files(model, sections=("graph",))["puma560.tex"]
    assert r"\xrightarrow{A_{6}(q_{6})}" in document
    assert r"\mathcal{F}_{0}" in document


@pytest.mark.needs_latex
@pytest.mark.slow
@pytest.mark.parametrize("lang", ["en", "de"])
def test_frame_sections_compile(tmp_path, lang: str) -> None:
    model = derive(load_robot("rpr"))
    files = latex_files(model, sections=("dh", "graph", "fk", "points"), lang=lang)
    for path, text in files.items():
        (tmp_path / path).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / path).write_text(text)
    (document,) = [p for p in files if p.endswith(".tex") and "/" not in p and "macros" not in p]
    pdf = compile_pdf(tmp_path / document)
    assert pdf.read_bytes()[:4] == b"%PDF"


def test_graph_with_base_and_tool_breaks_long_chains() -> None:
    from dataclasses import replace

    from symkin.emit.latex.sections_frames import graph_chain

    shift = sp.Matrix([[1, 0, 0, 0.1], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    robot = replace(load_robot("puma560"), base=shift, tool=shift)
    graph = graph_content(derive(robot, closed_forms=False))
    assert graph.frames == ("W", *(str(i) for i in range(7)), "E")
    assert graph.edges == ("base", *("joint",) * 6, "tool")
    chain = graph_chain(graph)
    lines = chain.split(r"\\")
    assert len(lines) == 2  # eight arrows, four a line; the second line starts at frame 3
    assert lines[1].strip().startswith(r"\mathcal{F}_{3} \xrightarrow{A_{4}(q_{4})}")
    assert r"\xrightarrow{T_{\mathrm{base}}} \mathcal{F}_{0}" in lines[0]
