"""The numeric part of the C library, ``templates/c/lib`` (real type, xorshift64, pose error,
Cholesky, damped least squares), on its own: every source compiles alone as strict C99 in
double and float (``-Wconversion -Wdouble-promotion``, AddressSanitizer and UBSan), and small
programs are checked against values computed here independently:

* Cholesky: ``numpy.linalg.solve`` on random symmetric positive definite systems; a matrix
  that is not positive definite (an eigenvalue below zero, a NaN) is refused;
* xorshift64: Marsaglia's shifts 13, 7, 17 written out below in Python integers;
* pose error: transforms made from a known axis and angle (Rodrigues' formula), so the
  expected rotation vector is the one the pose was made with, at every angle up to pi;
* damped least squares: a planar two-link arm whose forward kinematics and Jacobian are
  written by hand in the C program; the answer is judged by the forward formula here.

The generated files paste these same sources (``templates/c/library.j2``); that the pasted
text is the file, byte for byte, is checked too.
"""

from __future__ import annotations

import math
import re
import subprocess
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from codegen_helpers import CC, CONVERSION, ROOT, SANITIZE, STRICT, run_parallel
from symkin.emit.c_library import PARTS, library_files
from symkin.emit.render import render

# Every source built with sanitizers in two precisions: seconds, so in the slow tier.
pytestmark = [pytest.mark.needs_cc, pytest.mark.slow]

LIB = ROOT / "templates" / "c" / "lib"
SOURCES = [f"symkin_{part}.c" for part in PARTS]
PRECISIONS = {"double": [], "float": ["-DSYMKIN_FLOAT"]}
FLAGS = [*STRICT, *CONVERSION, *SANITIZE, f"-I{LIB}"]

# Programs reading numbers (%lf) from stdin and printing results (%.17g), one per library part.
PRELUDE = r"""
#include <stdio.h>
#include <stdint.h>
#include "symkin_real.h"

static real_t read_real(void)
{
    double value = 0;
    if (scanf("%lf", &value) != 1) {
        value = 0;
    }
    return (real_t)value;
}

static void print_real(real_t value)
{
    printf("%.17g\n", (double)value);
}
"""

PROGRAMS = {
    # "n a[n*n] b[n]" repeated: the status of the factorisation, then x = a^-1 b.
    "cholesky": r"""
#include "symkin_cholesky.h"

int main(void)
{
    real_t a[64], x[8];
    int n, i;
    while (scanf("%d", &n) == 1 && n > 0 && n <= 8) {
        for (i = 0; i < n * n; ++i) {
            a[i] = read_real();
        }
        for (i = 0; i < n; ++i) {
            x[i] = read_real();
        }
        if (symkin_cholesky_factor(a, n)) {
            printf("1\n");
            symkin_cholesky_solve(a, n, x);
            for (i = 0; i < n; ++i) {
                print_real(x[i]);
            }
        } else {
            printf("0\n");
        }
    }
    return 0;
}
""",
    # "seed count": count states, then count uniform numbers from the same seed.
    "xorshift": r"""
#include <inttypes.h>
#include "symkin_xorshift.h"

int main(void)
{
    uint64_t seed, state;
    int count, i;
    if (scanf("%" SCNu64, &seed) != 1) {
        return 1;
    }
    count = (int)read_real();
    state = seed;
    for (i = 0; i < count; ++i) {
        printf("%" PRIu64 "\n", symkin_xorshift64(&state));
    }
    state = seed;
    for (i = 0; i < count; ++i) {
        print_real(symkin_uniform(&state));
    }
    return 0;
}
""",
    # "T_target[16] T[16]" repeated: e[6], the position error and the rotation error.
    "pose_error": r"""
#include "symkin_pose_error.h"

int main(void)
{
    real_t target[16], pose[16], e[6], position, rotation;
    int i;
    for (;;) {
        for (i = 0; i < 32; ++i) {
            const real_t value = read_real();
            if (feof(stdin)) {
                return 0;
            }
            if (i < 16) {
                target[i] = value;
            } else {
                pose[i - 16] = value;
            }
        }
        symkin_pose_error(target, pose, e, &position, &rotation);
        for (i = 0; i < 6; ++i) {
            print_real(e[i]);
        }
        print_real(position);
        print_real(rotation);
    }
}
""",
    # A planar two-link arm (links 1 and 0.5 along x, both joints about z, limits +-3):
    # "T_target[16] q_seed[2]" repeated: status, iterations, restarts, q[2].
    "dls": r"""
#include <math.h>
#include "symkin_dls.h"

static void fk_jacobian(const real_t *q, const real_t *p, real_t *T, real_t *J)
{
    const double q1 = (double)q[0], q12 = (double)q[0] + (double)q[1];
    const real_t c1 = (real_t)cos(q1), s1 = (real_t)sin(q1), c12 = (real_t)cos(q12);
    const real_t s12 = (real_t)sin(q12);
    int i;
    (void)p;
    for (i = 0; i < 16; ++i) {
        T[i] = 0;
    }
    for (i = 0; i < 12; ++i) {
        J[i] = 0;
    }
    T[0] = c12; T[1] = -s12; T[4] = s12; T[5] = c12; T[10] = 1; T[15] = 1;
    T[3] = c1 + c12 / 2;
    T[7] = s1 + s12 / 2;
    J[0] = -s1 - s12 / 2; J[1] = -s12 / 2;
    J[2] = c1 + c12 / 2;  J[3] = c12 / 2;
    J[10] = 1;            J[11] = 1;
}

int main(void)
{
    const int revolute[2] = { 1, 1 };
    const real_t span[2] = { 6, 6 }, lower[2] = { -3, -3 }, upper[2] = { 3, 3 };
    const symkin_dls_problem problem = {
        2, 0, fk_jacobian, revolute, span, 5, REAL(0.5), REAL(1e-4), 12345
    };
    symkin_dls_options options;
    symkin_dls_result result;
    real_t target[16], q[2], work[SYMKIN_DLS_WORKSPACE(2, 5)];
    int i;
    options.max_iterations = 100;
    options.max_restarts = 20;
    options.position_tolerance = REAL(1e-5);
    options.rotation_tolerance = REAL(1e-5);
    options.damping = REAL(1e-6);
    options.error_damping = REAL(0.1);
    options.position_only = 0;
    options.lower = lower;
    options.upper = upper;
    options.seed = 7;
    for (;;) {
        for (i = 0; i < 18; ++i) {
            const real_t value = read_real();
            if (feof(stdin)) {
                return 0;
            }
            if (i < 16) {
                target[i] = value;
            } else {
                q[i - 16] = value;
            }
        }
        symkin_dls_solve(&problem, target, q, NULL, &options, work, q, &result);
        printf("%d %d %d\n", result.status, result.iterations, result.restarts);
        print_real(q[0]);
        print_real(q[1]);
    }
}
""",
}


