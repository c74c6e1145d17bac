"""The CPython extension built by `symkin derive`: same numbers as the generated NumPy module.

The NumPy module is itself compared with the reference evaluator (test_codegen.py), so
agreement here closes the chain C kernel -> binding -> Python.
"""

from __future__ import annotations

import importlib.util
import shutil
import subprocess
import sysconfig
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import symkin
from numeric_dh import without_inertials
from symkin.cli import main
from symkin.emit.python_ext import bindings
from symkin.errors import SymkinError
from symkin.kernels.passes import kernel_from_assignments
from symkin.kernels.spec import KernelInput
from symkin.runtime.extension import load_extension

pytestmark = pytest.mark.needs_cc

ROBOTS = ("planar_2r", "scara", "puma560", "panda", "stanford")


def _import_file(path: Path):
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module", params=ROBOTS)
def built(request, tmp_path_factory):
    name = request.param
    out = tmp_path_factory.mktemp(name)
    assert main(["derive", name, "--out", str(out), "--emit", "numpy,python"]) == 0
    extension = load_extension(next((out / "python").glob(f"{name}_ext*.so")))
    reference = _import_file(out / "numpy" / f"{name}_kinematics.py")
    return symkin.load_robot(name), extension, reference


KERNELS = ("fk", "position", "jacobian", "position_jacobian", "fk_jacobian")


def _random_states(robot, count, seed):
    return np.random.default_rng(seed).uniform(-1.5, 1.5, size=(count, robot.dof))


def _as_tuple(value):
    return value if isinstance(value, tuple) else (value,)


@pytest.mark.parametrize("kernel", KERNELS)
def test_single_and_batched_calls_match_numpy(built, kernel):
    robot, extension, reference = built
    states = _random_states(robot, 25, seed=3)
    batch = _as_tuple(getattr(extension, kernel)(states))
    expected_batch = _as_tuple(getattr(reference, kernel)(states))
    for got, want in zip(batch, expected_batch, strict=True):
        assert got.shape == want.shape
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)
    for q in states[:5]:
        for got, want in zip(
            _as_tuple(getattr(extension, kernel)(q)),
            _as_tuple(getattr(reference, kernel)(q)),
            strict=True,
        ):
            assert got.shape == want.shape
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)


def test_parameters_can_be_overridden(built):
    robot, extension, reference = built
    assert robot.parameters, "ROBOTS are chosen to have parameters"
    q = _random_states(robot, 1, seed=5)[0]
    p = np.asarray(reference.DEFAULT_PARAMETERS) * 1.7
    np.testing.assert_allclose(extension.fk(q, p), reference.fk(q, p), rtol=0, atol=1e-12)
    assert not np.allclose(extension.fk(q, p), extension.fk(q))


def test_determinant_matches_when_square(built):
    robot, extension, reference = built
    if not hasattr(reference, "det"):
        assert not hasattr(extension, "det")
        return
    states = _random_states(robot, 10, seed=9)
    np.testing.assert_allclose(extension.det(states), reference.det(states), rtol=1e-12, atol=1e-15)


def test_bad_shapes_raise_python_errors(built):
    robot, extension, _ = built
    n, shape = robot.dof, rf"numbers of shape \({robot.dof},\) or \(N, {robot.dof}\)"
    with pytest.raises(ValueError, match=rf"^fk\(q, p=None\): every state input must be {shape}"):
        extension.fk(np.zeros(n + 1))
    with pytest.raises(ValueError, match=rf"{shape}, the same for all .*\(got 3 dimensions\)"):
        extension.fk(np.zeros((2, 3, n)))
    with pytest.raises(ValueError, match=r"got 0 dimensions"):
        extension.fk(1.0)
    with pytest.raises(ValueError, match=shape):
        extension.fk(["a"] * n)
    count = len(robot.parameters)
    with pytest.raises(ValueError, match=rf"p must hold {count} numbers \(got {count + 2}\)"):
        extension.fk(np.zeros(n), np.zeros(count + 2))
    with pytest.raises(ValueError, match=rf"p must hold {count} numbers \(got 2 dimensions\)"):
        extension.fk(np.zeros(n), np.zeros((1, count)))
    with pytest.raises(TypeError):
        extension.fk()


