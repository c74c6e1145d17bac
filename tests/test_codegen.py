"""Generated code of every catalogue robot, compiled and run: NumPy, C (double and float,
ctypes and sanitizers), the generated Makefile and CasADi (values, AD, its own C codegen)."""

from __future__ import annotations

import re
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType

import casadi
import numpy as np
import pytest

import symkin
from codegen_helpers import (
    CC,
    CONVERSION,
    SANITIZE,
    SHARED,
    STRICT,
    Build,
    CLibrary,
    Reference,
    as_outputs,
    assert_close,
    c_driver,
    function_bodies,
    import_path,
    numpy_shape,
    parameters,
    random_states,
    run_parallel,
    strip_comments,
    write_tree,
)
from symkin.generate import files_for_robot, robot_kernels
from symkin.kernels import Kernel, kinematics_kernels

pytestmark = pytest.mark.needs_cc

NAMES = symkin.catalogue_names()
STATES = 20
DOUBLE_TOLERANCE = 1e-12
FLOAT_TOLERANCE = 1e-4
KERNEL_NAMES = ("fk", "position", "jacobian", "position_jacobian", "fk_jacobian")


@dataclass
class Generated:
    """One robot's generated files in tmp, its NumPy module and its C builds."""

    name: str
    robot: symkin.Robot
    model: symkin.Model
    kernels: tuple[Kernel, ...]
    root: Path
    files: dict[str, str]
    float_files: dict[str, str]
    numpy: ModuleType
    reference: Reference
    states: np.ndarray
    builds: dict[str, Build]

    @property
    def p(self) -> np.ndarray:
        return parameters(self.robot)

    def c_dir(self, precision: str) -> Path:
        return self.root / precision / "c"

    def numpy_outputs(self, kernel: Kernel, q, p=None) -> tuple[np.ndarray, ...]:
        function = getattr(self.numpy, kernel.name)
        result = function(q) if p is None else function(q, p)
        return as_outputs(result, kernel)


# Each robot here is compiled in two precisions; the quick tier keeps two of them.
QUICK = ("planar_2r", "scara")


@pytest.fixture(
    scope="module",
    params=[n if n in QUICK else pytest.param(n, marks=pytest.mark.slow) for n in NAMES],
)
def gen(request, tmp_path_factory) -> Generated:
    name = request.param
    robot = symkin.load_robot(name)
    model = symkin.derive(robot)
    files = files_for_robot(robot)
    float_files = files_for_robot(robot, ("c",), "float")
    root = tmp_path_factory.mktemp(name)
    write_tree(root / "double", files)
    write_tree(root / "float", float_files)
    write_tree(root / "make", {k: v for k, v in files.items() if k.startswith("c/")})
    kernels = kinematics_kernels(model)
    states = random_states(robot, STATES, seed=1000 + NAMES.index(name))
    (root / "double" / "c" / "driver.c").write_text(c_driver(robot, kernels, states[:3]))
    d, f = f"double/c/{name}.c", f"float/c/{name}.c"
    builds = run_parallel(
        {
            "double_so": [CC, *STRICT, *CONVERSION, *SHARED, "-o", "double/libkin.so", d, "-lm"],
            "float_so": [CC, *STRICT, *CONVERSION, *SHARED, "-o", "float/libkin.so", f, "-lm"],
            "asan_example": [
                CC, *STRICT, *SANITIZE, "-o", "double/c/example_asan",
                "double/c/example.c", d, "-lm",
            ],
            "asan_driver": [
                CC, *STRICT, *SANITIZE, "-o", "double/c/driver_asan",
                "double/c/driver.c", d, "-lm",
            ],
            "float_example": [
                CC, *STRICT, *CONVERSION, "-o", "float/c/example", "float/c/example.c", f,
                "-lm",
            ],
            "vla": [CC, *STRICT, "-Wvla", "-fsyntax-only", d, f],
            "make": ["make", "-C", "make/c"],
        },
        cwd=root,
    )  # fmt: skip
    module = import_path(f"generated_{name}_kinematics", root / "double" / "numpy" /
                         f"{name}_kinematics.py")  # fmt: skip
    return Generated(
        name, robot, model, kernels, root, files, float_files, module, Reference(model), states,
        builds,
    )  # fmt: skip


