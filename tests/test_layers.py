"""The one-way layer contract (docs/architecture.md) and the size limits of the code.

The contract itself is import-linter's, configured in pyproject.toml and run by `make lint`;
these tests show that it holds on the tree and that it catches an upward import.
"""

from __future__ import annotations

import ast
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "symkin"
LINT_IMPORTS = Path(sys.executable).with_name("lint-imports")

#: Limits from the issue: a module over this many lines is split, a function over this many
#: lines gives its reason in a ``# long:`` comment above the def (complexity: ruff's C901).
MODULE_LINES = 600
FUNCTION_LINES = 60
REASONS = ("# long:",)


def _lint_imports(source_root: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [str(LINT_IMPORTS), "--config", str(ROOT / "pyproject.toml"), "--no-cache"],
        cwd=source_root,
        env={"PYTHONPATH": str(source_root), "PATH": "/usr/bin:/bin"},
        capture_output=True,
        text=True,
        check=False,
    )


def test_the_tree_keeps_the_layer_contract():
    result = _lint_imports(ROOT / "src")
    assert result.returncode == 0, result.stdout + result.stderr
    assert "KEPT" in result.stdout


@pytest.mark.parametrize(
    ("module", "upward"),
    [
        ("robot.py", "import symkin.cli"),  # ground reaching the front end
        ("derive/kinematics.py", "from symkin.emit import c"),  # derivation knowing a backend
        ("emit/c.py", "from symkin.solve import evaluate"),  # emitter reaching a solver
    ],
)
def test_an_upward_import_breaks_the_contract(tmp_path: Path, module: str, upward: str):
    copy = tmp_path / "symkin"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__"))
    target = copy / module
    # A lazy import inside a function counts too: that is how the old cycles hid.
    target.write_text(target.read_text() + f"\n\ndef _upward():\n    {upward}\n")
    result = _lint_imports(tmp_path)
    assert result.returncode != 0, result.stdout
    assert "BROKEN" in result.stdout


def _python_modules() -> list[Path]:
    return sorted(p for p in PACKAGE.rglob("*.py") if "__pycache__" not in p.parts)


def test_no_module_is_over_the_line_limit():
    long_modules = {
        str(p.relative_to(PACKAGE)): n
        for p in _python_modules()
        if (n := len(p.read_text().splitlines())) > MODULE_LINES
    }
    assert not long_modules, f"split these modules (lines): {long_modules}"


def _has_reason(lines: list[str], node: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    first = min([node.lineno, *(d.lineno for d in node.decorator_list)])
    index = first - 2
    while index >= 0 and lines[index].strip().startswith("#"):  # the comment block above
        if lines[index].strip().startswith(REASONS):
            return True
        index -= 1
    return False


def test_long_functions_give_their_reason():
    offenders = []
    for path in _python_modules():
        text = path.read_text()
        lines = text.splitlines()
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                length = (node.end_lineno or node.lineno) - node.lineno + 1
                if length > FUNCTION_LINES and not _has_reason(lines, node):
                    offenders.append(f"{path.relative_to(PACKAGE)}:{node.lineno} {node.name}")
    assert not offenders, "functions over 60 lines without a '# long:' reason: " + ", ".join(
        offenders
    )


def test_every_package_of_the_tree_is_listed_for_the_wheel():
    """pyproject.toml lists the packages by hand (templates are mapped in); a folder with an
    ``__init__.py`` missing from that list is left out of the wheel and breaks ``symkin``."""
    import tomllib

    setuptools = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    listed = set(setuptools["packages"])
    in_tree = {
        ".".join(init.parent.relative_to(PACKAGE.parent).parts)
        for init in PACKAGE.rglob("__init__.py")
    }
    assert in_tree - listed == set()