def test_point_kernels_with_three_outputs(tmp_path):
    # Position, velocity and acceleration of a point: three outputs, in a batch large enough
    # that an output written past its array would corrupt memory.
    point = np.array([0.1, 0.05, 0.0])
    assert main(["derive", "planar_2r", "--out", str(tmp_path), "--emit", "numpy,python",
                 "--point", "2:0.1,0.05,0"]) == 0  # fmt: skip
    extension = load_extension(next((tmp_path / "python").glob("planar_2r_ext*.so")))
    reference = _import_file(tmp_path / "numpy" / "planar_2r_kinematics.py")
    q, dq, ddq = np.random.default_rng(12).uniform(-2, 2, size=(3, 1000, 2))
    got = extension.point1(q, dq, ddq)
    assert len(got) == 3
    for value, want in zip(got, reference.point1(q, dq, ddq), strict=True):
        np.testing.assert_allclose(value, want, rtol=0, atol=1e-12)
    # Independently of the point kernel: the position is T applied to the point.
    expected = extension.fk(q)[:, :3, :3] @ point + extension.fk(q)[:, :3, 3]
    np.testing.assert_allclose(got[0], expected, atol=1e-12)


@pytest.mark.parametrize(("robot", "extra"), [("panda", []), ("planar_2r", ["--point", "2:1,0,0"])])
def test_extension_source_compiles_without_warnings(tmp_path, robot, extra):
    assert (
        main(["derive", robot, "--out", str(tmp_path), "--emit", "python", "--no-build", *extra])
        == 0
    )
    command = [
        shutil.which("cc") or "gcc", "-O2", "-Wall", "-Wextra", "-Wshadow", "-Werror",
        "-shared", "-fPIC", f"-I{sysconfig.get_paths()['include']}", f"-I{np.get_include()}",
        str(tmp_path / "python" / f"{robot}_ext.c"), str(tmp_path / "c" / f"{robot}.c"),
        "-o", str(tmp_path / "strict.so"), "-lm",
    ]  # fmt: skip
    done = subprocess.run(command, capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr


def test_robot_without_parameters_and_repeated_arguments(tmp_path):
    # --numeric-parameters leaves no parameters: p defaults to an empty vector.
    # The catalogue file without its inertial data: pi stays an input.
    bare = tmp_path / "planar_2r.toml"
    bare.write_text(without_inertials("planar_2r"), encoding="utf-8")
    assert main(["derive", str(bare), "--out", str(tmp_path), "--emit", "numpy,python",
                 "--numeric-parameters"]) == 0  # fmt: skip
    extension = load_extension(next((tmp_path / "python").glob("planar_2r_ext*.so")))
    reference = _import_file(tmp_path / "numpy" / "planar_2r_kinematics.py")
    q = np.array([0.3, -0.8])
    np.testing.assert_allclose(extension.fk(q), reference.fk(q), rtol=0, atol=1e-12)
    np.testing.assert_array_equal(extension.fk(q, []), extension.fk(q))
    with pytest.raises(ValueError, match=r"p must hold 0 numbers"):
        extension.fk(q, [1.0])
    pi = np.tile([1.0, 0.1, 0.0, 0.0, 0.01, 0.02, 0.02, 0.0, 0.0, 0.0], 2)
    # Zero masses and inertias make M(q) singular: an error, not NaN (the C code's answer).
    singular = r"ddq is not finite: M\(q\) is not positive definite.*\(state 0\)"
    with pytest.raises(ValueError, match=singular):
        extension.forward_dynamics(np.stack([q, q]), np.zeros((2, 2)), np.ones((2, 2)), pi=0 * pi)
    with pytest.raises(TypeError, match=r"got multiple values for argument 'pi'"):
        extension.gravity(q, None, pi, pi=pi)
    with pytest.raises(TypeError, match=r"got multiple values for argument 'p'"):
        extension.fk(q, [], p=[])
    with pytest.raises(TypeError, match=r"state inputs by position"):
        extension.fk(q=q)


@pytest.mark.slow
def test_float_precision_extension(tmp_path):
    assert main(["derive", "puma560", "--out", str(tmp_path), "--precision", "float"]) == 0
    extension = load_extension(next((tmp_path / "python").glob("puma560_ext*.so")))
    reference = _import_file(tmp_path / "numpy" / "puma560_kinematics.py")
    states = np.random.default_rng(1).uniform(-2, 2, size=(50, 6))
    transforms = extension.fk(states)
    assert transforms.dtype == np.float32
    np.testing.assert_allclose(transforms, reference.fk(states), rtol=0, atol=5e-6)


# Dynamics functions, their state inputs (forward dynamics takes tau in place of ddq).
DYNAMICS = {
    "mass_matrix": ("q",),
    "gravity": ("q",),
    "coriolis": ("q", "dq"),
    "coriolis_matrix": ("q", "dq"),
    "inverse_dynamics": ("q", "dq", "ddq"),
    "forward_dynamics": ("q", "dq", "tau"),
}


def _inertial_values(robot, seed):
    """Physical values (positive mass, principal moments that satisfy the triangle
    inequality) for the 10 symbols of every link the robot file leaves without data."""
    rng = np.random.default_rng(seed)
    values = []
    for joint in robot.joints:
        if joint.link is None:
            values += [rng.uniform(1, 3), *rng.uniform(-0.1, 0.1, 3)]
            values += [*rng.uniform(0.05, 0.09, 3), 0.0, 0.0, 0.0]
    return {"pi": np.array(values)} if values else {}


@pytest.mark.parametrize("kernel", DYNAMICS)
def test_dynamics_match_numpy(built, kernel):
    robot, extension, reference = built
    extra = _inertial_values(robot, seed=4)
    rng = np.random.default_rng(6)
    batch = [rng.uniform(-1.5, 1.5, size=(12, robot.dof)) for _ in DYNAMICS[kernel]]
    for arguments in (batch, [b[0] for b in batch]):
        got = getattr(extension, kernel)(*arguments, **extra)
        want = getattr(reference, kernel)(*arguments, **extra)
        assert got.shape == want.shape
        np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-10)


