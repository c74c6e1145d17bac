"""Generated closed-form IK in C (``c/<robot>_ik_closed.c``), double and float, through ctypes.

Expected values come from two independent places:

* the forward kinematics of ``tests/numeric_dh.py`` (products of elementary transforms, base
  and tool of the hand-written robots built from their xyz/rpy numbers): every returned
  solution must reproduce the target, and the joint values the target was made from must be
  among the solutions;
* the Python closed forms (``symkin.solve.ik.closed_form.closed_form_ik``, whose own tests compare
  with a multi-start numeric solve and Robotics Toolbox): the same solutions in the same order,
  with the same branch flags and limit flags.

The robots: every catalogue robot with a closed form, plus the hand-written robots of
``test_ik_closed_form.py`` (modified DH, base and tool transforms, joint offsets, a planar arm
with a prismatic joint between its revolute joints).  Their C kinematics is the ``fk`` kernel
of the product form: the other kernels are not used and take minutes for some six-joint tables.
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

import symkin
from codegen_helpers import (
    ROOT,
    function_bodies,
    parameters,
    run_parallel,
    sanitized_driver_command,
    solver_library_command,
    strip_comments,
    write_tree,
)
from numeric_dh import NumericRobot, wrap
from symkin.emit.c import emit_c
from symkin.emit.ik_closed_c import BRANCH_BITS, emit_ik_closed_c
from symkin.generate import files_for_robot
from symkin.kernels import Kernel, kernel_from_outputs, state_inputs
from symkin.kernels.ik.plan import closed_form_plan
from symkin.solve.ik.closed_form import closed_form_ik, has_closed_form
from test_ik_closed_form import HAND, model, random_q, reference, robot, task_error

CATALOGUE = (
    "planar_2r",
    "planar_3r",
    "scara",
    "puma560",
    "stanford",
    "cylindrical_rtt_wrist",
    "ur5",
)

pytestmark = [pytest.mark.needs_cc, pytest.mark.slow]  # builds every family in C
ROBOTS = (*CATALOGUE, *HAND)
TOLERANCE = 1e-9  # double: FK of a solution vs. the target (m over size, rotation entries, rad)
FLOAT_TOLERANCE = 1e-4
SAME_Q = 1e-8  # double: C and Python give the same joint values (angles modulo 2 pi)
FLOAT_SAME_Q = 2e-3
INVALID_INPUT = -1
DRIVER = ROOT / "bench" / "ik_closed_loop.c"
# One robot of each kind of arm, run under the sanitizers.
SANITIZED = ("puma560", "stanford", "cylindrical_rtt_wrist", "ur5", "planar_3r")


@cache
def fk_kernel(name: str) -> Kernel:
    """The ``fk`` kernel from the unsimplified product form (quick to build for any table)."""
    m = model(name)
    outputs = [("T", m.product_form.forward_kinematics, "pose of the tool in the base frame")]
    return kernel_from_outputs("fk", "forward kinematics", state_inputs(m), outputs)


def branch_from_bits(bits: int) -> dict[str, str]:
    return {flag: value for (flag, value), (bit, _) in BRANCH_BITS.items() if bits & bit}


def revolute(name: str) -> np.ndarray:
    return np.array([j.type == "revolute" for j in robot(name).joints])


def joint_difference(name: str, q: np.ndarray, other: np.ndarray) -> np.ndarray:
    difference = np.asarray(q, dtype=float) - np.asarray(other, dtype=float)
    return np.abs(np.where(revolute(name), wrap(difference), difference))


@dataclass
class Solutions:
    count: int
    q: np.ndarray  # count x n
    branch: list[dict[str, str]]
    within_limits: list[bool]


class ClosedFormLibrary:
    """A compiled ``<robot>_ik_closed.c`` + ``<robot>.c``, called through ctypes."""

    SENTINEL = -7

    def __init__(self, path: Path, name: str, precision: str) -> None:
        self.name, self.n = name, robot(name).dof
        self.dtype = np.float64 if precision == "double" else np.float32
        self.function = getattr(ctypes.CDLL(str(path)), f"{name}_ik_closed")
        self.function.restype = ctypes.c_int
        # T, p (none for a robot without parameters), q, branch, within_limits.
        self.takes_p = bool(robot(name).parameters)
        self.function.argtypes = [ctypes.c_void_p] * (5 if self.takes_p else 4)
        self.size = 8  # at least MAX_SOLUTIONS of every robot

    def solve(self, target, p=None, *, flags: bool = True) -> Solutions:
        """Solve; ``p`` defaults to the robot file's values.  Checks that nothing is written
        past the returned solutions."""
        p = parameters(robot(self.name)) if p is None else p
        target = np.ascontiguousarray(target, dtype=self.dtype)
        p = np.ascontiguousarray(p, dtype=self.dtype)
        q = np.full(self.size * self.n + 4, np.nan, dtype=self.dtype)
        branch = np.full(self.size + 4, self.SENTINEL, dtype=np.int32)
        within = np.full(self.size + 4, self.SENTINEL, dtype=np.int32)
        count = self.function(
            target.ctypes.data,
            *([p.ctypes.data if p.size else None] if self.takes_p else []),
            q.ctypes.data,
            branch.ctypes.data if flags else None,
            within.ctypes.data if flags else None,
        )
        used = max(count, 0)
        assert np.all(np.isnan(q[used * self.n :])), "wrote past the solutions"
        assert np.all(branch[used:] == self.SENTINEL) and np.all(within[used:] == self.SENTINEL)
        return Solutions(
            count,
            q[: used * self.n].reshape(used, self.n).astype(float),
            [branch_from_bits(int(b)) for b in branch[:used]],
            [bool(w) for w in within[:used]],
        )


@dataclass
class Built:
    root: Path
    files: dict[tuple[str, str], dict[str, str]]
    libraries: dict[tuple[str, str], ClosedFormLibrary]


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> Built:
    root = tmp_path_factory.mktemp("ik_closed_c")
    files, commands = {}, {}
    for name in ROBOTS:
        for precision in ("double", "float"):
            kernels = (fk_kernel(name),)
            files[name, precision] = {
                **emit_c(robot(name), kernels, precision),
                **emit_ik_closed_c(robot(name), kernels, precision),
            }
            c = root / f"{name}_{precision}" / "c"
            write_tree(c.parent, files[name, precision])
            commands[name, precision] = solver_library_command(c, name, "ik_closed", "libclosed.so")
    for name in SANITIZED:
        c = root / f"{name}_double" / "c"
        commands[name, "driver"] = sanitized_driver_command(c, name, "ik_closed", DRIVER)
    for build in run_parallel(commands, root).values():
        build.check()
    libraries = {
        (name, precision): ClosedFormLibrary(
            root / f"{name}_{precision}" / "c" / "libclosed.so", name, precision
        )
        for name in ROBOTS
        for precision in ("double", "float")
    }
    return Built(root, files, libraries)


def targets(name: str, count: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Joint values within the limits and their poses by the independent FK."""
    rng = np.random.default_rng(seed)
    qs = np.array([random_q(name, rng) for _ in range(count)])
    return qs, np.array([reference(name).fk(q) for q in qs])


