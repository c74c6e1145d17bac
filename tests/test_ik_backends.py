"""``solve_ik`` on its backends (solve/ik/backends.py, runtime/compiled_ik.py): the generated C
solver through the CPython extension, its NumPy twin, and the fallback without a compiler.

Every answer is judged by the independent forward kinematics of ``numeric_dh`` (elementary
rotations and translations multiplied in NumPy, written apart from symkin), never by the
solver's own report.
"""

from __future__ import annotations

import functools
import math
import os

import numpy as np
import pytest

from numeric_dh import overrides, reference, robot, vee
from symkin.errors import ParameterError, SymkinError
from symkin.runtime import compiled_ik, modules
from symkin.solve.ik.numeric import solve_ik

pytestmark = pytest.mark.filterwarnings("ignore::symkin.errors.RobotWarning")

TOL = 1e-10
CHECK = 1e-9  # what the independent FK must confirm (its rounding differs from symkin's)


def independent_errors(name: str, q: np.ndarray, target: np.ndarray) -> tuple[float, float]:
    """Position error (m) and rotation angle (rad) of ``q`` against ``target``, computed from
    the independent FK: the angle of ``R_t^T R`` as atan2(|vee|, (tr - 1) / 2)."""
    T = reference(name).fk(np.asarray(q, dtype=float))
    relative = target[:3, :3].T @ T[:3, :3]
    angle = math.atan2(np.linalg.norm(vee(relative)), (np.trace(relative) - 1) / 2)
    return float(np.linalg.norm(T[:3, 3] - target[:3, 3])), angle


def within_limits(name: str, q: np.ndarray) -> bool:
    return all(
        j.limits is None or j.limits[0] - 1e-12 <= v <= j.limits[1] + 1e-12
        for v, j in zip(q, robot(name).joints, strict=True)
    )


def targets(name: str, count: int, seed: int) -> list[np.ndarray]:
    """Poses of random joint values within the limits (unlimited joints in [-pi, pi] or
    [-0.5, 0.5] m), by the independent FK: reachable by construction."""
    rng = np.random.default_rng(seed)
    poses = []
    for _ in range(count):
        q = [
            rng.uniform(*j.limits)
            if j.limits
            else rng.uniform(-math.pi, math.pi)
            if j.type == "revolute"
            else rng.uniform(-0.5, 0.5)
            for j in robot(name).joints
        ]
        poses.append(reference(name).fk(np.array(q)))
    return poses


@pytest.fixture
def no_compiler(monkeypatch: pytest.MonkeyPatch) -> None:
    """``CC`` names a program that does not exist, and no extension is remembered."""
    monkeypatch.setenv("CC", "/nonexistent/symkin-test-cc")
    # Fresh caches for the test (identity and content); the process's own come back after it.
    monkeypatch.setattr(modules, "_RECENT", {})
    monkeypatch.setattr(compiled_ik, "_build", functools.lru_cache(compiled_ik._build.__wrapped__))


# (robot, position only, poses): rpr and hand_standard (a parameter without a value, given by
# override; base and tool) with the tool position, the 6R and 7R arms with the whole pose.
CASES = [
    ("rpr", True, 30),
    ("hand_standard", True, 20),
    ("puma560", False, 30),
    ("panda", False, 15),
]


@pytest.mark.needs_cc
@pytest.mark.parametrize(("name", "position_only", "count"), CASES)
def test_compiled_and_numpy_backends_agree_and_reach_the_pose(
    name: str, position_only: bool, count: int, model_of
) -> None:
    model = model_of(name)
    for k, target in enumerate(targets(name, count, seed=11)):
        results = {
            backend: solve_ik(
                model,
                target,
                position_only=position_only,
                backend=backend,
                rest_posture=None,
                overrides=overrides(name),
            )
            for backend in ("c", "numpy")
        }
        assert results["c"].backend == "c" and results["numpy"].backend == "numpy"
        assert results["c"].success == results["numpy"].success, (name, k)
        for result in results.values():
            assert result.success, (name, k, result.backend, result.residual)
            position, rotation = independent_errors(name, result.q, target)
            assert position <= CHECK, (name, k, result.backend)
            assert position_only or rotation <= CHECK, (name, k, result.backend)
            assert within_limits(name, result.q)
        # The same algorithm, the same seed: the same restarts and the same answer.
        assert results["c"].restarts == results["numpy"].restarts, (name, k)
        np.testing.assert_allclose(results["c"].q, results["numpy"].q, atol=1e-6)


@pytest.mark.needs_cc
def test_the_default_call_runs_the_compiled_solver(model_of) -> None:
    target = targets("rpr", 1, seed=3)[0]
    result = solve_ik(model_of("rpr"), target, position_only=True)
    assert result.backend == "c" and result.success


