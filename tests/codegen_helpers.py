"""Helpers for the generated-code tests: files on disk, imports, C builds and references."""

from __future__ import annotations

import ctypes
import importlib.util
import re
import shutil
import subprocess
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType

import numpy as np

import symkin
from symkin.derive.numeric import numeric_function
from symkin.kernels import Kernel

ROOT = Path(__file__).resolve().parents[1]
CC = shutil.which("gcc") or shutil.which("cc") or "gcc"
STRICT = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-O2"]
# Implicit narrowing and float-to-double promotion: the kernels and the numeric IK stay clean.
CONVERSION = ["-Wconversion", "-Wdouble-promotion"]
SHARED = ["-shared", "-fPIC"]
SANITIZE = ["-fsanitize=address,undefined", "-fno-sanitize-recover=all", "-g"]
GUARD = 4  # sentinel elements after every output array passed to C through ctypes


def write_tree(root: Path, files: dict[str, str]) -> None:
    for relative, text in files.items():
        path = root / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")


def import_path(name: str, path: Path) -> ModuleType:
    """Import a module from a file without touching ``sys.modules``."""
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@dataclass
class Build:
    """A finished command: its arguments, exit status and combined output."""

    command: list[str]
    returncode: int
    output: str

    def check(self) -> None:
        assert self.returncode == 0, f"{' '.join(self.command)} failed:\n{self.output}"


def run_parallel(commands: dict[str, list[str]], cwd: Path) -> dict[str, Build]:
    """Run independent commands (compiler calls) at the same time and collect them all."""
    processes = {
        key: subprocess.Popen(
            command, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True
        )
        for key, command in commands.items()
    }
    results = {}
    for key, process in processes.items():
        output, _ = process.communicate(timeout=300)
        results[key] = Build(commands[key], process.returncode, output)
    return results


def solver_library_command(
    c: Path, name: str, solver: str, library: str, extra: tuple[str, ...] = ()
) -> list[str]:
    """Strict C99 shared library of a generated solver (``<name>_<solver>.c``) and the robot's
    kernels (``<name>.c``), both in folder ``c``; ``extra`` warning flags."""
    return [
        CC, *STRICT, *extra, "-Wvla", *SHARED, "-o", str(c / library),
        str(c / f"{name}_{solver}.c"), str(c / f"{name}.c"), "-lm",
    ]  # fmt: skip


def sanitized_driver_command(c: Path, name: str, solver: str, driver: Path) -> list[str]:
    """A bench driver (``bench/ik_*_loop.c``) over a generated solver, built with AddressSanitizer
    and UBSan; the driver includes ``ROBOT_<SOLVER>_HEADER``."""
    return [
        CC, *STRICT, *SANITIZE, f"-DROBOT={name}", f"-DROBOT_MACRO={name.upper()}",
        f'-DROBOT_{solver.upper()}_HEADER="{name}_{solver}.h"', f"-I{c}", "-o", str(c / "driver"),
        str(driver), str(c / f"{name}_{solver}.c"), str(c / f"{name}.c"), "-lm",
    ]  # fmt: skip


def numpy_shape(rows: int, cols: int) -> tuple[int, ...]:
    """The documented NumPy output shape: (rows, cols), (rows,) for a column, () for 1x1."""
    if cols == 1:
        return () if rows == 1 else (rows,)
    return (rows, cols)


def random_states(robot: symkin.Robot, count: int, seed: int) -> np.ndarray:
    """Seeded joint values: angles in [-pi, pi], prismatic joints in [-1, 1] m."""
    rng = np.random.default_rng(seed)
    spans = np.array([np.pi if j.type == "revolute" else 1.0 for j in robot.joints])
    return rng.uniform(-1.0, 1.0, size=(count, robot.dof)) * spans


def parameters(robot: symkin.Robot) -> np.ndarray:
    return np.array([v for _, v in robot.parameters], dtype=float)