def assert_same_as_python(name: str, solutions: Solutions, target: np.ndarray, same_q: float):
    """Same number, order, joint values, branch flags and limit flags as ``closed_form_ik``."""
    python = closed_form_ik(model(name), target)
    assert solutions.count == len(python), (solutions.count, len(python))
    for k, expected in enumerate(python):
        assert joint_difference(name, solutions.q[k], expected.q).max() <= same_q, k
        assert solutions.branch[k] == dict(expected.branch), k
        assert solutions.within_limits[k] == expected.within_limits, k


def assert_near_python(name: str, solutions: Solutions, target: np.ndarray, same_q: float):
    """Single precision: every Python solution has a C solution within ``same_q`` and every C
    solution a Python one with the same flags.  (Within about 1e-3 rad of a stretched elbow
    float rounds cos delta to 1, and the two elbows come out as one.)"""
    python = closed_form_ik(model(name), target)
    for expected in python:
        assert any(joint_difference(name, q, expected.q).max() <= same_q for q in solutions.q)
    for q, branch, inside in zip(
        solutions.q, solutions.branch, solutions.within_limits, strict=True
    ):
        assert any(
            joint_difference(name, q, s.q).max() <= same_q
            and branch == dict(s.branch)
            and inside == s.within_limits
            for s in python
        )


