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
from functools import lru_cache
from pathlib import Path
from types import ModuleType

from symkin.derive import Model
from symkin.errors import SymkinError


@lru_cache(maxsize=16)
def generated_numpy_module(model: Model, kind: str = "dynamics") -> ModuleType:
    """The NumPy backend's ``kind`` kernels ("kinematics" or "dynamics") rendered and imported
    once per model: the fast numeric path for solvers (IK, simulation, trajectories).
    The generated code is checked against the symbolic model in the test suite."""
    return _generated_module(model, "numpy", kind)


@lru_cache(maxsize=16)
def generated_casadi_module(model: Model, kind: str = "dynamics") -> ModuleType:
    """The CasADi backend's ``kind`` kernels, loaded the same way: ``fk_function``,
    ``forward_dynamics_function`` and the others build ``casadi.Function`` objects for
    optimisation (trajectories, IK through IPOPT)."""
    return _generated_module(model, "casadi", kind)


def _generated_module(model: Model, backend: str, kind: str) -> ModuleType:
    # Imported here, not at the top: ``import symkin`` should not load the code generators.
    from symkin.emit.casadi import emit_casadi
    from symkin.emit.numpy import emit_numpy
    from symkin.kernels import dynamics_kernels, kinematics_kernels

    kernels = {"kinematics": kinematics_kernels, "dynamics": dynamics_kernels}
    if kind not in kernels:
        raise SymkinError(f"unknown kernel kind {kind!r}; expected one of {', '.join(kernels)}")
    emit = {"numpy": emit_numpy, "casadi": emit_casadi}[backend]
    (source,) = emit(model.robot, kernels[kind](model)).values()
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
    path = _module_directory() / f"{name}.py"
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


def _module_directory() -> Path:
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