# Which symbolic quantity of the model each kernel output is.
REFERENCE_OUTPUTS = {
    "T": lambda model: model.forward_kinematics,
    "p_tool": lambda model: model.tool_position,
    "J": lambda model: model.geometric_jacobian,
    "Jp": lambda model: model.position_jacobian,
    "det": lambda model: model.determinant(),
    # Backend parity only; test_point_kernels.py checks it against sqrt(det(J J^T)).
    "mu": lambda model: model.manipulability(),
}


@dataclass
class Reference:
    """The reference evaluator for every output of every kernel, lambdified once."""

    model: symkin.Model
    functions: dict[str, object] = field(default_factory=dict)

    def __call__(self, output: str, q: np.ndarray) -> np.ndarray:
        if output == "mu" and self.model.determinant() is None:
            # A redundant arm: sqrt(det(J J^T)) of the task rows of the reference Jacobian.
            rows = ["x", "y", "z", "wx", "wy", "wz"]
            jacobian = self("J", q)[[rows.index(r) for r in self.model.task_rows]]
            return np.array(np.sqrt(np.linalg.det(jacobian @ jacobian.T)))
        if output not in self.functions:
            assert output in REFERENCE_OUTPUTS, f"no reference for kernel output {output!r}"
            expr = REFERENCE_OUTPUTS[output](self.model)
            self.functions[output] = numeric_function(self.model, expr)
        return self.functions[output](q)


def assert_close(actual, expected, tolerance: float, what: str) -> None:
    """``|actual - expected| <= tolerance * max(1, max |expected|)`` entry by entry."""
    actual = np.asarray(actual, dtype=float)
    expected = np.asarray(expected, dtype=float)
    assert actual.shape == expected.shape, f"{what}: shape {actual.shape} != {expected.shape}"
    scale = max(1.0, float(np.max(np.abs(expected), initial=0.0)))
    error = float(np.max(np.abs(actual - expected), initial=0.0))
    assert np.all(np.isfinite(actual)), f"{what}: non-finite values {actual}"
    assert error <= tolerance * scale, f"{what}: max error {error:.3g} > {tolerance * scale:.3g}"


def as_outputs(result, kernel: Kernel) -> tuple:
    """A NumPy/CasADi kernel's return value as a tuple, one entry per output."""
    return result if len(kernel.outputs) > 1 else (result,)


class CLibrary:
    """A compiled generated C file, called through ctypes with guarded output arrays."""

    def __init__(self, path: Path, robot: symkin.Robot, dtype: type) -> None:
        self.lib = ctypes.CDLL(str(path))
        self.robot = robot
        self.dtype = np.dtype(dtype)

    def _array(self, values) -> np.ndarray:
        return np.ascontiguousarray(values, dtype=self.dtype)

    def _function(self, name: str, outputs: int, batch: bool):
        function = getattr(self.lib, f"{self.robot.name}_{name}{'_batch' if batch else ''}")
        function.restype = None
        pointers = [ctypes.c_void_p] * (2 + outputs)
        function.argtypes = [ctypes.c_size_t, *pointers] if batch else pointers
        return function

    def _call(self, kernel: Kernel, q: np.ndarray, p: np.ndarray, count: int | None):
        q, p = self._array(q), self._array(p)
        sizes = [o.size * (count or 1) for o in kernel.outputs]
        buffers = [np.full(size + GUARD, np.nan, dtype=self.dtype) for size in sizes]
        function = self._function(kernel.name, len(sizes), count is not None)
        arguments = [q.ctypes.data_as(ctypes.c_void_p), p.ctypes.data_as(ctypes.c_void_p)]
        arguments += [b.ctypes.data_as(ctypes.c_void_p) for b in buffers]
        function(*([ctypes.c_size_t(count)] if count is not None else []), *arguments)
        results = []
        for output, size, buffer in zip(kernel.outputs, sizes, buffers, strict=True):
            assert np.all(np.isnan(buffer[size:])), f"{kernel.name}: wrote past {output.name}"
            assert not np.any(np.isnan(buffer[:size])), f"{kernel.name}: {output.name} not filled"
            shape = numpy_shape(*output.shape)
            results.append(buffer[:size].reshape(((count,) if count else ()) + shape))
        return tuple(results)

    def single(self, kernel: Kernel, q, p) -> tuple[np.ndarray, ...]:
        return self._call(kernel, q, p, None)

    def batch(self, kernel: Kernel, q, p) -> tuple[np.ndarray, ...]:
        q = self._array(q)
        return self._call(kernel, q, p, q.shape[0])