# ---------------------------------------------------------------- double precision


def test_every_catalogue_robot_with_a_closed_form_has_one_in_c():
    for name in symkin.catalogue_names():
        kernels = (fk_kernel(name),) if name in CATALOGUE else ()
        written = emit_ik_closed_c(robot(name), kernels, "double")
        assert bool(written) == has_closed_form(robot(name)), name
    assert set(CATALOGUE) == {n for n in symkin.catalogue_names() if has_closed_form(robot(n))}


@pytest.mark.slow
@pytest.mark.parametrize("name", ROBOTS)
def test_double_solutions_reach_the_target_and_match_python(built, name):
    library = built.libraries[name, "double"]
    qs, poses = targets(name, 40, seed=1)
    for q_true, target in zip(qs, poses, strict=True):
        solutions = library.solve(target)
        assert solutions.count >= 1
        for q in solutions.q:
            assert task_error(name, reference(name).fk(q), target) <= TOLERANCE
        assert min(joint_difference(name, q, q_true).max() for q in solutions.q) <= 1e-7
        assert_same_as_python(name, solutions, target, SAME_Q)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["puma560", "craig_puma", "kuka_like", "stanford", "ur5"])
def test_generic_six_joint_poses_have_every_branch(built, name):
    """Two shoulders x two elbows (or reaches) x two wrists: eight distinct solutions at most,
    and every flag value of the family occurs over a few poses."""
    library = built.libraries[name, "double"]
    _, poses = targets(name, 10, seed=2)
    seen = set()
    for target in poses:
        solutions = library.solve(target)
        assert 1 <= solutions.count <= 8
        for k, q in enumerate(solutions.q):
            others = np.delete(solutions.q, k, axis=0)
            assert all(joint_difference(name, q, other).max() > 1e-6 for other in others)
        seen |= {item for branch in solutions.branch for item in branch.items()}
    flags = closed_form_plan(robot(name)).shape.flags
    assert seen == {key for key in BRANCH_BITS if key[0] in flags and key[1] != "singular"}


@pytest.mark.slow
def test_solutions_outside_the_limits_are_flagged(built):
    """Stanford arm: the backward reach needs a negative stroke, outside [0.3048, 1.27] m."""
    _, poses = targets("stanford", 5, seed=3)
    lower = np.array([j.limits[0] for j in robot("stanford").joints])
    upper = np.array([j.limits[1] for j in robot("stanford").joints])
    for target in poses:
        solutions = built.libraries["stanford", "double"].solve(target)
        rows = zip(solutions.q, solutions.branch, solutions.within_limits, strict=True)
        for q, branch, inside in rows:
            assert inside == bool(np.all((lower <= q) & (q <= upper)))
            if branch["extension"] == "backward":
                assert q[2] < 0 and not inside


def test_puma_shoulder_beyond_pi_is_given_inside_its_limits(built):
    """Joint 2's limits are -45..225 deg: 200 deg is returned as 200 deg, not -160."""
    q = np.array([0.2, 200 * math.pi / 180, -0.5, 0.3, 0.6, 0.1])
    solutions = built.libraries["puma560", "double"].solve(reference("puma560").fk(q))
    assert any(np.abs(s - q).max() <= 1e-9 for s in solutions.q)


