"""The generated C IK solver brought to Python: a CPython extension built once per robot and
process.

The extension binds ``fk_jacobian`` and the damped-least-squares solver ``<robot>_ik``
(``emit/ik_c.py``) as ``fk_jacobian(q, p)`` and ``ik(...)`` (``templates/python/
ik_binding.c.j2``).  It is compiled by :func:`symkin.runtime.extension.build_extension` (the
compiler named by ``CC``, else ``cc``) in this process's private module directory and loaded
from there.  A robot whose build fails (no compiler, a compile error) is remembered as failed,
so the caller falls back to NumPy without trying again.
"""

from __future__ import annotations

import hashlib
import os
import threading
from functools import lru_cache
from types import ModuleType

from symkin.derive import Model
from symkin.errors import SymkinError
from symkin.runtime.extension import build_extension, load_extension
from symkin.runtime.modules import module_directory, remembered

# One build at a time: two threads asking for the same robot must not compile into the same
# folder at once (the second finds the first's result in the cache).
_LOCK = threading.Lock()


def _unlocked_after_fork() -> None:
    """A child forked while another thread compiles would inherit ``_LOCK`` held, by a thread
    that does not exist in the child, and wait on it forever; it gets a fresh lock instead."""
    global _LOCK
    _LOCK = threading.Lock()


os.register_at_fork(after_in_child=_unlocked_after_fork)


def ik_extension(model: Model) -> ModuleType:
    """The compiled ``fk_jacobian`` and ``ik`` of ``model``'s robot (double precision).

    Raises :class:`~symkin.errors.SymkinError` when the extension cannot be built; the failure
    is remembered for the process, like the module.
    """
    with _LOCK:
        built = remembered(model, "ik_extension", _build)
    if isinstance(built, SymkinError):
        raise built
    return built


@lru_cache(maxsize=32)
def _build(model: Model) -> ModuleType | SymkinError:
    """Render, compile and import the extension; the error instead when that fails."""
    # Imported here, not at the top: ``import symkin`` should not load the code generators.
    from symkin.emit.c import emit_c
    from symkin.emit.ik_c import emit_ik_c
    from symkin.emit.python_ext import emit_python_extension
    from symkin.kernels import pose_kernels

    robot = model.robot
    kernels = pose_kernels(model, ("fk_jacobian",))
    files = {
        **emit_c(robot, kernels),
        **emit_ik_c(robot, kernels),
        **emit_python_extension(robot, kernels, ik=True),
    }
    digest = hashlib.sha256("\0".join(f"{k}\0{v}" for k, v in sorted(files.items())).encode())
    folder = module_directory() / f"ext_{robot.name}_{digest.hexdigest()[:16]}"
    try:
        for relative in ("c/", "python/"):
            (folder / relative).mkdir(parents=True, exist_ok=True)
        for relative in (f"c/{robot.name}.h", f"c/{robot.name}_ik.h"):
            (folder / relative).write_text(files[relative], encoding="utf-8")
        sources = [f"python/{robot.name}_ext.c", f"c/{robot.name}.c", f"c/{robot.name}_ik.c"]
        for relative in sources:
            (folder / relative).write_text(files[relative], encoding="utf-8")
        return load_extension(build_extension(*(folder / s for s in sources)))
    except SymkinError as error:
        return error
    except (OSError, ImportError) as error:
        return SymkinError(f"cannot build the IK extension in {folder}: {error}")
