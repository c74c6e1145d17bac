"""Generated IK: the C damped-least-squares solver (double and float, through ctypes and
under sanitizers), the NumPy batch twin and the CasADi/IPOPT program.

Every solution is judged by the independent forward kinematics of ``numeric_dh`` (products of
elementary transforms), never by the solvers' own error.  Expected values otherwise come from
Python's solver (:mod:`symkin.solve.ik.numeric`, a different algorithm) and from a hand derivation
for the planar arm held at a joint limit.
"""

from __future__ import annotations

import ctypes
import math
import re
import subprocess
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import symkin
from codegen_helpers import (
    CONVERSION,
    GUARD,
    ROOT,
    function_bodies,
    parameters,
    run_parallel,
    sanitized_driver_command,
    solver_library_command,
    strip_comments,
    write_tree,
)
from numeric_dh import NumericRobot, model, robot, vee
from symkin.emit.c import emit_c
from symkin.emit.ik_c import emit_ik_c
from symkin.generate import files_for_robot
from symkin.kernels import kinematics_kernels
from symkin.kernels.ik.settings import DampedLeastSquares
from symkin.solve.ik.batch import pose_errors, solve_ik_batch
from symkin.solve.ik.casadi_ik import solve_ik_casadi
from symkin.solve.ik.numeric import solve_ik

pytestmark = [pytest.mark.needs_cc, pytest.mark.slow]  # C and NumPy IK on many poses

TOLERANCE = 1e-9  # the success criterion, in m and rad
FLOAT_TOLERANCE = 3e-5  # float solver stops at 1e-5; its float FK differs from ours by ~1e-6
SUCCESS, NOT_CONVERGED, INVALID_INPUT = 0, 1, 2
BUILDS = (("puma560", "double"), ("panda", "double"), ("planar_2r", "double"), ("puma560", "float"))
DRIVER = ROOT / "bench" / "ik_c_loop.c"


@cache
def reference(name: str) -> NumericRobot:
    return NumericRobot.from_robot(robot(name))


def limits(robot: symkin.Robot) -> tuple[np.ndarray, np.ndarray]:
    lower = np.array([j.limits[0] if j.limits else -math.inf for j in robot.joints])
    upper = np.array([j.limits[1] if j.limits else math.inf for j in robot.joints])
    return lower, upper


def random_within_limits(robot: symkin.Robot, count: int, rng: np.random.Generator) -> np.ndarray:
    """Uniform within the limits; joints without limits in [-pi, pi]."""
    lower, upper = limits(robot)
    low, high = (
        np.where(np.isfinite(lower), lower, -np.pi),
        np.where(np.isfinite(upper), upper, np.pi),
    )
    return low + rng.uniform(size=(count, robot.dof)) * (high - low)


def residuals(name: str, target: np.ndarray, q: np.ndarray) -> tuple[float, float]:
    """Position error (m) and rotation angle (rad) of the reference FK of ``q`` from ``target``:
    ``atan2(|vee(E - E^T)| / 2, (tr E - 1) / 2)`` for ``E = R_t R^T``, exact near 0."""
    pose = reference(name).fk(np.asarray(q, dtype=float))
    E = target[:3, :3] @ pose[:3, :3].T
    angle = math.atan2(np.linalg.norm(vee(E - E.T)) / 2, (np.trace(E) - 1) / 2)
    return float(np.linalg.norm(target[:3, 3] - pose[:3, 3])), angle