@pytest.mark.parametrize(
    ("name", "changes"),
    [
        ("puma560", {"a2": 0.5, "a3": -0.03, "d3": 0.1, "d4": 0.38}),
        ("ur5", {"d1": 0.1, "a2": -0.5, "a3": -0.35, "d4": 0.12, "d5": 0.08, "d6": 0.1}),
        ("stanford", {"d1": 0.3, "d2": 0.2, "d6": 0.2}),
        ("planar_3r", {"L1": 0.7, "L2": 1.1, "L3": 0.3}),
        ("kuka_like", {"d1": 0.35, "a1": 0.05, "a2": 0.5}),
    ],
)
def test_the_constants_follow_the_parameter_vector(built, name, changes):
    """p other than the file's values: the C constants come from p at run time."""
    overrides = {**robot(name).parameter_values(), **changes}
    p = np.array([overrides[n] for n, _ in robot(name).parameters])
    oracle = NumericRobot.from_robot(robot(name), overrides)
    library = built.libraries[name, "double"]
    rng = np.random.default_rng(4)
    for _ in range(10):
        q_true = random_q(name, rng)
        target = oracle.fk(q_true)
        solutions = library.solve(target, p)
        python = closed_form_ik(model(name), target, overrides)
        assert solutions.count == len(python) >= 1
        for q, expected in zip(solutions.q, python, strict=True):
            assert joint_difference(name, q, expected.q).max() <= SAME_Q
            assert task_error(name, oracle.fk(q), target) <= TOLERANCE
        assert min(joint_difference(name, q, q_true).max() for q in solutions.q) <= 1e-7
        # the file's values solve another robot
        default = library.solve(target)
        assert default.count != solutions.count or not np.allclose(default.q, solutions.q)


def test_puma_wrist_singularity_gives_q4_zero_and_no_nan(built):
    q = np.array([0.3, -0.4, 0.5, 0.7, 0.0, -0.2])
    target = reference("puma560").fk(q)
    solutions = built.libraries["puma560", "double"].solve(target)
    assert np.all(np.isfinite(solutions.q))
    assert solutions.count == 1 + 3 * 2  # the other arm branches bend their wrists
    (k,) = [k for k, b in enumerate(solutions.branch) if b["wrist"] == "singular"]
    singular = solutions.q[k]
    assert singular[3] == 0.0 and abs(singular[4]) <= 1e-8
    # only q4 + q6 is defined at q5 = 0 (alpha_4 = -alpha_5: the wrist is Rz(q4 + q6))
    assert abs(wrap(singular[5] - (q[3] + q[5]))) <= 1e-8
    assert_same_as_python("puma560", solutions, target, SAME_Q)


def test_ur5_wrist_singularity_gives_q6_zero_and_no_nan(built):
    q = np.array([0.3, -1.1, 1.2, -0.4, 0.0, 0.8])
    target = reference("ur5").fk(q)
    solutions = built.libraries["ur5", "double"].solve(target)
    assert np.all(np.isfinite(solutions.q))
    singular = [
        s for s, b in zip(solutions.q, solutions.branch, strict=True) if "singular" in b.values()
    ]
    assert len(singular) == 2  # two elbows
    for s in singular:
        assert s[5] == 0.0 and abs(s[4]) <= 1e-8
        assert np.abs(reference("ur5").fk(s) - target).max() <= TOLERANCE
    assert_same_as_python("ur5", solutions, target, SAME_Q)


@pytest.mark.parametrize("name", ["puma560", "kuka_like", "stanford", "ur5"])
def test_near_the_wrist_singularity_both_wrists_reach(built, name):
    q = random_q(name, np.random.default_rng(4))
    q[4] = 1e-7 - robot(name).joints[4].theta  # DH angle theta_5 = 1e-7 rad
    target = reference(name).fk(q)
    solutions = built.libraries[name, "double"].solve(target)
    assert {b["wrist"] for b in solutions.branch} == {"flip", "no_flip"}
    for s in solutions.q:
        assert np.abs(reference(name).fk(s) - target).max() <= TOLERANCE
    assert min(joint_difference(name, s, q).max() for s in solutions.q) <= 1e-6


def translation(x: float, y: float, z: float) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, 3] = [x, y, z]
    return pose


# Beyond the reach (planar arms: in their own plane, after the base transform); for the
# PUMA 560 and the Stanford arm also a wrist centre closer to the waist axis than the shoulder
# offset (d3, d2).  The cylindrical arm's slides reach every point.
UNREACHABLE = [
    *(
        (n, reference(n).base @ translation(3.0, 1.0, 0.5))
        for n in ROBOTS
        if n not in ("stanford", "cylindrical_rtt_wrist")
    ),
    ("puma560", translation(0.0, 0.0, 0.3)),
    ("stanford", translation(0.0, 0.0, 1.0)),
]


