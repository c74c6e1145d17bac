"""Robot -> kernels -> backends -> files, or a comparison with files on disk (``--check``).

Only this module and the command line write files.  Output is deterministic: the same robot
gives byte-identical text on every machine and under every ``PYTHONHASHSEED``.
"""

from __future__ import annotations

import difflib
import functools
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path

from symkin.derive import Model, derive
from symkin.emit.c import PRECISIONS, emit_c
from symkin.emit.casadi import emit_casadi
from symkin.emit.latex import latex_files
from symkin.emit.numpy import emit_numpy
from symkin.emit.python_ext import emit_python_extension
from symkin.errors import SymkinError
from symkin.io import catalogue_names, load_robot
from symkin.kernel import Kernel, dynamics_kernels, kinematics_kernels, point_kernels
from symkin.robot import Robot

# "python" is the CPython binding of the C kernels; it needs the "c" files beside it.
BACKENDS = ("numpy", "c", "python", "casadi")
# On request only: the derivation document is slow for 6-DOF arms and not code.
OPTIONAL_BACKENDS = ("latex",)


def check_backends(names: Iterable[str]) -> tuple[str, ...]:
    """Validate backend names from the command line."""
    chosen = tuple(dict.fromkeys(n.strip() for n in names if n.strip()))
    for name in chosen:
        if name not in BACKENDS + OPTIONAL_BACKENDS:
            choices = ", ".join(BACKENDS + OPTIONAL_BACKENDS)
            raise SymkinError(f"--emit: unknown backend {name!r}; choose from {choices}")
    if not chosen:
        raise SymkinError(f"--emit: name at least one backend of {', '.join(BACKENDS)}")
    return chosen


def robot_kernels(model: Model) -> tuple[Kernel, ...]:
    """Every kernel generated for a robot: kinematics, then dynamics."""
    return kinematics_kernels(model) + dynamics_kernels(model)


def files_for_robot(
    robot: Robot,
    backends: Sequence[str] = BACKENDS,
    precision: str = "double",
    points: Sequence[tuple[int, Sequence[float]]] = (),
) -> dict[str, str]:
    """``{relative path: text}`` of every chosen backend for one robot."""
    if precision not in PRECISIONS:
        raise SymkinError(f"--precision must be one of {', '.join(PRECISIONS)}, got {precision!r}")
    # Only the code backends need kernels; a LaTeX-only request should not pay for them.
    kernels = functools.cache(
        lambda: robot_kernels(derive(robot)) + point_kernels(derive(robot), points)
    )
    emitters: dict[str, Callable[[], dict[str, str]]] = {
        "numpy": lambda: emit_numpy(robot, kernels()),
        "c": lambda: emit_c(robot, kernels(), precision),
        "python": lambda: {
            **emit_c(robot, kernels(), precision),
            **emit_python_extension(robot, kernels(), precision),
        },
        "casadi": lambda: emit_casadi(robot, kernels()),
        "latex": lambda: {f"latex/{p}": t for p, t in latex_files(derive(robot)).items()},
    }
    files: dict[str, str] = {}
    for backend in check_backends(backends):
        files.update(emitters[backend]())
    return dict(sorted(files.items()))


def write_files(root: Path, files: dict[str, str]) -> None:
    for relative, text in files.items():
        path = root / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")


def difference(root: Path, files: dict[str, str]) -> str:
    """Unified diff between ``files`` and what is under ``root`` (extra files included)."""
    chunks = []
    on_disk = {p.relative_to(root).as_posix() for p in root.rglob("*") if p.is_file()}
    for relative in sorted(on_disk | set(files)):
        path = root / relative
        old = path.read_text(encoding="utf-8") if relative in on_disk else ""
        new = files.get(relative, "")
        if old != new:
            chunks.extend(
                difflib.unified_diff(
                    old.splitlines(keepends=True),
                    new.splitlines(keepends=True),
                    fromfile=f"{root.name}/{relative} (on disk)",
                    tofile=f"{root.name}/{relative} (fresh render)",
                )
            )
    return "".join(chunks)


def generate_catalogue(
    root: Path, check: bool = False, progress: Callable[[str], None] = lambda _: None
) -> str:
    """Render every catalogue robot into ``root/<robot>/``; with ``check``, only compare.

    Returns the unified diff of what differs (empty when all is up to date or was written).
    """
    diffs = []
    for name in catalogue_names():
        progress(name)
        files = files_for_robot(load_robot(name))
        if check:
            diffs.append(difference(root / name, files))
        else:
            write_files(root / name, files)
    return "".join(diffs)
