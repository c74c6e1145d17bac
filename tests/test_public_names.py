"""The public names of ``symkin`` (``__all__``), imported on first use (PEP 562)."""

from __future__ import annotations

import importlib
import subprocess
import sys

import symkin


def test_every_public_name_resolves_to_its_module_object() -> None:
    for name in symkin.__all__:
        value = getattr(symkin, name)
        module = importlib.import_module(value.__module__)
        # The object itself, not a copy: a class or function of the module that defines it.
        assert getattr(module, value.__name__) is value, name
    assert sorted(symkin.__all__) == sorted(set(symkin.__all__))
    assert set(symkin.__all__) <= set(dir(symkin))


def test_unknown_name_raises_attribute_error() -> None:
    try:
        symkin.no_such_name  # noqa: B018
    except AttributeError as error:
        assert "no_such_name" in str(error)
    else:  # pragma: no cover - the assertion below reports it
        raise AssertionError("symkin.no_such_name did not raise AttributeError")


def _fresh(code: str) -> str:
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120
    )
    return done.stdout.strip()


def test_the_command_line_does_not_import_scipy() -> None:
    # SciPy's integrators cost half a second of every command's start (issue 15: a warm
    # command under 1 s); only the commands that integrate import them.
    assert _fresh("import sys, symkin.cli; print('scipy' in sys.modules)") == "False"


def test_derive_stays_the_function_after_its_subpackage_is_imported() -> None:
    code = (
        "import symkin, symkin.derive.kinematics, symkin.solve.evaluate; "
        "print(callable(symkin.derive), symkin.kinematic_state.__name__)"
    )
    assert _fresh(code) == "True kinematic_state"