@dataclass
class Built:
    root: Path
    builds: dict


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> Built:
    root = tmp_path_factory.mktemp("c_sources")
    commands = {}
    for precision, define in PRECISIONS.items():
        for source in SOURCES:
            output = str(root / f"{source}.{precision}.o")
            commands[source, precision] = [
                CC,
                *FLAGS,
                *define,
                "-c",
                str(LIB / source),
                "-o",
                output,
            ]
        for part, program in PROGRAMS.items():
            driver = root / f"{part}_test.c"
            driver.write_text(PRELUDE + program, encoding="utf-8")
            output = str(root / f"{part}.{precision}")
            library = [str(LIB / source) for source in SOURCES]
            commands[part, precision] = [
                CC,
                *FLAGS,
                *define,
                "-o",
                output,
                str(driver),
                *library,
                "-lm",
            ]
    return Built(root, run_parallel(commands, root))


def run(built: Built, part: str, precision: str, text: str) -> list[str]:
    built.builds[part, precision].check()
    result = subprocess.run(
        [str(built.root / f"{part}.{precision}")],
        input=text, capture_output=True, text=True, timeout=60, check=False,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    return result.stdout.split()


def numbers(values) -> str:
    return " ".join(repr(float(v)) for v in np.ravel(values)) + "\n"


# ---------------------------------------------------------------- every source alone


@pytest.mark.slow
@pytest.mark.parametrize("precision", PRECISIONS)
@pytest.mark.parametrize("source", SOURCES)
def test_each_source_compiles_alone_strictly(built, source, precision):
    built.builds[source, precision].check()
    assert not built.builds[source, precision].output.strip()  # not even a note


@pytest.mark.parametrize("precision", PRECISIONS)
def test_each_header_compiles_alone(tmp_path, precision):
    for header in sorted(LIB.glob("symkin_*.h")):
        command = [CC, *STRICT, *CONVERSION, *PRECISIONS[precision], f"-I{LIB}", "-fsyntax-only",
                   "-x", "c", str(header)]  # fmt: skip
        result = subprocess.run(command, capture_output=True, text=True, check=False)
        assert result.returncode == 0, result.stderr


def test_float_library_names_no_double():
    text = (LIB / "symkin_real_float.h").read_text(encoding="utf-8")
    code = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    assert not re.search(r"\bdouble\b", code)
    for source in [*SOURCES, *(s.replace(".c", ".h") for s in SOURCES)]:
        code = re.sub(r"/\*.*?\*/", "", (LIB / source).read_text(encoding="utf-8"), flags=re.S)
        assert not re.search(r"\b(double|float)\b", code), source  # real_t only


def test_generated_files_paste_the_sources_byte_for_byte():
    files = library_files("float", *PARTS)
    assert files[0] == "symkin_real_float.h"
    pasted = render("c/library.j2", library=files)
    for name in files:
        assert (LIB / name).read_text(encoding="utf-8") in pasted, name
    assert "#define SYMKIN_API static" in pasted and "#define SYMKIN_AMALGAMATION" in pasted
    assert library_files("double", "dls", "xorshift") == [
        "symkin_real_double.h", "symkin_xorshift.h", "symkin_xorshift.c", "symkin_dls.h",
        "symkin_dls.c",
    ]  # fmt: skip


# ---------------------------------------------------------------- Cholesky


@pytest.mark.parametrize(("precision", "tolerance"), [("double", 1e-11), ("float", 2e-4)])
def test_cholesky_solves_random_spd_systems_like_numpy(built, precision, tolerance):
    rng = np.random.default_rng(21)
    systems = []
    for n in (1, 2, 3, 6, 7, 8):
        A = rng.normal(size=(n, n))
        A = A @ A.T + n * np.eye(n)  # eigenvalues >= n: well conditioned
        b = rng.normal(size=n)
        systems.append((n, A, b))
    text = "".join(f"{n} " + numbers(A) + numbers(b) for n, A, b in systems)
    out = run(built, "cholesky", precision, text)
    position = 0
    for n, A, b in systems:
        assert out[position] == "1"
        x = np.array([float(v) for v in out[position + 1 : position + 1 + n]])
        expected = np.linalg.solve(A, b)
        assert np.max(np.abs(x - expected)) < tolerance * max(1.0, np.max(np.abs(expected)))
        position += 1 + n
    assert position == len(out)


def test_cholesky_reads_only_the_lower_triangle(built):
    A = np.array([[4.0, 2.0], [2.0, 3.0]])
    upper_garbage = A.copy()
    upper_garbage[0, 1] = 1e300
    b = np.array([1.0, 2.0])
    out = run(built, "cholesky", "double", "2 " + numbers(upper_garbage) + numbers(b))
    assert out[0] == "1"
    np.testing.assert_allclose([float(v) for v in out[1:]], np.linalg.solve(A, b), rtol=1e-14)


@pytest.mark.parametrize("precision", PRECISIONS)
def test_cholesky_refuses_matrices_that_are_not_positive_definite(built, precision):
    indefinite = np.array([[1.0, 2.0], [2.0, 1.0]])  # eigenvalues 3 and -1
    singular = np.array([[1.0, 1.0], [1.0, 1.0]])
    not_a_number = np.array([[1.0, 0.0], [0.0, math.nan]])
    text = "".join("2 " + numbers(A) + numbers([1.0, 1.0]) for A in
                   (indefinite, singular, not_a_number, -np.eye(2)))  # fmt: skip
    assert run(built, "cholesky", precision, text) == ["0", "0", "0", "0"]


# ---------------------------------------------------------------- xorshift64


def marsaglia_xorshift64(state: int, count: int) -> list[int]:
    """Marsaglia (2003), the 64-bit generator with shifts (13, 7, 17) in Python integers."""
    mask = (1 << 64) - 1
    states = []
    for _ in range(count):
        state ^= (state << 13) & mask
        state ^= state >> 7
        state ^= (state << 17) & mask
        states.append(state)
    return states


@pytest.mark.parametrize("seed", [1, 0x9E3779B97F4A7C15, 2**64 - 1])
@pytest.mark.parametrize("precision", PRECISIONS)
def test_xorshift64_is_marsaglias_sequence(built, seed, precision):
    count = 200
    out = run(built, "xorshift", precision, f"{seed} {count}\n")
    expected = marsaglia_xorshift64(seed, count)
    assert [int(v) for v in out[:count]] == expected
    uniform = np.array([float(v) for v in out[count:]])
    top53 = [s >> 11 for s in expected]
    if precision == "double":
        reference = np.array([v * 2.0**-53 for v in top53])  # exact: 53 bits fit a double
    else:
        reference = np.array([np.float32(v) * np.float32(2.0**-53) for v in top53], dtype=float)
    np.testing.assert_array_equal(uniform, reference)
    assert np.all((uniform >= 0) & (uniform <= 1))


def test_xorshift64_known_first_value(built):
    # By hand from seed 1: 1 ^ 1<<13 = 0x2001; >>7 adds 0x40; ^ <<17 gives 0x40822041.
    assert run(built, "xorshift", "double", "1 1\n")[0] == str(0x40822041)


# ---------------------------------------------------------------- pose error


def rodrigues(axis: np.ndarray, angle: float) -> np.ndarray:
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def transform(R: np.ndarray, p: np.ndarray) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    return T


@pytest.mark.parametrize(("precision", "tolerance"), [("double", 1e-9), ("float", 2e-5)])
def test_pose_error_is_the_rotation_vector_of_a_known_rotation(built, precision, tolerance):
    """T_target = [E R, p_t] for a random pose [R, p] and E = Rodrigues(k, angle): e must be
    [p_t - p; angle k] (either sign of k at pi, where both vectors name E)."""
    rng = np.random.default_rng(8)
    angles = [0.0, 1e-12, 1e-6, 0.3, 1.0, 2.0, 3.0, math.pi - 1e-3, math.pi - 1e-7, math.pi]
    cases = []
    for angle in angles * 3:
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        R, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        R *= np.sign(np.linalg.det(R))  # a proper rotation
        p, p_target = rng.normal(size=3), rng.normal(size=3)
        cases.append(
            (transform(rodrigues(axis, angle) @ R, p_target), transform(R, p), axis, angle)
        )
    text = "".join(numbers(target) + numbers(pose) for target, pose, _, _ in cases)
    out = np.array([float(v) for v in run(built, "pose_error", precision, text)]).reshape(-1, 8)
    for row, (target, pose, axis, angle) in zip(out, cases, strict=True):
        dp = target[:3, 3] - pose[:3, 3]
        np.testing.assert_allclose(row[:3], dp, atol=tolerance)
        assert abs(row[6] - np.linalg.norm(dp)) < tolerance
        assert abs(row[7] - angle) < (tolerance if angle < 3 else math.sqrt(tolerance))
        expected = angle * axis
        error = np.linalg.norm(row[3:6] - expected)
        if angle > math.pi - 1e-2:  # -pi k names the same rotation as pi k
            error = min(error, np.linalg.norm(row[3:6] + expected))
        assert error < (tolerance if angle < 3 else math.sqrt(tolerance)), (angle, row, expected)


# ---------------------------------------------------------------- damped least squares


def planar_pose(q: np.ndarray) -> np.ndarray:
    """The arm of the C program: links 1 and 0.5, both joints about z."""
    x = math.cos(q[0]) + 0.5 * math.cos(q[0] + q[1])
    y = math.sin(q[0]) + 0.5 * math.sin(q[0] + q[1])
    return transform(rodrigues(np.array([0.0, 0.0, 1.0]), q[0] + q[1]), np.array([x, y, 0.0]))


@pytest.mark.parametrize("precision", PRECISIONS)
def test_dls_reaches_planar_targets_and_refuses_a_non_rotation(built, precision):
    rng = np.random.default_rng(4)
    goals = rng.uniform(-2.5, 2.5, size=(12, 2))
    seeds = rng.uniform(-2.5, 2.5, size=(12, 2))
    targets = [planar_pose(q) for q in goals]
    sheared = targets[0].copy()
    sheared[0, 1] += 0.1  # not orthonormal: invalid input, q left as the seed
    text = "".join(numbers(t) + numbers(s) for t, s in zip([*targets, sheared], [*seeds, seeds[0]],
                                                            strict=True))  # fmt: skip
    out = run(built, "dls", precision, text)
    rows = [out[i : i + 5] for i in range(0, len(out), 5)]
    assert len(rows) == 13
    for row, target in zip(rows[:12], targets, strict=True):
        assert row[0] == "0", row  # SYMKIN_DLS_SUCCESS
        q = np.array([float(v) for v in row[3:]])
        assert np.all(np.abs(q) <= 3)
        pose = planar_pose(q)
        assert np.linalg.norm(pose[:3, 3] - target[:3, 3]) < 3e-5
        assert np.max(np.abs(pose[:3, :3] - target[:3, :3])) < 3e-5
    assert rows[12][:3] == ["2", "0", "0"]  # SYMKIN_DLS_INVALID_INPUT, nothing done
    np.testing.assert_allclose([float(v) for v in rows[12][3:]], seeds[0], rtol=1e-6)