def test_forward_dynamics_recovers_the_accelerations(built):
    # An identity between two functions, not a comparison with the NumPy module.
    robot, extension, _ = built
    extra = _inertial_values(robot, seed=8)
    q, dq, ddq = np.random.default_rng(7).uniform(-1.5, 1.5, size=(3, 20, robot.dof))
    tau = extension.inverse_dynamics(q, dq, ddq, **extra)
    np.testing.assert_allclose(extension.forward_dynamics(q, dq, tau, **extra), ddq, atol=1e-8)


def test_inertial_parameters_positional_or_by_keyword(built):
    robot, extension, _ = built
    extra = _inertial_values(robot, seed=10)
    q, dq, ddq = np.random.default_rng(11).uniform(-1, 1, size=(3, robot.dof))
    by_keyword = extension.inverse_dynamics(q, dq, ddq, **extra)
    positional = extension.inverse_dynamics(q, dq, ddq, None, *extra.values())
    np.testing.assert_array_equal(by_keyword, positional)
    if not extra:
        with pytest.raises(TypeError, match=r"expected inverse_dynamics\(q, dq, ddq, p=None\)"):
            extension.inverse_dynamics(q, dq, ddq, pi=np.zeros(10))
        return
    count = len(extra["pi"])
    with pytest.raises(ValueError, match=rf"give the {count} inertial parameters"):
        extension.inverse_dynamics(q, dq, ddq)
    with pytest.raises(ValueError, match=rf"pi must hold {count} numbers"):
        extension.mass_matrix(q, pi=extra["pi"][:-1])
    with pytest.raises(TypeError, match=r"expected fk\(q, p=None\)"):
        extension.fk(q, pi=extra["pi"])
    with pytest.raises(ValueError, match=r"the same for all"):
        extension.coriolis(q, np.zeros((2, robot.dof)), **extra)


def test_a_kernel_with_two_vectors_besides_p_is_refused():
    """The binding's signature is ``(states..., p=None, <vector>=None)``: a second vector would
    be left unbound, so it is an error, not a silently unfilled input."""
    q, a, b, c = sp.symbols("q1 a b c", real=True)
    inputs = [
        KernelInput("q", (q,), "joint positions"),
        KernelInput("p", (a,), "parameters"),
        KernelInput("pi", (b,), "inertial parameters"),
        KernelInput("delta", (c,), "barycentric parameters"),
    ]
    kernel = kernel_from_assignments(
        "odd", "two vectors", inputs, [], [("y", sp.Matrix([q * a * b * c]), "y")]
    )
    with pytest.raises(SymkinError, match="odd takes 2 vectors besides p"):
        bindings(symkin.load_robot("planar_2r"), (kernel,))