def run(command: list[str], cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(command, cwd=cwd, capture_output=True, text=True, timeout=120)


# ---------------------------------------------------------------- NumPy


def test_kernels_are_the_documented_set(gen):
    names = [k.name for k in gen.kernels]
    assert names[:5] == list(KERNEL_NAMES)
    square = gen.model.determinant() is not None
    redundant = len(gen.model.task_rows) < gen.robot.dof
    assert names[5:] == (
        ["det", "manipulability"] if square else ["manipulability"] if redundant else []
    )
    for kernel in gen.kernels:
        assert callable(getattr(gen.numpy, kernel.name)), kernel.name
    assert gen.robot.dof == gen.numpy.DOF
    assert tuple(gen.numpy.PARAMETER_NAMES) == tuple(n for n, _ in gen.robot.parameters)
    np.testing.assert_array_equal(gen.numpy.DEFAULT_PARAMETERS, gen.p)


def test_numpy_matches_reference(gen):
    for q in gen.states:
        for kernel in gen.kernels:
            outputs = gen.numpy_outputs(kernel, q)
            assert len(outputs) == len(kernel.outputs)
            for output, value in zip(kernel.outputs, outputs, strict=True):
                what = f"{gen.name}.{kernel.name}.{output.name} at q={q.tolist()}"
                assert np.shape(value) == numpy_shape(*output.shape), what
                expected = gen.reference(output.name, q).reshape(numpy_shape(*output.shape))
                assert_close(value, expected, DOUBLE_TOLERANCE, what)


def test_numpy_batch_equals_loop(gen):
    rng = np.random.default_rng(7)
    q = rng.uniform(-np.pi, np.pi, size=(5, 7, gen.robot.dof))
    p = gen.p * 1.25 + 0.01  # explicit, non-default parameters go through too
    for kernel in gen.kernels:
        batched = gen.numpy_outputs(kernel, q, p)
        for output, value in zip(kernel.outputs, batched, strict=True):
            assert value.shape == (5, 7, *numpy_shape(*output.shape)), (kernel.name, output.name)
        # A batch of 35 takes sin and cos from the half-angle tangent, one state from math
        # (each within 4.5e-16, tests/test_numpy_batch.py): equal to rounding, not bit for bit,
        # and the Panda's manipulability (sqrt of a 6x6 Gram determinant) grows that to 1e-14.
        for i in range(5):
            for j in range(7):
                single = gen.numpy_outputs(kernel, q[i, j], p)
                for a, b in zip(batched, single, strict=True):
                    assert_close(a[i, j], b, 1e-13, f"{gen.name}.{kernel.name} batch [{i},{j}]")


def test_numpy_refuses_vectors_of_the_wrong_length(gen):
    """One value too many was ignored and one too few raised IndexError; the C extension
    already refused both.  A batch keeps working."""
    n = gen.robot.dof
    for kernel in gen.kernels:
        function = getattr(gen.numpy, kernel.name)
        for q in (np.zeros(n + 1), np.zeros(n - 1), np.zeros((3, n + 2))):
            with pytest.raises(ValueError, match=rf"^q: expected {n} values"):
                function(q)
        if gen.p.size:
            with pytest.raises(ValueError, match=rf"^p: expected {gen.p.size} values"):
                function(np.zeros(n), np.zeros(gen.p.size + 1))
        assert len(as_outputs(function(np.zeros((3, n))), kernel)[0]) == 3


def test_numpy_parameters_are_used_in_file_order(gen):
    overrides = {n: 0.5 + 0.1 * i for i, (n, _) in enumerate(gen.robot.parameters)}
    p = np.array([overrides[n] for n, _ in gen.robot.parameters])
    expected = symkin.numeric_function(gen.model, gen.model.forward_kinematics, overrides)
    for q in gen.states[:5]:
        assert_close(gen.numpy.fk(q, p), expected(q), DOUBLE_TOLERANCE, f"{gen.name}.fk(q, p)")


# ---------------------------------------------------------------- C through ctypes


def test_c_double_matches_numpy(gen):
    gen.builds["double_so"].check()
    lib = CLibrary(gen.root / "double" / "libkin.so", gen.robot, np.float64)
    p_other = gen.p * 1.25 + 0.01
    for kernel in gen.kernels:
        for p in (gen.p, p_other):
            expected = gen.numpy_outputs(kernel, gen.states, p)
            batch = lib.batch(kernel, gen.states, p)
            for got, want, output in zip(batch, expected, kernel.outputs, strict=True):
                assert_close(got, want, DOUBLE_TOLERANCE, f"{kernel.name}_batch {output.name}")
            for s, q in enumerate(gen.states[:8]):
                single = lib.single(kernel, q, p)
                for got, want, output in zip(single, expected, kernel.outputs, strict=True):
                    assert_close(got, want[s], DOUBLE_TOLERANCE, f"{kernel.name} {output.name}")


def test_c_float_matches_numpy(gen):
    gen.builds["float_so"].check()
    lib = CLibrary(gen.root / "float" / "libkin.so", gen.robot, np.float32)
    q32 = gen.states.astype(np.float32)
    p32 = gen.p.astype(np.float32)
    for kernel in gen.kernels:
        expected = gen.numpy_outputs(kernel, q32.astype(float), p32.astype(float))
        batch = lib.batch(kernel, q32, p32)
        for got, want, output in zip(batch, expected, kernel.outputs, strict=True):
            assert got.dtype == np.float32
            assert_close(got, want, FLOAT_TOLERANCE, f"float {kernel.name}_batch {output.name}")
        for s, q in enumerate(q32[:5]):
            single = lib.single(kernel, q, p32)
            for got, want, output in zip(single, expected, kernel.outputs, strict=True):
                assert_close(got, want[s], FLOAT_TOLERANCE, f"float {kernel.name} {output.name}")


def test_float_code_is_float_throughout(gen):
    for suffix in (".c", ".h"):
        text = strip_comments(gen.float_files[f"c/{gen.name}{suffix}"])
        assert not re.search(r"\bdouble\b", text), f"{gen.name}{suffix} (float) mentions double"
        # double-precision math functions in float code promote to double
        calls = re.findall(r"\b(sin|cos|tan|sqrt|atan2|acos|asin|atan|pow|fabs)\(", text)
        assert not calls, f"{gen.name}{suffix} (float) calls double functions: {set(calls)}"
        literals = re.findall(r"(?<![\w.])\d+\.\d*(?:[eE][-+]?\d+)?(?![\w.])", text)
        assert not literals, f"{gen.name}{suffix} (float) has double literals: {literals[:5]}"


# ---------------------------------------------------------------- C executables


def parse_example(stdout: str) -> tuple[str, np.ndarray]:
    lines = stdout.strip().splitlines()
    assert len(lines) == 5, stdout
    return lines[0], np.array([[float(x) for x in line.split()] for line in lines[1:]])


def example_q(gen) -> np.ndarray:
    return np.round(0.1 * np.arange(1, gen.robot.dof + 1), 1)


def test_example_runs_under_sanitizers(gen):
    gen.builds["asan_example"].check()
    result = run(["./example_asan"], gen.c_dir("double"))
    assert result.returncode == 0, result.stderr
    header, T = parse_example(result.stdout)
    q = example_q(gen)
    assert header == f"T of {gen.name} at q = ({', '.join(map(str, q))}):"
    assert T.shape == (4, 4)
    np.testing.assert_allclose(T, gen.numpy.fk(q), rtol=0, atol=1e-6)


def test_float_example_runs(gen):
    gen.builds["float_example"].check()
    result = run(["./example"], gen.c_dir("float"))
    assert result.returncode == 0, result.stderr
    header, T = parse_example(result.stdout)
    q = example_q(gen)
    assert header == f"T of {gen.name} at q = ({', '.join(map(str, q))}):"
    np.testing.assert_allclose(T, gen.numpy.fk(q), rtol=0, atol=1e-5)


def test_every_kernel_under_sanitizers(gen):
    gen.builds["asan_driver"].check()
    result = run(["./driver_asan"], gen.c_dir("double"))
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr
    seen = set()
    states = gen.states[:3]
    for line in result.stdout.splitlines():
        words = line.split()
        if words[0] == "single":
            index, kernel_name, output_name, values = int(words[1]), *words[2:4], words[4:]
            q = states[index : index + 1]
        else:
            assert words[0] == "batch", line
            index, kernel_name, output_name, values = None, *words[1:3], words[3:]
            q = states
        kernel = next(k for k in gen.kernels if k.name == kernel_name)
        position = [o.name for o in kernel.outputs].index(output_name)
        expected = np.asarray(gen.numpy_outputs(kernel, q)[position]).reshape(len(q), -1)
        got = np.array([float(v) for v in values]).reshape(len(q), -1)
        assert_close(got, expected, DOUBLE_TOLERANCE, f"driver {line[:40]}")
        seen.add((words[0], kernel_name, output_name))
    expected_seen = {
        (kind, k.name, o.name)
        for k in gen.kernels
        for o in k.outputs
        for kind in ("single", "batch")
    }
    assert seen == expected_seen


def test_generated_makefile_builds_the_example(gen):
    gen.builds["make"].check()
    example = gen.root / "make" / "c" / "example"
    assert example.exists()
    result = run(["./example"], example.parent)
    assert result.returncode == 0, result.stderr
    _, T = parse_example(result.stdout)
    np.testing.assert_allclose(T, gen.numpy.fk(example_q(gen)), rtol=0, atol=1e-6)


# ---------------------------------------------------------------- C source rules


def test_c_compiles_without_vlas(gen):
    gen.builds["vla"].check()


@pytest.mark.parametrize("precision", ["double", "float"])
def test_c_has_no_allocation_globals_or_recursion(gen, precision):
    files = gen.files if precision == "double" else gen.float_files
    text = strip_comments(files[f"c/{gen.name}.c"])
    header = strip_comments(files[f"c/{gen.name}.h"])
    for source in (text, header):
        assert not re.search(r"\b(malloc|calloc|realloc|free|alloca)\b", source)
        # no static data: the word appears only in #define SYMKIN_API static (the C library)
        assert not re.search(r"^(?!#).*\bstatic\b", source, re.M)
    depth = 0
    for line in text.splitlines():
        stripped = line.strip()
        if depth == 0 and stripped and not stripped.startswith("#") and stripped != "{":
            # at file scope only functions (one line of signature; the symkin C library's are
            # declared first and static) and types are allowed
            function = r"void \w+\([^;]*\)|SYMKIN_API \w+ \w+\([^;]*\);?"
            assert re.fullmatch(rf"{function}|typedef .*", stripped), f"file-scope line: {line!r}"
        depth += line.count("{") - line.count("}")
        assert depth >= 0
    assert depth == 0
    bodies = function_bodies(text)
    every_kernel = robot_kernels(gen.model)
    expected = {f"{gen.name}_{k.name}{s}" for k in every_kernel for s in ("", "_batch")}
    expected.add(f"{gen.name}_forward_dynamics")  # composed from two kernels, no batch form
    expected |= {"symkin_cholesky_factor", "symkin_cholesky_solve"}  # the C library's, for it
    assert set(bodies) == expected
    # no cycles in the call graph among generated functions (no recursion, direct or not)
    calls = {
        f: {g for g in bodies if re.search(rf"\b{g}\s*\(", body)} for f, body in bodies.items()
    }
    for start in bodies:
        stack, reached = list(calls[start]), set()
        while stack:
            g = stack.pop()
            assert g != start, f"{start} is recursive"
            if g not in reached:
                reached.add(g)
                stack.extend(calls[g])


@pytest.mark.parametrize("precision", ["double", "float"])
def test_trig_of_an_argument_at_most_once_per_function(gen, precision):
    files = gen.files if precision == "double" else gen.float_files
    bodies = function_bodies(strip_comments(files[f"c/{gen.name}.c"]))
    assert bodies
    for name, body in bodies.items():
        calls = re.findall(r"\b((?:sin|cos)f?\([^()]*\))", body)
        repeated = {c for c in calls if calls.count(c) > 1}
        assert not repeated, f"{name} evaluates {sorted(repeated)} more than once"
        for i in range(1, gen.robot.dof + 1):
            for f in ("sin", "cos"):
                count = len(re.findall(rf"\b{f}f?\(q{i}\)", body))
                assert count <= 1, f"{name}: {f}(q{i}) {count} times"


# ---------------------------------------------------------------- CasADi


@pytest.fixture(scope="module")
def casadi_module(gen):
    path = gen.root / "double" / "casadi" / f"{gen.name}_casadi.py"
    return import_path(f"generated_{gen.name}_casadi", path)


def casadi_outputs(function, kernel: Kernel, q, p) -> tuple[np.ndarray, ...]:
    result = function(q, p)
    result = result if isinstance(result, tuple | list) else (result,)
    assert len(result) == len(kernel.outputs)
    return tuple(
        np.array(r.full()).reshape(numpy_shape(*o.shape))
        for r, o in zip(result, kernel.outputs, strict=True)
    )


def test_casadi_functions_match_numpy(gen, casadi_module):
    assert gen.robot.dof == casadi_module.DOF
    np.testing.assert_array_equal(np.asarray(casadi_module.DEFAULT_PARAMETERS, float), gen.p)
    for kernel in gen.kernels:
        function = getattr(casadi_module, f"{kernel.name}_function")()
        assert function.name_in() == ["q", "p"]
        assert function.name_out() == [o.name for o in kernel.outputs]
        for q in gen.states[:8]:
            got = casadi_outputs(function, kernel, q, gen.p)
            for a, b, o in zip(got, gen.numpy_outputs(kernel, q), kernel.outputs, strict=True):
                assert_close(a, b, DOUBLE_TOLERANCE, f"casadi {kernel.name} {o.name}")


def test_casadi_derivative_of_position_is_position_jacobian(gen, casadi_module):
    fk = casadi_module.fk_function()
    q = casadi.SX.sym("q", gen.robot.dof)
    T = fk(q, casadi.DM(list(gen.p)))
    derivative = casadi.Function("dp_dq", [q], [casadi.jacobian(T[0:3, 3], q)])
    for state in gen.states:
        got = np.array(derivative(state).full())
        assert_close(got, gen.reference("Jp", state), DOUBLE_TOLERANCE, "AD of fk position")


def test_casadi_code_generation_compiles_and_matches(gen, casadi_module, tmp_path):
    generator = casadi.CodeGenerator(f"{gen.name}_cg.c", {"with_header": True})
    functions = {k.name: getattr(casadi_module, f"{k.name}_function")() for k in gen.kernels}
    for function in functions.values():
        generator.add(function)
    generator.generate(f"{tmp_path}/")
    library = tmp_path / f"lib{gen.name}_cg.so"
    build = run([CC, "-O1", *SHARED, "-o", str(library), f"{gen.name}_cg.c", "-lm"], tmp_path)
    assert build.returncode == 0, build.stderr
    assert (tmp_path / f"{gen.name}_cg.h").exists()
    for kernel in gen.kernels:
        external = casadi.external(f"{gen.name}_{kernel.name}", str(library))
        for q in gen.states[:4]:
            got = casadi_outputs(external, kernel, q, gen.p)
            for a, b, o in zip(got, gen.numpy_outputs(kernel, q), kernel.outputs, strict=True):
                assert_close(a, b, DOUBLE_TOLERANCE, f"casadi codegen {kernel.name} {o.name}")


def test_tools_are_available():
    """The C tests need a C compiler and make; fail loudly rather than skip."""
    assert shutil.which(CC), CC
    assert shutil.which("make")


def test_title_that_closes_a_comment_still_builds(tmp_path):
    # The title is copied into the generated files' header comments: '*/' would end a C
    # comment, a triple quote the NumPy module's docstring, a backslash escape something.
    text = (
        'name = "odd"\n'
        'title = "arm */ int x; \\"\\"\\" \\\\N{oops} \\\\"\n'
        '[[joints]]\ntype = "revolute"\na = 1\n'
    )
    robot = symkin.robot_from_toml(text, "odd.toml")
    assert "*/" in robot.title and '"""' in robot.title and "\\" in robot.title
    write_tree(tmp_path, files_for_robot(robot, ("numpy", "c")))
    compiled = run([CC, *STRICT, "-fsyntax-only", "c/odd.c"], tmp_path)
    assert compiled.returncode == 0, compiled.stderr
    module = import_path("generated_odd_title", tmp_path / "numpy" / "odd_kinematics.py")
    np.testing.assert_allclose(module.position(np.array([0.0])).ravel()[:2], [1.0, 0.0])
