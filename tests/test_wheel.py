"""The built wheel works on its own: templates and robot files ship inside it.

The wheel is built from a copy of the project (so the working tree gets no build/ folder),
installed without dependencies into a fresh venv (no network needed: the dependencies come
from this venv's site-packages, appended after the new venv's own), and run from a folder
outside the project.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

import symkin
from codegen_helpers import ROOT

pytestmark = [pytest.mark.slow, pytest.mark.needs_cc]

PROJECT_FILES = ("pyproject.toml", "README.md", "LICENSE", "setup.cfg", "MANIFEST.in")
PROJECT_DIRS = ("src", "templates")


def run(command: list[str], cwd: Path, env: dict[str, str] | None = None, timeout: float = 300):
    result = subprocess.run(
        command, cwd=cwd, capture_output=True, text=True, env=env, timeout=timeout, check=False
    )
    assert result.returncode == 0, f"{command} failed:\n{result.stdout}\n{result.stderr}"
    return result


def build_wheel(tmp: Path) -> Path:
    source = tmp / "project"
    source.mkdir()
    for name in PROJECT_FILES:
        if (ROOT / name).exists():
            shutil.copy2(ROOT / name, source / name)
    ignore = shutil.ignore_patterns("__pycache__", "*.egg-info", "*.so", "build")
    for name in PROJECT_DIRS:
        shutil.copytree(ROOT / name, source / name, ignore=ignore)
    dist = tmp / "dist"
    pip_wheel = [sys.executable, "-m", "pip", "wheel", "--no-deps", "--quiet", "-w", str(dist)]
    try:  # offline first: build with this venv's setuptools
        run([*pip_wheel, "--no-build-isolation", str(source)], cwd=tmp)
    except AssertionError:  # this venv lacks a build requirement: isolated build from PyPI
        run([*pip_wheel, str(source)], cwd=tmp)
    wheels = sorted(dist.glob("symkin-*.whl"))
    assert len(wheels) == 1, wheels
    return wheels[0]


@pytest.fixture(scope="module")
def installed(tmp_path_factory) -> dict[str, Path]:
    tmp = tmp_path_factory.mktemp("wheel")
    wheel = build_wheel(tmp)
    venv = tmp / "venv"
    run([sys.executable, "-m", "venv", "--without-pip", str(venv)], cwd=tmp)
    python = venv / "bin" / "python"
    run(
        [sys.executable, "-m", "pip", "--python", str(python), "install", "--quiet",
         "--no-deps", "--no-index", str(wheel)],
        cwd=tmp,
    )  # fmt: skip
    # The dependencies (sympy, numpy, jinja2, casadi) from this venv, *after* the new
    # venv's own site-packages; .pth files there are not processed, so the editable
    # install of symkin stays invisible.
    site = Path(
        run([str(python), "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"], tmp)
        .stdout.strip()
    )  # fmt: skip
    (site / "outer_dependencies.pth").write_text(sysconfig.get_path("purelib") + "\n")
    work = tmp / "elsewhere"
    work.mkdir()
    return {"wheel": wheel, "venv": venv, "python": python, "site": site, "work": work}


def clean_env() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    env["PYTHONNOUSERSITE"] = "1"
    return env


def test_wheel_contains_templates_and_robot_files(installed):
    names = set(zipfile.ZipFile(installed["wheel"]).namelist())
    for template in ("c/source.c.j2", "c/header.h.j2", "c/example.c.j2", "c/Makefile.j2",
                     "numpy/module.py.j2", "casadi/module.py.j2"):  # fmt: skip
        assert f"symkin/templates/{template}" in names
    for name in symkin.catalogue_names():
        assert f"symkin/robots/{name}.toml" in names
    assert not any(n.startswith(("tests/", "generated/", "templates/")) for n in names)


def test_installed_package_is_the_wheel_not_the_source_tree(installed):
    code = (
        "import symkin, symkin.templates; from importlib import resources; "
        "print(symkin.__file__); print(resources.files('symkin.templates'))"
    )
    result = run([str(installed["python"]), "-c", code], installed["work"], clean_env())
    module, templates = result.stdout.split()
    assert Path(module).is_relative_to(installed["site"]), module
    assert Path(templates).is_relative_to(installed["site"]), templates
    assert str(ROOT) not in result.stdout


def test_installed_command_lists_the_catalogue(installed):
    symkin_command = installed["venv"] / "bin" / "symkin"
    assert symkin_command.exists()
    result = run([str(symkin_command), "list"], installed["work"], clean_env())
    listed = [line.split()[0] for line in result.stdout.splitlines() if line.strip()]
    assert listed == list(symkin.catalogue_names())


def test_installed_command_derives_outside_the_project(installed):
    out = installed["work"] / "out" / "scara"
    symkin_command = installed["venv"] / "bin" / "symkin"
    result = run(
        [str(symkin_command), "derive", "scara", "--out", "out/scara", "--emit", "numpy,c,casadi"],
        installed["work"],
        clean_env(),
    )
    assert "wrote" in result.stdout
    expected = ["c/Makefile", "c/example.c", "c/scara.c", "c/scara.h",
                "c/scara_ik.c", "c/scara_ik.h", "c/scara_ik_closed.c", "c/scara_ik_closed.h",
                "casadi/scara_casadi.py", "numpy/scara_kinematics.py"]  # fmt: skip
    written = sorted(p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file())
    assert written == [".symkin-files", *expected]  # the manifest of what derive wrote
    # the installed package renders exactly what the committed generated/ holds
    for relative in expected:
        committed = ROOT / "generated" / "scara" / relative
        assert (out / relative).read_bytes() == committed.read_bytes(), relative