def c_driver(robot: symkin.Robot, kernels: tuple[Kernel, ...], states: np.ndarray) -> str:
    """A C program calling every kernel once per state and once batched, on exact-size heap
    buffers (so the sanitizers see any out-of-bounds access), printing every output."""
    name, macro, n = robot.name, robot.name.upper(), robot.dof
    count = len(states)
    values = ", ".join(repr(float(v)) for v in states.ravel())
    lines = [
        "#include <stdio.h>",
        "#include <stdlib.h>",
        "#include <string.h>",
        f'#include "{name}.h"',
        "",
        "static void show(const char *what, const double *x, size_t size)",
        "{",
        "    size_t i;",
        '    printf("%s", what);',
        '    for (i = 0; i < size; ++i) printf(" %.17g", x[i]);',
        '    printf("\\n");',
        "}",
        "",
        "int main(void)",
        "{",
        f"    static const double states[{count * n}] = {{ {values} }};",
        f"    static const double defaults[] = {macro}_DEFAULT_PARAMETERS;",
        f"    double *p = malloc(sizeof(double) * {macro}_NUM_PARAMETERS + 1);",
        f"    double *q = malloc(sizeof(double) * {n});",
        f"    double *qs = malloc(sizeof(double) * {count * n});",
        "    size_t s;",
        f"    if (sizeof defaults / sizeof defaults[0] != {macro}_NUM_PARAMETERS) return 3;",
        f"    if ({macro}_DOF != {n}) return 4;",
        "    if (!p || !q || !qs) return 5;",
        f"    memcpy(p, defaults, sizeof(double) * {macro}_NUM_PARAMETERS);",
        f"    memcpy(qs, states, sizeof(double) * {count * n});",
    ]
    for kernel in kernels:
        outs = [(o.name, o.size) for o in kernel.outputs]
        lines.append("    {")
        for out, size in outs:
            lines.append(f"        double *{out} = malloc(sizeof(double) * {size});")
            lines.append(f"        double *{out}_b = malloc(sizeof(double) * {size * count});")
        lines.append(f"        for (s = 0; s < {count}; ++s) {{")
        lines.append(f"            memcpy(q, states + s * {n}, sizeof(double) * {n});")
        lines.append(f"            {name}_{kernel.name}(q, p, {', '.join(o for o, _ in outs)});")
        for out, size in outs:
            lines.append(
                f'            printf("single %u ", (unsigned)s); show("{kernel.name} '
                f'{out}", {out}, {size});'
            )
        lines.append("        }")
        batch_outs = ", ".join(f"{o}_b" for o, _ in outs)
        lines.append(f"        {name}_{kernel.name}_batch({count}, qs, p, {batch_outs});")
        for out, size in outs:
            lines.append(f'        show("batch {kernel.name} {out}", {out}_b, {size * count});')
        for out, _ in outs:
            lines.append(f"        free({out}); free({out}_b);")
        lines.append("    }")
    lines += ["    free(p); free(q); free(qs);", "    return 0;", "}", ""]
    return "\n".join(lines)


def function_bodies(c_text: str) -> dict[str, str]:
    """``{function name: body}`` of the top-level function definitions in generated C."""
    pattern = re.compile(r"^\w[\w ]*?\b(\w+)\([^;{]*\)\s*\n\{\n(.*?)^\}", re.M | re.S)
    return {m.group(1): m.group(2) for m in pattern.finditer(c_text)}


def strip_comments(c_text: str) -> str:
    return re.sub(r"/\*.*?\*/", "", c_text, flags=re.S)