@pytest.mark.parametrize(("name", "target"), UNREACHABLE, ids=[n for n, _ in UNREACHABLE])
def test_unreachable_targets_give_no_solution(built, name, target):
    assert closed_form_ik(model(name), target) == ()  # the premise
    assert built.libraries[name, "double"].solve(target).count == 0
    assert built.libraries[name, "float"].solve(target).count == 0


def test_fully_stretched_planar_arm_has_one_solution(built):
    target = reference("planar_2r").fk(np.array([0.4, 0.0]))
    solutions = built.libraries["planar_2r", "double"].solve(target)
    assert solutions.count == 1
    assert joint_difference("planar_2r", solutions.q[0], [0.4, 0.0]).max() <= 1e-7


def test_planar_elbow_up_is_counterclockwise_of_the_line_to_the_hand(built):
    """Unit links: the elbow is at (cos q1, sin q1); "up" puts it left of the line from the
    base to the hand (positive cross product)."""
    _, poses = targets("planar_2r", 10, seed=5)
    for target in poses:
        solutions = built.libraries["planar_2r", "double"].solve(target)
        for q, branch in zip(solutions.q, solutions.branch, strict=True):
            elbow = np.array([math.cos(q[0]), math.sin(q[0])])
            cross = target[0, 3] * elbow[1] - target[1, 3] * elbow[0]
            assert (cross > 0) == (branch["elbow"] == "up")


def test_invalid_input_is_reported_and_nothing_written(built):
    library = built.libraries["puma560", "double"]
    target = reference("puma560").fk(np.full(6, 0.3))
    not_a_number, stretched, reflected, last_row = (target.copy() for _ in range(4))
    not_a_number[1, 2] = np.nan
    stretched[:3, :3] *= 1.01
    reflected[:3, 0] *= -1
    last_row[3, 0] = 0.1
    for case in (not_a_number, stretched, reflected, last_row):
        assert library.solve(case).count == INVALID_INPUT
    assert library.solve(target, np.array([0.4318, np.inf, 0.15, 0.43])).count == INVALID_INPUT
    assert library.solve(target, np.zeros(0)).count == INVALID_INPUT  # p == NULL


def test_flag_arrays_may_be_null(built):
    library = built.libraries["ur5", "double"]
    _, (target,) = targets("ur5", 1, seed=6)
    without = library.solve(target, flags=False)
    with_flags = library.solve(target)
    assert without.count == with_flags.count >= 1
    np.testing.assert_array_equal(without.q, with_flags.q)


def test_robot_without_parameters_takes_no_p(built):
    library = built.libraries["planar_mixed", "double"]
    assert not library.takes_p
    _, poses = targets("planar_mixed", 5, seed=7)
    for target in poses:
        solutions = library.solve(target)
        assert solutions.count >= 1
        assert_same_as_python("planar_mixed", solutions, target, SAME_Q)


# ---------------------------------------------------------------- single precision


@pytest.mark.parametrize("name", ROBOTS)
def test_float_solutions_reach_the_target_and_match_python(built, name):
    library = built.libraries[name, "float"]
    qs, poses = targets(name, 20, seed=8)
    for q_true, target in zip(qs, poses, strict=True):
        solutions = library.solve(target)
        for q in solutions.q:
            assert task_error(name, reference(name).fk(q), target) <= FLOAT_TOLERANCE
        assert min(joint_difference(name, q, q_true).max() for q in solutions.q) <= 1e-3
        assert_near_python(name, solutions, target, FLOAT_SAME_Q)
    for path, text in built.files[name, "float"].items():
        if "_ik_closed." in path:
            assert not re.search(r"\bdouble\b", strip_comments(text)), path


