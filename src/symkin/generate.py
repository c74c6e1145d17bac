"""Robot -> kernels -> backends -> files, or a comparison with files on disk (``--check``).

Only this module and the command line write files, all through
:func:`symkin.output_folder.write_folder`.  Output is deterministic: the same robot
gives byte-identical text on every machine and under every ``PYTHONHASHSEED``.
"""

from __future__ import annotations

import difflib
import functools
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path, PurePosixPath

from symkin.derive import Model, derive
from symkin.derive.budget import DEFAULT_BUDGET_SECONDS
from symkin.emit.c import PRECISIONS, emit_c
from symkin.emit.casadi import emit_casadi
from symkin.emit.ik_c import emit_ik_c
from symkin.emit.ik_closed_c import emit_ik_closed_c
from symkin.emit.latex import latex_files
from symkin.emit.numpy import emit_numpy
from symkin.emit.python_ext import emit_python_extension
from symkin.errors import ParameterError, literal
from symkin.io import catalogue_names, load_robot
from symkin.kernels import (
    Kernel,
    dynamics_kernels,
    kinematics_kernels,
    point_kernels,
    statics_kernels,
)
from symkin.kernels.derivatives import derivative_kernels
from symkin.kernels.regressor import barycentric_kernels, identification_kernels
from symkin.output_folder import (
    check_no_symlink,
    manifest_name,
    manifest_text,
    read_manifest,
    write_folder,
)
from symkin.progress import phase
from symkin.robot import Robot

# "python" is the CPython binding of the C kernels; it needs the "c" files beside it.
BACKENDS = ("numpy", "c", "python", "casadi")
# On request only: the derivation document is slow for 6-DOF arms and not code.
OPTIONAL_BACKENDS = ("latex",)


def check_backends(backends: Iterable[str]) -> tuple[str, ...]:
    """Validate backend names (blank ones are dropped, repeats kept once, order kept)."""
    chosen = tuple(dict.fromkeys(n.strip() for n in backends if n.strip()))
    for name in chosen:
        if name not in BACKENDS + OPTIONAL_BACKENDS:
            choices = ", ".join(BACKENDS + OPTIONAL_BACKENDS)
            raise ParameterError(
                f"{{backends}}: unknown backend {literal(repr(name))}; choose from {choices}"
            )
    if not chosen:
        raise ParameterError(f"{{backends}}: name at least one backend of {', '.join(BACKENDS)}")
    return chosen


def robot_kernels(
    model: Model, dynamics: bool = True, derivatives: bool = False
) -> tuple[Kernel, ...]:
    """Every kernel generated for a robot: kinematics, then dynamics unless ``dynamics`` is
    false, then the derivative kernels when ``derivatives`` is true (on request: they cost
    more than the dynamics; see :mod:`symkin.kernels.derivatives`)."""
    with phase("the kinematics kernels (CSE and rewrite passes)"):
        kinematics = kinematics_kernels(model)
    if not dynamics:
        return kinematics
    with phase("the dynamics kernels (CSE and rewrite passes)"):
        kernels = kinematics + dynamics_kernels(model) + statics_kernels(model)
    if not derivatives:
        return kernels
    with phase("the derivative kernels (tangent sweeps, CSE and rewrite passes)"):
        return kernels + derivative_kernels(model)


def files_for_robot(
    robot: Robot,
    backends: Sequence[str] = BACKENDS,
    precision: str = "double",
    points: Sequence[tuple[int, Sequence[float]]] = (),
    flags: Sequence[str] = (),
    *,
    budget: float | None = DEFAULT_BUDGET_SECONDS,
    closed_forms: bool = True,
    dynamics: bool = True,
    derivatives: bool = False,
    regressor: bool = False,
) -> dict[str, str]:
    """``{relative path: text}`` of every chosen backend for one robot.

    ``flags``: the front end's options that made the files, as it spells them; every file's
    "Regenerate with" line ends with them (``--precision float --numeric-parameters``).
    ``budget`` and ``closed_forms`` as for :func:`~symkin.derive.derive` (without a closed
    form, ``det`` and ``manipulability`` are computed numerically from the Jacobian);
    ``dynamics=False`` leaves the dynamics kernels out; ``derivatives=True`` adds the
    derivative kernels (and the forward dynamics' derivatives) to them; ``regressor=True``
    adds the identification kernels ``regressor`` and ``base_regressor`` and the dynamics of
    their parameters, ``mass_matrix_barycentric`` and ``inverse_dynamics_barycentric``
    (opt-in: they cost derivation time no other kernel needs).
    """
    if precision not in PRECISIONS:
        raise ParameterError(
            f"{{precision}} must be one of {', '.join(PRECISIONS)}, got {literal(repr(precision))}"
        )

    # Only the code backends need kernels; a LaTeX-only request should not pay for them.
    model = derive(robot, budget, closed_forms)

    def all_kernels() -> tuple[Kernel, ...]:
        extra = identification_kernels(model) + barycentric_kernels(model) if regressor else ()
        return robot_kernels(model, dynamics, derivatives) + point_kernels(model, points) + extra

    kernels = functools.cache(all_kernels)
    # "c" and "python" both need the C files: print them once.
    c_files = functools.cache(lambda: emit_c(robot, kernels(), precision, flags))

    emitters: dict[str, Callable[[], dict[str, str]]] = {
        "numpy": lambda: emit_numpy(robot, kernels(), flags),
        "c": lambda: {
            **c_files(),
            **emit_ik_c(robot, kernels(), precision, flags),
            **emit_ik_closed_c(robot, kernels(), precision, flags),
        },
        "python": lambda: {
            **c_files(),
            **emit_python_extension(robot, kernels(), precision, flags),
        },
        "casadi": lambda: emit_casadi(robot, kernels(), flags),
        "latex": lambda: {f"latex/{p}": t for p, t in latex_files(model).items()},
    }
    files: dict[str, str] = {}
    for backend in check_backends(backends):
        with phase(f"the {backend} files"):
            files.update(emitters[backend]())
    return dict(sorted(files.items()))


def _read_text(path: Path) -> str:
    try:
        return path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        return f"(binary file {path.name}, not generated by symkin)\n"


def difference(root: Path, files: dict[str, str]) -> str:
    """Unified diff between ``files`` (and their manifest) and what symkin wrote under ``root``.

    Files the manifest does not list are the user's and are not compared; a manifest marked
    incomplete (an interrupted run) shows as a difference.
    """
    manifest = manifest_name()
    listed, complete = read_manifest(root, manifest)
    expected = {**files, manifest: manifest_text(files)}
    on_disk = {r for r in listed | {manifest} if (root / r).is_file()}
    chunks = [] if complete else [f"{root.name}/{manifest}: a run stopped while writing\n"]
    for relative in sorted(on_disk | set(expected)):
        path = root / relative
        old = _read_text(path) if relative in on_disk else ""
        new = expected.get(relative, "")
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

    Each robot folder is written by :func:`~symkin.output_folder.write_folder`: a symlinked folder
    is refused, and only files of the folder's manifest are ever deleted.

        Returns the unified diff of what differs (empty when all is up to date or was written).
    """
    diffs = []
    for name in catalogue_names():
        progress(name)
        files = files_for_robot(load_robot(name))
        if check:
            check_no_symlink(root, PurePosixPath(name, "x"))
            diffs.append(difference(root / name, files))
        else:
            write_folder(root / name, files)
    return "".join(diffs)
