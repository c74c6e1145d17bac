"""The generated NumPy module's batch path: sines and cosines in pairs from one half-angle
tangent (``emit/numpy_trig.py``, ``_sincos``) and large batches evaluated block by block
(``_blocks``), against NumPy's own sin/cos and against the unblocked single-state path."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

import symkin
from codegen_helpers import import_path
from symkin.emit.numpy import emit_numpy, numpy_kernel_layout
from symkin.emit.numpy_trig import pair_trig
from symkin.kernels import Kernel, KernelInput, KernelOutput, dynamics_kernels, kinematics_kernels


def _module(tmp_path, robot: symkin.Robot, kernels: tuple[Kernel, ...]):
    [(name, text)] = emit_numpy(robot, kernels).items()
    path = tmp_path / name.replace("/", "_")
    path.write_text(text)
    return import_path(path.stem, path)


@pytest.fixture(scope="module")
def planar_kernels(model_of):
    model = model_of("planar_3r")
    return model, kinematics_kernels(model) + dynamics_kernels(model)


@pytest.fixture(scope="module")
def planar(planar_kernels, tmp_path_factory):
    model, kernels = planar_kernels
    return model, _module(tmp_path_factory.mktemp("numpy_batch"), model.robot, kernels)


def test_sincos_matches_numpy_sin_and_cos(planar):
    _, module = planar
    rng = np.random.default_rng(3)
    edges = np.pi * np.array([0.0, -0.0, 0.5, -0.5, 1.0, -1.0, 1.5, 2.0, 7.0, -11.0])
    angles = np.concatenate(
        [edges, np.nextafter(edges, 9.0), rng.uniform(-4, 4, 4000), rng.uniform(-1e3, 1e3, 500)]
    )
    angles = np.concatenate([angles, [1e-300, -5e-324, 1e-8]])
    sin, cos = module._sincos(angles)  # more than 32 angles: the half-angle tangent
    assert np.abs(sin - np.sin(angles)).max() < 1e-15 * np.maximum(1.0, np.abs(angles)).max()
    assert np.abs(cos - np.cos(angles)).max() < 1e-15 * np.maximum(1.0, np.abs(angles)).max()
    small = np.abs(angles) < 4
    assert np.abs(sin - np.sin(angles))[small].max() <= 4.5e-16
    assert np.abs(cos - np.cos(angles))[small].max() <= 4.5e-16
    # sin x = x for small normal x, to the last bit (x/2 of a subnormal x may round to 0)
    tiny = (np.abs(angles) < 1e-7) & (np.abs(angles) > 1e-307)
    np.testing.assert_array_equal(sin[tiny], angles[tiny])


def test_sincos_propagates_nan_and_inf(planar):
    _, module = planar
    angles = np.full(40, np.nan)
    angles[::2] = np.inf
    with np.errstate(invalid="ignore"):
        sin, cos = module._sincos(angles)
    assert np.isnan(sin).all() and np.isnan(cos).all()
    for one in (np.float64(np.inf), np.array(-np.inf), np.array(np.nan)):  # the one-angle path
        with np.errstate(invalid="ignore"):
            sin, cos = module._sincos(one)
        assert np.isnan(sin) and np.isnan(cos)
        assert isinstance(sin, np.floating) or np.ndim(sin) == 0


def test_sincos_of_one_angle_and_of_a_few(planar):
    _, module = planar
    angles = np.random.default_rng(9).uniform(-4, 4, 20)
    for x in angles:
        sin, cos = module._sincos(np.array(x))
        assert isinstance(sin, np.float64) and isinstance(cos, np.float64)
        assert abs(sin - np.sin(x)) <= 2.3e-16 and abs(cos - np.cos(x)) <= 2.3e-16
    sin, cos = module._sincos(angles)  # 20 angles: numpy.sin and numpy.cos themselves
    np.testing.assert_array_equal(sin, np.sin(angles))
    np.testing.assert_array_equal(cos, np.cos(angles))
    # An angle of the parameters alone (a twist given as a parameter) is a Python float.
    sin, cos = module._sincos(0.3490658503988659)
    assert abs(sin - math.sin(0.3490658503988659)) <= 2.3e-16
    assert abs(cos - math.cos(0.3490658503988659)) <= 2.3e-16


@pytest.mark.parametrize("block", [33, 40, 1000])
def test_blocked_batch_equals_single_states(planar, block, monkeypatch):
    model, module = planar
    monkeypatch.setattr(module, "BLOCK_ROWS", block)
    rng = np.random.default_rng(block)
    q, dq, ddq = (rng.uniform(-np.pi, np.pi, size=(3, 47, 3)) for _ in range(3))
    reference = symkin.numeric_function(model, model.forward_kinematics)
    poses = module.fk(q)
    masses = module.mass_matrix(q)
    torques = module.inverse_dynamics(q, dq, ddq)
    assert poses.shape == (3, 47, 4, 4) and masses.shape == (3, 47, 3, 3)
    for i in range(3):
        for j in range(47):
            np.testing.assert_allclose(poses[i, j], reference(q[i, j]), rtol=0, atol=1e-14)
            np.testing.assert_allclose(poses[i, j], module.fk(q[i, j]), rtol=0, atol=1e-14)
            np.testing.assert_allclose(masses[i, j], module.mass_matrix(q[i, j]), atol=1e-12)
            single = module.inverse_dynamics(q[i, j], dq[i, j], ddq[i, j])
            np.testing.assert_allclose(torques[i, j], single, rtol=1e-13, atol=1e-12)


def test_every_kernel_blocked_equals_single_states(planar, planar_kernels, monkeypatch):
    """Each kernel (several outputs, vector and scalar outputs, one to three state inputs)
    over 3 x 30 states in blocks of 40 (a remainder block of 10) against one call per state."""
    _, module = planar
    _, kernels = planar_kernels
    monkeypatch.setattr(module, "BLOCK_ROWS", 40)
    rng = np.random.default_rng(11)
    for kernel in kernels:
        states = [
            rng.uniform(-2, 2, size=(3, 30, len(i.symbols))) for i in kernel.inputs if i.name != "p"
        ]
        batch = getattr(module, kernel.name)(*states)
        batch = batch if isinstance(batch, tuple) else (batch,)
        assert len(batch) == len(kernel.outputs)
        for i, j in ((0, 0), (1, 9), (2, 29)):
            single = getattr(module, kernel.name)(*(s[i, j] for s in states))
            single = single if isinstance(single, tuple) else (single,)
            for got, want in zip(batch, single, strict=True):
                np.testing.assert_allclose(got[i, j], want, rtol=1e-13, atol=1e-13)


def test_batched_parameters_and_broadcast_states_still_broadcast(planar, monkeypatch):
    """Parameters per state, or a single dq for a batch of q, take the one-call path."""
    _, module = planar
    monkeypatch.setattr(module, "BLOCK_ROWS", 33)
    rng = np.random.default_rng(5)
    q = rng.uniform(-np.pi, np.pi, size=(100, 3))
    p = module.DEFAULT_PARAMETERS * rng.uniform(
        0.5, 1.5, size=(100, module.DEFAULT_PARAMETERS.size)
    )
    poses = module.fk(q, p)
    for k in (0, 50, 99):
        np.testing.assert_allclose(poses[k], module.fk(q[k], p[k]), rtol=0, atol=1e-14)
    dq = rng.uniform(-1, 1, size=3)
    torques = module.inverse_dynamics(q, dq, np.zeros_like(q))
    for k in (0, 50, 99):
        single = module.inverse_dynamics(q[k], dq, np.zeros(3))
        np.testing.assert_allclose(torques[k], single, rtol=1e-13, atol=1e-12)


def test_large_batch_allocates_about_the_output(planar, monkeypatch):
    """tracemalloc counts NumPy's buffers: a batch of 50 blocks may use its output plus
    block-sized arrays (a tenth of the output here), not full-size intermediates (each of
    which would be 1/16 of the output; the one-call path holds several at a time)."""
    import tracemalloc

    _, module = planar
    monkeypatch.setattr(module, "BLOCK_ROWS", 1000)
    q = np.random.default_rng(1).uniform(-np.pi, np.pi, size=(50_000, 3))
    module.fk(q[:10])
    tracemalloc.start()
    poses = module.fk(q)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert poses.nbytes <= peak < 1.1 * poses.nbytes


def _toy_kernel() -> Kernel:
    x, y, a = sp.symbols("x y a", real=True)
    t0, t1 = sp.symbols("t0 t1", real=True)
    inputs = (KernelInput("q", (x, y), "angles"), KernelInput("p", (a,), "length"))
    assignments = ((t0, sp.cos(x)), (t1, a * sp.sin(x) + sp.sin(sp.sin(y))))
    matrix = sp.ImmutableMatrix([[t0 + t1, sp.cos(x + y)], [sp.sin(y) * t1, sp.cos(2)]])
    return Kernel("toy", "a toy", inputs, (KernelOutput("T", matrix, "out"),), assignments)


def test_pair_trig_keeps_the_values_and_pairs_each_angle():
    kernel = _toy_kernel()
    rewritten, pairs = pair_trig(kernel)
    assert {p.angle for p in pairs.values()} == {
        sp.Symbol("x", real=True),
        sp.Symbol("y", real=True),
        sp.Symbol("x", real=True) + sp.Symbol("y", real=True),
    }
    for index, pair in pairs.items():
        assert rewritten.assignments[index] == (pair.sin, sp.sin(pair.angle))
        assert rewritten.assignments[index + 1] == (pair.cos, sp.cos(pair.angle))
    x = next(p for p in pairs.values() if p.angle == sp.Symbol("x", real=True))
    assert x.cos == sp.Symbol("t0", real=True)  # the intermediate that was cos(x) keeps its name

    def evaluate(k: Kernel, values: dict) -> sp.Matrix:
        scope = dict(values)
        for symbol, expr in k.assignments:
            scope[symbol] = expr.xreplace(scope)
        return k.outputs[0].matrix.xreplace(scope).evalf()

    values = {
        s: sp.Float(v)
        for s, v in zip(sp.symbols("x y a", real=True), (0.3, -1.2, 0.7), strict=True)
    }
    assert (evaluate(kernel, values) - evaluate(rewritten, values)).norm() < 1e-14
    layout = numpy_kernel_layout(kernel)
    assert sum("_sincos(" in code for _, code in layout.assignments) == 3
    assert layout.counts == kernel.operation_counts
    # sin(sin(y)) keeps NumPy's sin (its angle holds a sine); cos(2) holds no symbol
    assert any("numpy.sin(" in code for _, code in layout.assignments)
    assert "numpy.cos(2)" in "".join(e.code for e in layout.outputs[0].entries)