def problems(name: str, count: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Targets from the reference FK of random q within limits, seeds from other random q."""
    rng = np.random.default_rng(seed)
    q_true = random_within_limits(robot(name), count, rng)
    seeds = random_within_limits(robot(name), count, rng)
    targets = np.array([reference(name).fk(q) for q in q_true])
    return targets, seeds, q_true


class IKLibrary:
    """A compiled ``<robot>_ik.c`` + ``<robot>.c``, called through ctypes."""

    def __init__(self, path: Path, robot: symkin.Robot, precision: str) -> None:
        real = ctypes.c_double if precision == "double" else ctypes.c_float
        n = robot.dof

        class Options(ctypes.Structure):
            _fields_ = [
                ("max_iterations", ctypes.c_int),
                ("max_restarts", ctypes.c_int),
                ("position_tolerance", real),
                ("rotation_tolerance", real),
                ("damping", real),
                ("error_damping", real),
                ("position_only", ctypes.c_int),
                ("lower", real * n),
                ("upper", real * n),
                ("seed", ctypes.c_uint64),
            ]

        class Result(ctypes.Structure):
            _fields_ = [
                ("status", ctypes.c_int),
                ("iterations", ctypes.c_int),
                ("restarts", ctypes.c_int),
                ("position_error", real),
                ("rotation_error", real),
            ]

        self.robot, self.dtype = robot, np.float64 if precision == "double" else np.float32
        self.Options, self.Result = Options, Result
        self.lib = ctypes.CDLL(str(path))
        self.solve_function = getattr(self.lib, f"{robot.name}_ik")
        self.solve_function.restype = ctypes.c_int
        self.solve_function.argtypes = [
            *[ctypes.c_void_p] * 3,
            ctypes.POINTER(Options),
            ctypes.c_void_p,
            ctypes.POINTER(Result),
        ]
        self.default_options = getattr(self.lib, f"{robot.name}_ik_default_options")
        self.default_options.restype = None

    def options(self, **changes: object):
        options = self.Options()
        self.default_options(ctypes.byref(options))
        for key, value in changes.items():
            if key in ("lower", "upper"):
                getattr(options, key)[:] = [float(v) for v in value]
            else:
                setattr(options, key, value)
        return options

    def solve(self, target, seed, options=None, q_initial=np.nan):
        """``(status, q, result)``; ``q`` has guard entries after it that must stay NaN."""
        n = self.robot.dof
        target = np.ascontiguousarray(target, dtype=self.dtype)
        seed = np.ascontiguousarray(seed, dtype=self.dtype)
        p = np.ascontiguousarray(parameters(self.robot), dtype=self.dtype)
        q = np.full(n + GUARD, np.nan, dtype=self.dtype)
        q[:n] = q_initial
        result = self.Result()
        status = self.solve_function(
            target.ctypes.data_as(ctypes.c_void_p),
            seed.ctypes.data_as(ctypes.c_void_p),
            p.ctypes.data_as(ctypes.c_void_p) if p.size else None,
            None if options is None else ctypes.byref(options),
            q.ctypes.data_as(ctypes.c_void_p),
            ctypes.byref(result),
        )
        assert np.all(np.isnan(q[n:])), "the solver wrote past q"
        assert status == result.status
        return status, q[:n].astype(float), result


@dataclass
class Built:
    root: Path
    files: dict[tuple[str, str], dict[str, str]]
    libraries: dict[tuple[str, str], IKLibrary]


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> Built:
    root = tmp_path_factory.mktemp("ik_generated")
    files, commands = {}, {}
    for name, precision in BUILDS:
        kernels = kinematics_kernels(model(name))
        files[name, precision] = {
            **emit_c(robot(name), kernels, precision),
            **emit_ik_c(robot(name), kernels, precision),
        }
        directory = root / f"{name}_{precision}"
        write_tree(directory, files[name, precision])
        c = directory / "c"
        commands[name, precision] = solver_library_command(
            c, name, "ik", "libik.so", tuple(CONVERSION)
        )
    commands["driver"] = sanitized_driver_command(
        root / "puma560_double" / "c", "puma560", "ik", DRIVER
    )
    for build in run_parallel(commands, root).values():
        build.check()
    libraries = {
        key: IKLibrary(root / f"{key[0]}_{key[1]}" / "c" / "libik.so", robot(key[0]), key[1])
        for key in BUILDS
    }
    return Built(root, files, libraries)


# ---------------------------------------------------------------- C, double precision


@pytest.mark.parametrize("name", ["puma560", "panda", "planar_2r"])
def test_c_ik_reaches_random_reachable_targets(built, name):
    library = built.libraries[name, "double"]
    lower, upper = limits(library.robot)
    options = library.options()
    cap = options.max_iterations * (options.max_restarts + 1)
    targets, seeds, _ = problems(name, 40, seed=5)
    for target, seed in zip(targets, seeds, strict=True):
        status, q, result = library.solve(target, seed, options)
        assert status == SUCCESS
        position, rotation = residuals(name, target, q)
        assert position < TOLERANCE and rotation < TOLERANCE, (position, rotation)
        assert np.all((lower <= q) & (q <= upper))
        assert result.iterations <= cap
        assert abs(result.position_error - position) < 1e-12


@pytest.mark.parametrize("name", ["puma560", "planar_2r"])
def test_c_ik_agrees_with_the_python_solver_on_the_same_branch(built, name):
    """Seeds near the generating q put both solvers on that branch; a 6-DOF arm (and the
    planar arm) has isolated solutions there, so the answers must coincide."""
    library = built.libraries[name, "double"]
    targets, _, q_true = problems(name, 8, seed=11)
    rng = np.random.default_rng(3)
    lower, upper = limits(library.robot)
    for target, q0 in zip(targets, q_true, strict=True):
        seed = np.clip(q0 + rng.uniform(-0.05, 0.05, library.robot.dof), lower, upper)
        status, q_c, _ = library.solve(target, seed)
        python = solve_ik(model(name), target, seed, restarts=0)
        assert status == SUCCESS and python.success
        difference = np.angle(np.exp(1j * (q_c - python.q)))  # revolute: modulo 2 pi
        np.testing.assert_allclose(difference, 0.0, atol=1e-7)


def test_c_ik_position_only_matches_the_position(built):
    library = built.libraries["puma560", "double"]
    targets, seeds, _ = problems("puma560", 10, seed=21)
    options = library.options(position_only=1)
    for target, seed in zip(targets, seeds, strict=True):
        status, q, result = library.solve(target, seed, options)
        assert status == SUCCESS
        assert residuals("puma560", target, q)[0] < TOLERANCE
        assert result.position_error < TOLERANCE


def test_c_ik_unreachable_target_fails_with_the_best_finite_pose(built):
    library = built.libraries["puma560", "double"]
    lower, upper = limits(library.robot)
    target = reference("puma560").fk(np.zeros(6))
    target[:3, 3] += [3.0, 0.0, 0.0]  # the arm reaches under 1 m from its shoulder
    options = library.options(max_restarts=3)
    status, q, result = library.solve(target, np.zeros(6), options)
    assert status == NOT_CONVERGED
    assert np.all(np.isfinite(q)) and np.all((lower <= q) & (q <= upper))
    assert result.restarts == 3
    assert result.iterations <= options.max_iterations * 4
    position, rotation = residuals("puma560", target, q)
    assert position > 2.0
    # the returned q is the one whose errors are reported
    assert result.position_error == pytest.approx(position, abs=1e-12)
    assert result.rotation_error == pytest.approx(rotation, abs=1e-12)


def test_c_ik_rejects_invalid_input_and_leaves_q_alone(built):
    library = built.libraries["puma560", "double"]
    target = reference("puma560").fk(np.full(6, 0.3))
    seed = np.zeros(6)
    not_a_number = target.copy()
    not_a_number[0, 3] = np.nan
    stretched = target.copy()
    stretched[:3, :3] *= 1.01
    crossed = library.options(lower=[1.0] * 6, upper=[-1.0] * 6)
    cases = [
        (not_a_number, seed, None),
        (stretched, seed, None),
        (target, np.full(6, np.inf), None),
        (target, seed, crossed),
        (target, seed, library.options(max_iterations=-1)),
        (target, seed, library.options(position_tolerance=0.0)),
    ]
    for case_target, case_seed, options in cases:
        status, q, result = library.solve(case_target, case_seed, options, q_initial=7.0)
        assert status == INVALID_INPUT
        assert np.all(q == 7.0)
        assert result.iterations == 0


def test_c_ik_holds_limits_when_they_make_the_target_unreachable(built):
    """Planar 2R (unit links) with |q2| <= 0.8 reaches radii 2 cos(q2 / 2) >= 2 cos(0.4); the
    target (from q = (0.3, 1.4)) lies at radius 2 cos(0.7), so no pose within the limits is
    closer than 2 cos(0.4) - 2 cos(0.7).  (DLS gives up on an unreachable target, so it need
    not reach that bound; the CasADi program below must.)"""
    library = built.libraries["planar_2r", "double"]
    target = reference("planar_2r").fk(np.array([0.3, 1.4]))
    lower, upper = np.array([-math.pi, -0.8]), np.array([math.pi, 0.8])
    options = library.options(position_only=1, lower=lower, upper=upper, max_restarts=5)
    status, q, result = library.solve(target, np.array([0.0, 0.2]), options)
    assert status == NOT_CONVERGED
    assert np.all((lower <= q) & (q <= upper))
    bound = 2 * math.cos(0.4) - 2 * math.cos(0.7)
    position = residuals("planar_2r", target, q)[0]
    assert bound - 1e-12 <= position < bound + 0.1
    assert result.position_error == pytest.approx(position, abs=1e-12)


# ---------------------------------------------------------------- C, single precision


def test_float_ik_converges_to_a_float_tolerance(built):
    library = built.libraries["puma560", "float"]
    lower, upper = limits(library.robot)
    targets, seeds, _ = problems("puma560", 30, seed=8)
    for target, seed in zip(targets, seeds, strict=True):
        status, q, _ = library.solve(target, seed)
        assert status == SUCCESS
        position, rotation = residuals("puma560", target, q)
        assert position < FLOAT_TOLERANCE and rotation < FLOAT_TOLERANCE, (position, rotation)
        assert np.all((lower - 1e-6 <= q) & (q <= upper + 1e-6))  # limits rounded to float
    for path, text in built.files["puma560", "float"].items():
        if "_ik." in path:
            assert not re.search(r"\bdouble\b", strip_comments(text)), path


# ---------------------------------------------------------------- C source rules and the driver


def test_ik_c_allocates_nothing_has_no_file_scope_data_and_no_recursion(built):
    for (name, precision), files in built.files.items():
        source = strip_comments(files[f"c/{name}_ik.c"])
        header = strip_comments(files[f"c/{name}_ik.h"])
        for text in (source, header):
            assert not re.search(r"\b(malloc|calloc|realloc|free|alloca)\b", text)
        depth = 0
        for line in source.splitlines():
            stripped = line.strip()
            if depth == 0 and stripped and not stripped.startswith("#") and stripped != "{":
                # functions (the symkin C library's are static) and types; no data
                function = r"(static |SYMKIN_API )?\w+ \w+\([^;]*\);?"
                assert re.fullmatch(rf"{function}|typedef .*", stripped), (
                    f"{name} {precision}: file-scope line {line!r}"
                )
            depth += line.count("{") - line.count("}")
        assert depth == 0
        bodies = function_bodies(source)
        assert {f"{name}_ik", f"{name}_ik_default_options"} <= set(bodies)
        for function, body in bodies.items():
            callees = {g for g in bodies if g != function and re.search(rf"\b{g}\s*\(", body)}
            assert not re.search(rf"\b{function}\s*\(", body), f"{function} calls itself"
            assert all(function not in bodies[g] for g in callees), f"{function}: cycle"


def test_sanitized_bench_driver_solves_and_fails_cleanly(built):
    """bench/ik_c_loop.c under AddressSanitizer/UBSan: reachable targets, one far away."""
    targets, seeds, _ = problems("puma560", 4, seed=13)
    far = targets[0].copy()
    far[:3, 3] += 5.0
    rows = [
        np.concatenate([t.ravel(), s])
        for t, s in zip([*targets, far], [*seeds, seeds[0]], strict=True)
    ]
    text = "5 6\n" + "\n".join(" ".join(repr(float(v)) for v in row) for row in rows) + "\n"
    run = subprocess.run(
        [str(built.root / "puma560_double" / "c" / "driver"), "1"],
        input=text, capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    lines = [line.split() for line in run.stdout.splitlines()]
    assert [int(line[0]) for line in lines] == [SUCCESS] * 4 + [NOT_CONVERGED]
    for line, target in zip(lines[:4], targets, strict=True):
        q = np.array([float(v) for v in line[4:]])
        assert max(residuals("puma560", target, q)) < TOLERANCE
    assert all(math.isfinite(float(v)) for v in lines[4][4:])


# ---------------------------------------------------------------- NumPy batch


def test_numpy_batch_equals_per_pose_solves_and_the_c_solver(built):
    name = "puma560"
    targets, seeds, _ = problems(name, 16, seed=17)
    batch = solve_ik_batch(model(name), targets, seeds)
    assert batch.success.all()
    library = built.libraries[name, "double"]
    for i, (target, seed) in enumerate(zip(targets, seeds, strict=True)):
        alone = solve_ik_batch(model(name), target, seed)
        np.testing.assert_allclose(alone.q[0], batch.q[i], rtol=0, atol=1e-12)
        assert (alone.iterations[0], alone.restarts[0]) == (batch.iterations[i], batch.restarts[i])
        assert max(residuals(name, target, batch.q[i])) < TOLERANCE
        # Same algorithm, same restart stream: the same steps (a different last bit of libm's
        # sin/cos could only flip a threshold test by the smallest of margins).
        status, q_c, result = library.solve(target, seed)
        assert status == SUCCESS
        assert (result.iterations, result.restarts) == (batch.iterations[i], batch.restarts[i])
        np.testing.assert_allclose(q_c, batch.q[i], rtol=0, atol=1e-9)


def test_numpy_batch_reaches_panda_targets_within_limits():
    name = "panda"
    targets, seeds, _ = problems(name, 30, seed=19)
    lower, upper = limits(robot(name))
    batch = solve_ik_batch(model(name), targets, seeds, settings=DampedLeastSquares(seed=99))
    assert batch.success.all()
    for target, q in zip(targets, batch.q, strict=True):
        assert max(residuals(name, target, q)) < TOLERANCE
        assert np.all((lower <= q) & (q <= upper))


def test_pose_error_is_the_rotation_vector_at_every_angle():
    """The error's rotation part against SciPy's rotation vector, from tiny angles to pi."""
    rng = np.random.default_rng(29)
    axes = rng.normal(size=(40, 3))
    axes /= np.linalg.norm(axes, axis=1)[:, None]
    angles = np.concatenate(
        [[1e-12, 1e-6, 0.5, 1.5, 2.5, 3.0, math.pi - 1e-6], rng.uniform(0, math.pi, 33)]
    )
    rotvecs = axes * angles[:, None]
    targets = np.tile(np.eye(4), (40, 1, 1))
    targets[:, :3, :3] = Rotation.from_rotvec(rotvecs).as_matrix()
    poses = np.tile(np.eye(4), (40, 1, 1))
    poses[:, :3, :3] = Rotation.random(40, random_state=5).as_matrix()
    poses[:, :3, 3] = rng.normal(size=(40, 3))
    targets[:, :3, :3] = targets[:, :3, :3] @ poses[:, :3, :3]  # so that R_t R^T = exp(rotvec)
    e, position, angle = pose_errors(targets, poses)
    np.testing.assert_allclose(e[:, 3:], rotvecs, rtol=0, atol=1e-9)
    np.testing.assert_allclose(angle, angles, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(position, np.linalg.norm(poses[:, :3, 3], axis=1), rtol=1e-15)


def test_numpy_batch_rejects_mismatched_input():
    with pytest.raises(symkin.SymkinError, match="one per target"):
        solve_ik_batch(model("planar_2r"), np.stack([np.eye(4)] * 2), np.zeros((3, 2)))
    with pytest.raises(symkin.SymkinError, match="seeds"):
        solve_ik_batch(model("planar_2r"), np.eye(4), np.zeros(3))


# ---------------------------------------------------------------- CasADi / IPOPT


def test_casadi_ik_reaches_puma_targets_within_limits():
    name = "puma560"
    targets, seeds, _ = problems(name, 3, seed=23)
    lower, upper = limits(robot(name))
    for target, seed in zip(targets, seeds, strict=True):
        result = solve_ik_casadi(model(name), target, seed, restarts=10)
        assert result.success and result.method == "ipopt"
        assert max(residuals(name, target, result.q)) < TOLERANCE
        assert np.all((lower <= result.q) & (result.q <= upper))


def test_casadi_ik_holds_a_joint_at_its_limit():
    """Planar 2R, unit links, |q2| <= 0.8, position only.  The target (from q = (0.3, 1.4))
    lies at radius 2 cos(0.7) < 2 cos(0.4), the smallest radius the limit allows, so the best
    pose has |q2| = 0.8 and points the arm at the target:
    q1 + atan2(sin q2, 1 + cos q2) = q1 + q2 / 2 = atan2(y, x)."""
    target = reference("planar_2r").fk(np.array([0.3, 1.4]))
    lower, upper = np.array([-math.pi, -0.8]), np.array([math.pi, 0.8])
    result = solve_ik_casadi(
        model("planar_2r"), target, [0.0, 0.2], position_only=True, limits=(lower, upper)
    )
    assert not result.success
    assert abs(result.q[1]) == pytest.approx(0.8, abs=1e-9)
    assert result.q[0] + result.q[1] / 2 == pytest.approx(
        math.atan2(target[1, 3], target[0, 3]), abs=1e-7
    )
    assert result.position_error == pytest.approx(2 * math.cos(0.4) - 2 * math.cos(0.7), abs=1e-9)
    assert np.all((lower <= result.q) & (result.q <= upper))


# ---------------------------------------------------------------- generate


def test_c_backend_writes_the_ik_files_beside_the_kernels():
    for precision in ("double", "float"):
        files = files_for_robot(robot("planar_2r"), ["c"], precision)
        assert {"c/planar_2r_ik.h", "c/planar_2r_ik.c"} <= set(files)
        header = files["c/planar_2r_ik.h"]
        assert '#include "planar_2r.h"' in header
        assert f"int planar_2r_ik(const {precision} T_target[16]" in header