def test_float_wrist_singularity_has_no_nan(built):
    q = np.array([0.3, -0.4, 0.5, 0.7, 0.0, -0.2])
    target = reference("puma560").fk(q)
    solutions = built.libraries["puma560", "float"].solve(target)
    assert solutions.count >= 1 and np.all(np.isfinite(solutions.q))
    for s in solutions.q:
        assert np.abs(reference("puma560").fk(s) - target).max() <= FLOAT_TOLERANCE


# ---------------------------------------------------------------- C source rules, driver, generate


def test_closed_form_c_allocates_nothing_has_no_file_scope_data_and_no_recursion(built):
    for (name, precision), files in built.files.items():
        # The pasted C library (templates/c/lib) has its own test: tests/test_ik_closed_sources.py.
        pasted = r"/\* ---- symkin C library .*? end of the symkin C library ---- \*/"
        generated = re.sub(pasted, "", files[f"c/{name}_ik_closed.c"], flags=re.S)
        source = strip_comments(generated)
        header = strip_comments(files[f"c/{name}_ik_closed.h"])
        for text in (source, header):
            assert not re.search(r"\b(malloc|calloc|realloc|free|alloca)\b", text)
            assert not re.search(r"\bM_[A-Z0-9_]+\b", text), "POSIX constant in C99 code"
        depth, in_type = 0, False
        for line in source.splitlines():
            stripped = line.strip()
            if stripped == "typedef struct {":
                in_type = True
            elif depth == 0 and stripped and not stripped.startswith("#") and stripped != "{":
                signature = r"(static )?(void|int|float|double) \w+\(.*\)"
                assert in_type or re.fullmatch(signature, stripped), (
                    f"{name} {precision}: file-scope line {line!r}"
                )
            if stripped.startswith("} constants;"):
                in_type = False
            depth += line.count("{") - line.count("}")
        assert depth == 0
        bodies = function_bodies(source)
        assert f"{name}_ik_closed" in bodies
        for function, body in bodies.items():
            assert not re.search(rf"\b{function}\s*\(", body), f"{function} calls itself"


@pytest.mark.parametrize("name", SANITIZED)
def test_sanitized_bench_driver_solves_singular_and_unreachable_poses(built, name):
    """bench/ik_closed_loop.c under AddressSanitizer/UBSan; six-joint arms also at q5 = 0, and
    the unreachable targets above."""
    n = robot(name).dof
    qs, poses = targets(name, 3, seed=9)
    cases = list(poses)
    if n == 6:
        singular = qs[0].copy()
        singular[4] = -robot(name).joints[4].theta
        cases.append(reference(name).fk(singular))
    unreachable = [target for robot_name, target in UNREACHABLE if robot_name == name]
    cases += unreachable
    rows = [" ".join(repr(float(v)) for v in t.ravel()) for t in cases]
    run = subprocess.run(
        [str(built.root / f"{name}_double" / "c" / "driver"), "2"],
        input=f"{len(cases)} {n}\n" + "\n".join(rows) + "\n",
        capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    lines = [line.split() for line in run.stdout.splitlines()]
    reachable = len(cases) - len(unreachable)
    assert len(lines) == len(cases) and all(int(line[0]) == 0 for line in lines[reachable:])
    for line, target in zip(lines[:reachable], cases[:reachable], strict=True):
        count, values = int(line[0]), [float(v) for v in line[2:]]
        assert count == len(closed_form_ik(model(name), target)) >= 1
        assert len(values) == count * (n + 2) and np.all(np.isfinite(values))
        for q in np.reshape(values, (count, n + 2))[:, 2:]:
            assert task_error(name, reference(name).fk(q), target) <= TOLERANCE


def test_c_backend_writes_closed_form_files_only_where_there_is_a_closed_form():
    scara = files_for_robot(symkin.load_robot("scara"), ["c"], "float")
    assert {"c/scara_ik_closed.h", "c/scara_ik_closed.c"} <= set(scara)
    assert '#include "scara.h"' in scara["c/scara_ik_closed.h"]
    assert "int scara_ik_closed(const float T[16], const float *p," in scara["c/scara_ik_closed.h"]
    rpr = files_for_robot(symkin.load_robot("rpr"), ["c"])
    assert not any("_ik_closed" in path for path in rpr)
