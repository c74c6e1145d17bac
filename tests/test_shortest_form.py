"""The cheap test that lets the kinematics kernels skip a form that cannot be shortest.

Expected values: operation counts of ``sympy.cse`` output (another computation than the
bound), and the form chosen with every form built.
"""

from __future__ import annotations

import pytest
import sympy as sp

import symkin
from symkin.kernels import catalogue
from symkin.kernels.spec import KernelInput, kernel_from_outputs

q1, q2, q3 = sp.symbols("q1 q2 q3", real=True)
INPUTS = (KernelInput("q", (q1, q2, q3), "joint positions"),)


def test_products_bound_never_exceeds_the_cse_count():
    c1, s1, c2, s2, c3 = sp.cos(q1), sp.sin(q1), sp.cos(q2), sp.sin(q2), sp.cos(q3)
    matrices = [
        sp.Matrix([0.3 * c1 * c2 - 0.2 * s1 * s2 + c3, c1 * c2 * c3 + s1]),
        sp.expand(sp.Matrix([(c1 + s2 + 0.5 * c3) ** 3, (c1 * s1 - c2) ** 2 * c3])),
        sp.Matrix([(c1 + s1) * (c2 + s2) * (c3 + 1), c1]),
    ]
    for matrix in matrices:
        outputs = [("y", matrix, "test")]
        count = kernel_from_outputs("k", "test", INPUTS, outputs).operation_counts["total"]
        assert 0 < catalogue._products_lower_bound(outputs) <= count


# Derives the UR5's kinematics twice (about 10 s).
@pytest.mark.slow
def test_skipping_forms_picks_the_kernel_that_building_all_would(monkeypatch):
    model = symkin.derive(symkin.load_robot("ur5"))
    kernels = catalogue.kinematics_kernels(model)
    monkeypatch.setattr(catalogue, "_products_lower_bound", lambda outputs: 0)
    every_form = catalogue.kinematics_kernels(model)
    assert [k.name for k in kernels] == [k.name for k in every_form]
    for chosen, expected in zip(kernels, every_form, strict=True):
        assert chosen.operation_counts == expected.operation_counts
        assert chosen.assignments == expected.assignments