def test_without_a_compiler_the_numpy_twin_runs_and_still_solves(no_compiler, model_of) -> None:
    name = "hand_standard"
    model = model_of(name)
    for target in targets(name, 5, seed=4):
        result = solve_ik(model, target, position_only=True, overrides=overrides(name))
        assert result.backend == "numpy" and result.success
        assert independent_errors(name, result.q, target)[0] <= CHECK


def test_asking_for_the_compiled_solver_without_a_compiler_says_why(no_compiler, model_of):
    target = targets("rpr", 1, seed=5)[0]
    with pytest.raises(SymkinError, match=r"no C compiler found.*symkin-test-cc"):
        solve_ik(model_of("rpr"), target, position_only=True, backend="c")


def test_requests_beyond_damped_least_squares_run_the_python_solver(model_of) -> None:
    """Newton, weights and a task of its own are the general solver's; 'auto' picks it and
    'c' refuses them, naming the parameter."""
    model = model_of("rpr")
    target = targets("rpr", 1, seed=6)[0]
    newton = solve_ik(model, target, position_only=True, method="newton")
    weighted = solve_ik(model, target, position_only=True, weights=[1.0, 2.0, 1.0])
    two_rows = solve_ik(model, target, task=["x", "y"])
    for result in (newton, weighted, two_rows):
        assert result.backend == "python" and result.success
    with pytest.raises(ParameterError, match="backend"):
        solve_ik(model, target, position_only=True, method="newton", backend="c")
    with pytest.raises(ParameterError, match="backend"):
        solve_ik(model, target, position_only=True, backend="fortran")


@pytest.mark.needs_cc
def test_a_redundant_arm_keeps_its_rest_posture_on_the_compiled_solver(model_of) -> None:
    """hand_standard has 4 joints for 3 position rows: the solution moves toward the middle
    of the ranges (0 for its unlimited joints) without leaving the target."""
    name = "hand_standard"
    model = model_of(name)
    for target in targets(name, 5, seed=8):
        free = solve_ik(
            model, target, position_only=True, rest_posture=None, overrides=overrides(name)
        )
        rest = solve_ik(model, target, position_only=True, overrides=overrides(name))
        assert rest.backend == "c" and rest.success
        assert independent_errors(name, rest.q, target)[0] <= CHECK
        assert np.linalg.norm(rest.q) <= np.linalg.norm(free.q) + 1e-9


@pytest.mark.needs_cc
def test_the_extension_checks_its_arguments_and_batches(model_of) -> None:
    model = model_of("rpr")
    extension = compiled_ik.ik_extension(model)
    lower = np.array([j.limits[0] if j.limits else -np.inf for j in robot("rpr").joints])
    upper = np.array([j.limits[1] if j.limits else np.inf for j in robot("rpr").joints])
    settings = (100, 10, 1e-10, 1e-10, 1e-9, 0.1, True, 1)
    poses = np.stack(targets("rpr", 4, seed=9))
    seeds = np.zeros((4, 3))
    q, status, iterations, restarts, _, _ = extension.ik(
        poses, seeds, np.array([1.0]), lower, upper, *settings
    )
    assert q.shape == (4, 3) and status.tolist() == [0, 0, 0, 0]
    for k in range(4):  # each pose of the batch alone gives the same answer
        alone = extension.ik(poses[k], seeds[k], np.array([1.0]), lower, upper, *settings)
        np.testing.assert_array_equal(alone[0], q[k])
        assert alone[1:4] == (status[k], iterations[k], restarts[k])
        assert independent_errors("rpr", q[k], poses[k])[0] <= CHECK
    with pytest.raises(ValueError, match="T_target must be numbers of shape"):
        extension.ik(np.eye(3), seeds[0], None, lower, upper, *settings)
    with pytest.raises(ValueError, match="q_seed"):
        extension.ik(poses, seeds[:2], None, lower, upper, *settings)
    with pytest.raises(TypeError, match="expected ik"):
        extension.ik(poses, seeds)


def test_a_child_forked_during_a_compile_gets_a_free_lock() -> None:
    """A fork while another thread compiles (the lock held) must not leave the child waiting
    for a thread it does not have."""
    with compiled_ik._LOCK:  # as while a compile runs
        pid = os.fork()
        if pid == 0:  # the child: exit 0 when the lock can be taken
            os._exit(0 if compiled_ik._LOCK.acquire(timeout=5) else 1)
    _, status = os.waitpid(pid, 0)
    assert os.waitstatus_to_exitcode(status) == 0
