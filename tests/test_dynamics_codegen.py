"""Generated dynamics code (NumPy, C through ctypes, CasADi) against the symbolic model.

For each robot the files are generated and compiled once (module fixture).  The reference is
the symbolic Newton–Euler model evaluated by ``sympy.lambdify`` with its named intermediates
evaluated in order; inverse dynamics is also checked against ``M ddq + c + G`` (+ friction).
"""

from __future__ import annotations

import ctypes
import subprocess
import warnings
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest
import sympy as sp

import symkin
from codegen_helpers import (
    CC,
    CONVERSION,
    SANITIZE,
    SHARED,
    STRICT,
    import_path,
    run_parallel,
    write_tree,
)
from symkin.derive.dynamics import Dynamics
from symkin.errors import RobotWarning
from symkin.generate import files_for_robot
from symkin.kernels import Kernel, dynamics_kernels, inertial_symbols

pytestmark = pytest.mark.needs_cc

NAMES = ("planar_2r", "rpr", "puma560", "panda")
STATES = 6
TOLERANCE = 1e-11
KERNELS = ("mass_matrix", "gravity", "coriolis", "coriolis_matrix", "inverse_dynamics")


def load(name: str) -> symkin.Robot:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RobotWarning)
        return symkin.load_robot(name)


def physical_inertials(model: symkin.Model, seed: int) -> np.ndarray:
    """Values for ``pi`` (m, cx, cy, cz, ixx, iyy, izz, ixy, ixz, iyz per link)."""
    rng = np.random.default_rng(seed)
    values = []
    for _ in range(len(inertial_symbols(model)) // 10):
        second = rng.uniform(0.01, 0.2, 3)
        principal = [second[1] + second[2], second[0] + second[2], second[0] + second[1]]
        rotation, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        t = rotation @ np.diag(principal) @ rotation.T
        values += [rng.uniform(0.5, 5.0), *rng.uniform(-0.2, 0.2, 3)]
        values += [t[0, 0], t[1, 1], t[2, 2], t[0, 1], t[0, 2], t[1, 2]]
    return np.array(values, dtype=float)


@dataclass
class Generated:
    name: str
    robot: symkin.Robot
    model: symkin.Model
    kernels: dict[str, Kernel]
    root: Path
    numpy: ModuleType
    casadi: ModuleType
    lib: ctypes.CDLL
    p: np.ndarray
    pi: np.ndarray | None
    reference: dict[str, object]


def reference_functions(model: symkin.Model, values: dict) -> dict[str, object]:
    ne: Dynamics = model.newton_euler
    assignments = [(s, e.xreplace(values)) for s, e in ne.assignments]
    outputs = {
        "mass_matrix": ne.mass_matrix,
        "gravity": ne.gravity_vector,
        "coriolis": ne.coriolis_vector,
        "coriolis_matrix": ne.coriolis_matrix,
        "friction": ne.friction,
    }
    args = [model.q, model.dq, model.ddq]
    return {
        key: sp.lambdify(
            args, sp.Matrix(m).xreplace(values), "numpy", cse=lambda e: (assignments, e)
        )
        for key, m in outputs.items()
    }


@pytest.fixture(scope="module", params=NAMES)
def gen(request, tmp_path_factory) -> Generated:
    name = request.param
    robot = load(name)
    model = symkin.derive(robot)
    root = tmp_path_factory.mktemp(f"dyn_{name}")
    write_tree(root, files_for_robot(robot, ("numpy", "c", "casadi")))
    builds = run_parallel(
        {"so": [CC, *STRICT, *CONVERSION, *SHARED, "-o", "libdyn.so", f"c/{name}.c", "-lm"]},
        cwd=root,
    )
    builds["so"].check()
    p = np.array([v for _, v in robot.parameters], dtype=float)
    symbols = inertial_symbols(model)
    pi = physical_inertials(model, seed=NAMES.index(name)) if symbols else None
    values = {s: robot.parameter_values()[s.name] for s in robot.parameter_symbols}
    if pi is not None:
        values |= dict(zip(symbols, pi.tolist(), strict=True))
    return Generated(
        name,
        robot,
        model,
        {k.name: k for k in dynamics_kernels(model)},
        root,
        import_path(f"dyn_{name}_numpy", root / "numpy" / f"{name}_kinematics.py"),
        import_path(f"dyn_{name}_casadi", root / "casadi" / f"{name}_casadi.py"),
        ctypes.CDLL(str(root / "libdyn.so")),
        p,
        pi,
        reference_functions(model, values),
    )


def states(gen: Generated, seed: int):
    rng = np.random.default_rng(seed)
    shape = (STATES, gen.robot.dof)
    return rng.uniform(-3, 3, shape), rng.uniform(-2, 2, shape), rng.uniform(-4, 4, shape)


def rates_of(kernel: Kernel) -> list[str]:
    return [i.name for i in kernel.inputs if i.name in ("dq", "ddq")]


def call_numpy(gen: Generated, name: str, q, dq, ddq) -> np.ndarray:
    kernel = gen.kernels[name]
    rates = {"dq": dq, "ddq": ddq}
    args = [q, *(rates[r] for r in rates_of(kernel)), gen.p]
    return getattr(gen.numpy, name)(*args, **({"pi": gen.pi} if gen.pi is not None else {}))


def call_c(gen: Generated, name: str, q, dq, ddq) -> np.ndarray:
    kernel = gen.kernels[name]
    (output,) = kernel.outputs
    rates = {"dq": dq, "ddq": ddq}
    arrays = [q, *(rates[r] for r in rates_of(kernel)), gen.p]
    if gen.pi is not None:
        arrays.append(gen.pi)
    arrays = [np.ascontiguousarray(a, dtype=float) for a in arrays]
    out = np.full(output.size + 4, np.nan)
    function = getattr(gen.lib, f"{gen.name}_{name}")
    function.restype = None
    function.argtypes = [ctypes.c_void_p] * (len(arrays) + 1)
    function(*[a.ctypes.data_as(ctypes.c_void_p) for a in arrays], out.ctypes.data)
    assert np.all(np.isnan(out[output.size :])), f"{name} wrote past its output"
    rows, cols = output.shape
    return out[: output.size].reshape((rows, cols) if cols > 1 else (rows,))


def call_casadi(gen: Generated, name: str, q, dq, ddq) -> np.ndarray:
    kernel = gen.kernels[name]
    function = getattr(gen.casadi, f"{name}_function")()
    rates = {"dq": dq, "ddq": ddq}
    args = [q, *(rates[r] for r in rates_of(kernel)), gen.p]
    if gen.pi is not None:
        args.append(gen.pi)
    result = np.array(function(*args).full())
    rows, cols = kernel.outputs[0].shape
    return result.reshape((rows, cols) if cols > 1 else (rows,))


def reference(gen: Generated, name: str, q, dq, ddq) -> np.ndarray:
    if name == "inverse_dynamics":
        m = reference(gen, "mass_matrix", q, dq, ddq)
        rest = sum(reference(gen, k, q, dq, ddq) for k in ("coriolis", "gravity", "friction"))
        return m @ ddq + rest
    result = np.array(gen.reference[name](q, dq, ddq), dtype=float)
    return result if result.shape[1] > 1 else result.ravel()


def close(actual, expected, what: str) -> None:
    actual, expected = np.asarray(actual, float), np.asarray(expected, float)
    assert actual.shape == expected.shape, f"{what}: {actual.shape} != {expected.shape}"
    scale = max(1.0, float(np.max(np.abs(expected))))
    error = float(np.max(np.abs(actual - expected)))
    assert error <= TOLERANCE * scale, f"{what}: error {error:.3g} (scale {scale:.3g})"


def test_dynamics_kernels_are_generated(gen):
    assert set(KERNELS) <= set(gen.kernels)
    for name in KERNELS:
        assert hasattr(gen.numpy, name) and hasattr(gen.casadi, f"{name}_function")
        assert hasattr(gen.lib, f"{gen.name}_{name}")


@pytest.mark.parametrize("kernel", KERNELS)
def test_numpy_c_casadi_and_symbolic_agree(gen, kernel):
    q, dq, ddq = states(gen, seed=40)
    for state in zip(q, dq, ddq, strict=True):
        expected = reference(gen, kernel, *state)
        close(call_numpy(gen, kernel, *state), expected, f"{gen.name} numpy {kernel}")
        close(call_c(gen, kernel, *state), expected, f"{gen.name} C {kernel}")
        close(call_casadi(gen, kernel, *state), expected, f"{gen.name} casadi {kernel}")


def test_numpy_batch_equals_single_states(gen):
    q, dq, ddq = states(gen, seed=41)
    batch = call_numpy(gen, "inverse_dynamics", q, dq, ddq)
    assert batch.shape == (STATES, gen.robot.dof)
    for k, state in enumerate(zip(q, dq, ddq, strict=True)):
        close(batch[k], call_numpy(gen, "inverse_dynamics", *state), "batch")
    masses = call_numpy(gen, "mass_matrix", q, dq, ddq)
    assert masses.shape == (STATES, gen.robot.dof, gen.robot.dof)


def test_generated_inverse_dynamics_is_m_ddq_plus_c_plus_g(gen):
    q, dq, ddq = states(gen, seed=42)
    for state in zip(q, dq, ddq, strict=True):
        m = call_c(gen, "mass_matrix", *state)
        c = call_c(gen, "coriolis", *state)
        g = call_c(gen, "gravity", *state)
        cm = call_c(gen, "coriolis_matrix", *state)
        close(cm @ state[1], c, "C dq vs c")
        friction = np.array(gen.reference["friction"](*state), dtype=float).ravel()
        close(call_c(gen, "inverse_dynamics", *state), m @ state[2] + c + g + friction, "tau")


def test_dynamics_under_sanitizers(gen, tmp_path):
    n, name = gen.robot.dof, gen.name
    q, dq, ddq = states(gen, seed=43)

    def array(values) -> str:
        return ", ".join(repr(float(v)) for v in np.ravel(values))

    # PUMA 560's file has every link's data (no pi argument); the others are symbolic and get
    # random physical values through pi.
    pi_arg = ", pi" if gen.pi is not None else ""
    pi_line = [] if gen.pi is None else [f"    static const double pi[] = {{ {array(gen.pi)} }};"]

    lines = [
        "#include <stdio.h>",
        "#include <stdlib.h>",
        f'#include "{name}.h"',
        "int main(void) {",
        f"    static const double q[{n}] = {{ {array(q[0])} }};",
        f"    static const double dq[{n}] = {{ {array(dq[0])} }};",
        f"    static const double ddq[{n}] = {{ {array(ddq[0])} }};",
        f"    static const double p[{len(gen.p)}] = {{ {array(gen.p)} }};",
        *pi_line,
        f"    double *M = malloc(sizeof(double) * {n * n});",
        f"    double *C = malloc(sizeof(double) * {n * n});",
        f"    double *v = malloc(sizeof(double) * {n});",
        "    int i;",
        f"    {name}_mass_matrix(q, p{pi_arg}, M);",
        f"    {name}_coriolis_matrix(q, dq, p{pi_arg}, C);",
        f"    {name}_gravity(q, p{pi_arg}, v);",
        f"    {name}_coriolis(q, dq, p{pi_arg}, v);",
        f"    {name}_inverse_dynamics(q, dq, ddq, p{pi_arg}, v);",
        f'    for (i = 0; i < {n}; ++i) printf("%.17g\\n", v[i]);',
        "    free(M); free(C); free(v);",
        "    return 0;",
        "}",
    ]
    driver = tmp_path / "driver.c"
    driver.write_text("\n".join(lines) + "\n")
    source = gen.root / "c" / f"{name}.c"
    exe = tmp_path / "driver"
    command = [CC, *STRICT, *SANITIZE, f"-I{gen.root / 'c'}", "-o", str(exe), str(driver)]
    build = subprocess.run([*command, str(source), "-lm"], capture_output=True, text=True)
    assert build.returncode == 0, build.stdout + build.stderr
    result = subprocess.run([str(exe)], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    values = np.array([float(x) for x in result.stdout.split()])
    close(values, reference(gen, "inverse_dynamics", q[0], dq[0], ddq[0]), "sanitized tau")


def test_mass_matrix_bias_is_m_and_the_torques_at_rest(gen):
    """``mass_matrix_bias`` (from the torque recursion at ddq = 0) against M and c + G + F of
    the separate mass-matrix, Coriolis and gravity recursions, in NumPy, C and CasADi."""
    n = gen.robot.dof
    q, dq, ddq = states(gen, seed=44)
    extra = [gen.pi] if gen.pi is not None else []
    function = gen.lib[f"{gen.name}_mass_matrix_bias"]
    function.restype = None
    function.argtypes = [ctypes.c_void_p] * (5 + len(extra))
    casadi_function = gen.casadi.mass_matrix_bias_function()
    for state in zip(q, dq, ddq, strict=True):
        m = reference(gen, "mass_matrix", *state)
        bias = sum(reference(gen, k, *state) for k in ("coriolis", "gravity", "friction"))
        numpy_m, numpy_bias = gen.numpy.mass_matrix_bias(state[0], state[1], gen.p, *extra)
        close(numpy_m, m, f"{gen.name} numpy M")
        close(numpy_bias, bias, f"{gen.name} numpy bias")
        arrays = [np.ascontiguousarray(a, dtype=float) for a in (*state[:2], gen.p, *extra)]
        out_m, out_bias = np.full(n * n + 4, np.nan), np.full(n + 4, np.nan)
        function(*(a.ctypes.data for a in arrays), out_m.ctypes.data, out_bias.ctypes.data)
        assert np.all(np.isnan(out_m[n * n :])) and np.all(np.isnan(out_bias[n:]))
        close(out_m[: n * n].reshape(n, n), m, f"{gen.name} C M")
        close(out_bias[:n], bias, f"{gen.name} C bias")
        casadi_m, casadi_bias = casadi_function(state[0], state[1], gen.p, *extra)
        close(np.array(casadi_m.full()), m, f"{gen.name} casadi M")
        close(np.array(casadi_bias.full()).ravel(), bias, f"{gen.name} casadi bias")
