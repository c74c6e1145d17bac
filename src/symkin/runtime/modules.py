"""Generated NumPy and CasADi modules brought to life for the numeric solvers.

The kernels of a model are rendered by the emitters, written once into a directory this layer
owns (one per process, removed at exit) and imported through the import system, so tracebacks
and profilers see a real file and the library never ``exec``s a string.
"""

from __future__ import annotations

import atexit
import hashlib
import importlib.util
import os
import shutil
import tempfile
import threading
from collections.abc import Callable, Hashable
from functools import lru_cache
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING, TypeVar

from symkin.derive import Model
from symkin.errors import SymkinError

if TYPE_CHECKING:
    from symkin.kernels import Kernel

T = TypeVar("T")


# What the numeric solvers call, nothing more: the determinant, the singular set, the
# Christoffel C and every readable (contracted) form are left out, so an arm whose determinant
# takes minutes still gets its first IK answer in seconds.
KINDS = ("kinematics", "dynamics", "derivatives", "identification")
POSE_KERNELS = ("fk", "position", "fk_jacobian")


def generated_numpy_module(model: Model, kind: str = "dynamics") -> ModuleType:
    """The NumPy backend's ``kind`` kernels ("kinematics": ``fk``, ``position`` and
    ``fk_jacobian``; "dynamics": ``mass_matrix``, ``gravity``,
    ``coriolis``, ``inverse_dynamics``, ``forward_dynamics``; "derivatives": those and
    ``inverse_dynamics_derivatives``, ``jacobian_derivative``,
    ``forward_dynamics_derivatives``; "identification": ``regressor`` and
    ``base_regressor``) rendered and imported once per robot and process:
    the fast numeric path for solvers (IK, simulation, trajectories).

    They come from the model's product form (:attr:`Model.product_form`), the form code
    generation starts from, so a simplified model shares the module of its product form and
    nothing readable is derived for it.  The generated code is checked against the symbolic
    model in the test suite."""
    return remembered(model, ("numpy", kind), _generated_module, "numpy", kind)


def generated_casadi_module(model: Model, kind: str = "dynamics") -> ModuleType:
    """The CasADi backend's ``kind`` kernels, loaded the same way: ``fk_function``,
    ``forward_dynamics_function`` and the others build ``casadi.Function`` objects for
    optimisation (trajectories, IK through IPOPT)."""
    return remembered(model, ("casadi", kind), _generated_module, "casadi", kind)


def generated_point_module(
    model: Model, points: tuple[tuple[int, tuple[float, ...]], ...], backend: str = "numpy"
) -> ModuleType:
    """The NumPy (or, with ``backend="casadi"``, CasADi) kernels ``point1, point2, ...``
    (position, velocity and acceleration of each ``(link, (x, y, z))`` point), from the product
    form, built once per robot, point set and backend."""
    return remembered(model, ("points", points, backend), _point_module, points, backend)


# The modules of the models used last, by identity: hashing a model hashes its robot's every
# SymPy number, which for the PUMA takes three times as long as its fk_jacobian kernel.
_RECENT: dict[tuple[int, Hashable], tuple[Model, object]] = {}
_RECENT_SIZE = 64
_RECENT_LOCK = threading.Lock()


def remembered(model: Model, key: Hashable, build: Callable[..., T], *arguments: Hashable) -> T:
    """``build(model.product_form, *arguments)`` (a module, or any value ``build`` makes once
    per robot), looked up by the model's identity first and by its content (``build``'s own
    cache, shared by equal robots) after that.  Both caches are bounded, so a process that
    makes many models does not keep them all."""
    entry = _RECENT.get((id(model), key))
    if entry is not None and entry[0] is model:
        return entry[1]
    value = build(model.product_form, *arguments)
    with _RECENT_LOCK:  # threads may share a model; the oldest entry goes first
        if len(_RECENT) >= _RECENT_SIZE:
            del _RECENT[next(iter(_RECENT))]
        _RECENT[(id(model), key)] = (model, value)  # the model is kept: its id is not reused
    return value


@lru_cache(maxsize=32)
def _generated_module(model: Model, backend: str, kind: str) -> ModuleType:
    # Imported here, not at the top: ``import symkin`` should not load the code generators.
    from symkin.kernels import dynamics_kernels, pose_kernels, statics_kernels

    if kind not in KINDS:
        raise SymkinError(f"unknown kernel kind {kind!r}; expected one of {', '.join(KINDS)}")
    if kind == "kinematics":
        kernels = pose_kernels(model, POSE_KERNELS)
    elif kind == "identification":
        from symkin.kernels.regressor import identification_kernels

        kernels = identification_kernels(model)
    else:
        kernels = dynamics_kernels(model, coriolis_matrix=False) + statics_kernels(model)
    if kind == "derivatives":  # on request only: the derivatives cost more than tau
        from symkin.kernels.derivatives import derivative_kernels

        kernels += derivative_kernels(model)
    return _module_from_kernels(model, backend, kind, kernels)


@lru_cache(maxsize=32)
def _point_module(
    model: Model, points: tuple[tuple[int, tuple[float, ...]], ...], backend: str
) -> ModuleType:
    from symkin.kernels import point_kernels

    return _module_from_kernels(model, backend, "points", point_kernels(model, points))


def _module_from_kernels(
    model: Model, backend: str, kind: str, kernels: tuple[Kernel, ...]
) -> ModuleType:
    from symkin.emit.casadi import emit_casadi
    from symkin.emit.numpy import emit_numpy

    emit = {"numpy": emit_numpy, "casadi": emit_casadi}[backend]
    (source,) = emit(model.robot, kernels).values()
    return module_from_source(source, f"{model.robot.name}_{backend}_{kind}")


def module_from_source(source: str, stem: str) -> ModuleType:
    """Write generated Python ``source`` into this process's module directory and import it.

    The file is named by a hash of its text, so two models whose code is identical share
    one file, and a module name is never reused for different code.  Each writer writes a
    file of its own and renames it into place, so threads loading the same code never see a
    half-written file.  The module is not entered in ``sys.modules``: its functions are
    called, not pickled.
    """
    digest = hashlib.sha256(source.encode()).hexdigest()[:16]
    name = f"_symkin_{stem}_{digest}"
    path = module_directory() / f"{name}.py"
    if not path.exists():
        try:
            descriptor, staging = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
            with os.fdopen(descriptor, "w", encoding="utf-8") as file:
                file.write(source)
            os.replace(staging, path)
        except OSError as error:
            raise SymkinError(
                f"cannot write generated code to {path.parent} ({error.strerror}); "
                "set TMPDIR to a writable directory"
            ) from None
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:  # pragma: no cover - a .py path always has one
        raise SymkinError(f"cannot import the generated module {path}")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


_DIRECTORIES: dict[int, Path] = {}


def module_directory() -> Path:
    """A private directory for this process's generated modules, removed when it exits.

    Keyed by process: a forked child makes its own and never removes its parent's.
    """
    pid = os.getpid()
    directory = _DIRECTORIES.get(pid)
    if directory is None or not directory.is_dir():
        try:
            directory = Path(tempfile.mkdtemp(prefix="symkin-modules-"))
        except OSError as error:
            raise SymkinError(
                f"cannot create a directory for generated code in {tempfile.gettempdir()} "
                f"({error.strerror}); set TMPDIR to a writable directory"
            ) from None
        _DIRECTORIES[pid] = directory
        atexit.register(_remove, directory, pid)
    return directory


def _remove(directory: Path, pid: int) -> None:
    if os.getpid() == pid:
        shutil.rmtree(directory, ignore_errors=True)
