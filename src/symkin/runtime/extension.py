"""Compile a generated CPython extension with the system C compiler and load it.

This is the one place symkin runs a compiler for users (``symkin derive`` with the C backend).
"""

from __future__ import annotations

import importlib.util
import os
import shlex
import shutil
import subprocess
import sysconfig
from pathlib import Path
from types import ModuleType

import numpy as np

from symkin.errors import SymkinError

OPTIMISATION_FLAGS = ("-O2",)


def extension_path(source: Path) -> Path:
    """``<robot>_ext.cpython-311-x86_64-linux-gnu.so`` beside the source."""
    return source.with_name(source.stem + sysconfig.get_config_var("EXT_SUFFIX"))


def build_extension(source: Path, kernels_source: Path, *more_sources: Path) -> Path:
    """Compile ``python/<robot>_ext.c`` with ``c/<robot>.c`` (and ``more_sources``, e.g.
    ``c/<robot>_ik.c``) into an importable module."""
    compiler = shlex.split(os.environ.get("CC", "")) or [shutil.which("cc") or "gcc"]
    if shutil.which(compiler[0]) is None:
        raise SymkinError(f"no C compiler found ({compiler[0]!r}); install gcc or set CC")
    target = extension_path(source)
    command = [
        *compiler,
        *OPTIMISATION_FLAGS,
        "-shared",
        "-fPIC",
        f"-I{sysconfig.get_paths()['include']}",
        f"-I{np.get_include()}",
        str(source),
        str(kernels_source),
        *map(str, more_sources),
        "-o",
        str(target),
        "-lm",
    ]
    try:
        completed = subprocess.run(command, capture_output=True, text=True, check=False)
    except OSError as error:
        raise SymkinError(f"cannot run the C compiler {compiler[0]!r}: {error}") from None
    if completed.returncode != 0:
        first_lines = "\n".join(completed.stderr.splitlines()[:15])
        raise SymkinError(f"compiling {source.name} failed:\n{first_lines}")
    return target


def load_extension(path: Path | str) -> ModuleType:
    """Import a compiled extension from its file."""
    path = Path(path)
    name = path.name.split(".")[0]
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise SymkinError(f"cannot load {path}")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
