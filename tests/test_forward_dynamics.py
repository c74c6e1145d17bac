"""Generated forward dynamics (NumPy, C, CasADi) inverts the generated inverse dynamics.

tau = ID(q, dq, ddq) computed by the Newton–Euler kernel is a product; forward dynamics solves
M ddq = tau - ID(q, dq, 0) by Cholesky (C), numpy.linalg.solve (NumPy) and casadi.solve:
recovering ddq is a check that the solve, the mass matrix and the bias agree.
"""

from __future__ import annotations

import importlib.util
import subprocess

import numpy as np
import pytest

import symkin
from symkin.generate import files_for_robot
from symkin.kernels import inertial_symbols
from symkin.output_folder import write_folder

pytestmark = pytest.mark.needs_cc

ROBOTS = ("planar_2r", "rpr", "puma560", "panda")
STRICT = ["-std=c99", "-O1", "-Wall", "-Wextra", "-Werror", "-pedantic"]
SANITIZE = ["-fsanitize=address,undefined", "-fno-sanitize-recover=all"]


def _module(path):
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _inertial_values(model, rng):
    """Physical random data for links without it: positive masses, PSD inertias."""
    values = []
    for _ in range(len(inertial_symbols(model)) // 10):
        principal = rng.uniform(0.01, 0.1, 3)
        values += [rng.uniform(0.5, 2.0), *rng.uniform(-0.1, 0.1, 3), *principal, 0, 0, 0]
    return np.array(values)


@pytest.fixture(scope="module", params=ROBOTS)
def generated(request, tmp_path_factory):
    robot = symkin.load_robot(request.param)
    root = tmp_path_factory.mktemp(robot.name)
    write_folder(root, files_for_robot(robot, ("numpy", "c", "casadi")))
    return robot, root


def test_forward_dynamics_recovers_the_accelerations(generated):
    robot, root = generated
    model = symkin.derive(robot)
    numpy_module = _module(root / "numpy" / f"{robot.name}_kinematics.py")
    casadi_module = _module(root / "casadi" / f"{robot.name}_casadi.py")
    rng = np.random.default_rng(11)
    pi = _inertial_values(model, rng)
    extra = {"pi": pi} if pi.size else {}
    q, dq, ddq = rng.uniform(-1, 1, size=(3, 8, robot.dof))
    tau = numpy_module.inverse_dynamics(q, dq, ddq, **extra)
    np.testing.assert_allclose(numpy_module.forward_dynamics(q, dq, tau, **extra), ddq, atol=1e-9)
    forward = casadi_module.forward_dynamics_function()
    p = numpy_module.DEFAULT_PARAMETERS
    for k in range(3):
        args = [q[k], dq[k], tau[k], p] + ([pi] if pi.size else [])
        np.testing.assert_allclose(np.array(forward(*args)).ravel(), ddq[k], atol=1e-9)


def test_c_forward_dynamics_under_sanitizers(generated, tmp_path):
    robot, root = generated
    model = symkin.derive(robot)
    numpy_module = _module(root / "numpy" / f"{robot.name}_kinematics.py")
    rng = np.random.default_rng(5)
    pi = _inertial_values(model, rng)
    extra = {"pi": pi} if pi.size else {}
    q, dq, ddq = rng.uniform(-1, 1, size=(3, robot.dof))
    tau = numpy_module.inverse_dynamics(q, dq, ddq, **extra)

    # A sanitized library cannot be loaded into an uninstrumented Python, so a small C
    # driver runs the generated code under the sanitizers and prints ddq.
    def array(values):
        return ", ".join(repr(float(v)) for v in np.atleast_1d(values)) or "0"

    pi_arg = ", pi" if pi.size else ""
    driver = tmp_path / "driver.c"
    p = numpy_module.DEFAULT_PARAMETERS
    driver.write_text(
        f'#include <stdio.h>\n#include "{root / "c" / (robot.name + ".h")}"\n'
        "int main(void) {\n"
        f"    const double q[] = {{{array(q)}}}, dq[] = {{{array(dq)}}};\n"
        f"    const double tau[] = {{{array(tau)}}};\n"
        f"    const double p[] = {{{array(p)}}}, pi[] = {{{array(pi)}}};\n"
        f"    double ddq[{robot.dof}];\n    int i;\n    (void)pi;\n"
        f"    {robot.name}_forward_dynamics(q, dq, tau, p{pi_arg}, ddq);\n"
        f'    for (i = 0; i < {robot.dof}; ++i) printf("%.17g\\n", ddq[i]);\n'
        "    return 0;\n}\n"
    )
    program = tmp_path / "driver"
    sources = [str(driver), str(root / "c" / f"{robot.name}.c")]
    command = ["gcc", *STRICT, *SANITIZE, *sources, "-o", str(program), "-lm"]
    subprocess.run(command, check=True)
    result = subprocess.run([str(program)], capture_output=True, text=True, check=True)
    values = np.array([float(v) for v in result.stdout.split()])
    np.testing.assert_allclose(values, ddq, atol=1e-9)
