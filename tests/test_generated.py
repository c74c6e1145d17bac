"""The committed generated/ tree: up to date, deterministic, free of dates and paths; and the
``derive`` command's backend and precision options."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import symkin
from codegen_helpers import ROOT
from symkin.cli import main
from symkin.generate import BACKENDS

GENERATED = ROOT / "generated"
DETERMINISM_ROBOTS = ("scara", "rpr", "planar_3r")
SMALL_ROBOTS = ("scara", "rpr")
HEADER_LINES = 8

RENDER_DIGEST = """
import hashlib, sys
import symkin
from symkin.generate import files_for_robot
digest = hashlib.sha256()
for name in sys.argv[1:]:
    for precision in ("double", "float"):
        files = files_for_robot(symkin.load_robot(name), precision=precision)
        for path, text in files.items():
            digest.update(path.encode() + b"\\0" + text.encode() + b"\\0")
print(digest.hexdigest())
"""


def generated_files() -> list[Path]:
    return sorted(p for p in GENERATED.rglob("*") if p.is_file())


def test_generated_tree_has_every_catalogue_robot():
    robots = sorted(p.name for p in GENERATED.iterdir() if p.is_dir())
    assert robots == sorted(symkin.catalogue_names())
    for name in robots:
        relative = {p.relative_to(GENERATED / name).as_posix() for p in generated_files()
                    if p.is_relative_to(GENERATED / name)}  # fmt: skip
        assert relative >= {
            "c/Makefile",
            "c/example.c",
            f"c/{name}.c",
            f"c/{name}.h",
            f"casadi/{name}_casadi.py",
            f"numpy/{name}_kinematics.py",
        }


@pytest.mark.slow
def test_generate_check_passes_on_the_committed_tree(capsys):
    assert main(["generate", "--check", "--root", str(GENERATED)]) == 0
    assert "up to date" in capsys.readouterr().out


@pytest.fixture
def small_copy(tmp_path, monkeypatch) -> Path:
    """A copy of generated/ for two small robots, with the catalogue cut down to match."""
    import symkin.generate

    monkeypatch.setattr(symkin.generate, "catalogue_names", lambda: list(SMALL_ROBOTS))
    copy = tmp_path / "generated"
    for name in SMALL_ROBOTS:
        shutil.copytree(GENERATED / name, copy / name)
    return copy


def test_generate_check_passes_on_an_unchanged_copy(small_copy, capsys):
    assert main(["generate", "--check", "--root", str(small_copy)]) == 0
    assert "up to date" in capsys.readouterr().out


def test_generate_check_fails_with_a_diff_after_an_edit(small_copy, capsys):
    edited = small_copy / "scara" / "c" / "scara.c"
    lines = edited.read_text(encoding="utf-8").splitlines(keepends=True)
    index = next(i for i, line in enumerate(lines) if "T[0] =" in line)
    original = lines[index]
    lines[index] = "    T[0] = 42;\n"
    edited.write_text("".join(lines), encoding="utf-8")
    assert main(["generate", "--check", "--root", str(small_copy)]) == 2
    captured = capsys.readouterr()
    assert "--- scara/c/scara.c (on disk)" in captured.out
    assert "+++ scara/c/scara.c (fresh render)" in captured.out
    assert "\n-    T[0] = 42;\n" in captured.out
    assert f"\n+{original}" in captured.out
    assert "@@ " in captured.out
    assert "out of date" in captured.err
    # only the edited file differs, and the check did not rewrite it
    assert captured.out.count("(on disk)") == 1
    assert "T[0] = 42;" in edited.read_text(encoding="utf-8")


def test_generate_check_reports_extra_and_missing_files(small_copy, capsys):
    (small_copy / "rpr" / "numpy" / "rpr_kinematics.py").unlink()
    # A file of symkin's (in the manifest) that a fresh render no longer makes, and a file of
    # the user's (not in it): the first is reported, the second is none of symkin's business.
    manifest = small_copy / "rpr" / ".symkin-files"
    manifest.write_text(manifest.read_text(encoding="utf-8") + "c/old.c\n", encoding="utf-8")
    (small_copy / "rpr" / "c" / "old.c").write_text("left over\n", encoding="utf-8")
    (small_copy / "rpr" / "stray.txt").write_text("the user's\n", encoding="utf-8")
    assert main(["generate", "--check", "--root", str(small_copy)]) == 2
    out = capsys.readouterr().out
    assert "rpr/numpy/rpr_kinematics.py" in out
    assert "rpr/c/old.c" in out
    assert "stray.txt" not in out


def test_generate_deletes_only_its_own_stale_files(small_copy):
    manifest = small_copy / "rpr" / ".symkin-files"
    manifest.write_text(manifest.read_text(encoding="utf-8") + "c/old.c\n", encoding="utf-8")
    (small_copy / "rpr" / "c" / "old.c").write_text("left over\n", encoding="utf-8")
    notes = small_copy / "scara" / "notes.txt"  # the user's file in a robot folder
    notes.write_text("my notes\n", encoding="utf-8")
    assert main(["generate", "--root", str(small_copy)]) == 0
    assert not (small_copy / "rpr" / "c" / "old.c").exists()
    assert notes.read_text(encoding="utf-8") == "my notes\n"


def test_generate_never_follows_a_symlinked_robot_folder(small_copy, tmp_path, capsys):
    thesis = tmp_path / "thesis"
    thesis.mkdir()
    (thesis / "chapter1.tex").write_text("precious\n", encoding="utf-8")
    shutil.rmtree(small_copy / "rpr")
    (small_copy / "rpr").symlink_to(thesis, target_is_directory=True)
    assert main(["generate", "--root", str(small_copy)]) == 2
    assert "symbolic link" in capsys.readouterr().err
    assert sorted(p.name for p in thesis.iterdir()) == ["chapter1.tex"]
    assert (thesis / "chapter1.tex").read_text(encoding="utf-8") == "precious\n"


def test_generate_writes_what_check_accepts(small_copy, tmp_path):
    root = tmp_path / "fresh"
    assert main(["generate", "--root", str(root)]) == 0
    assert main(["generate", "--check", "--root", str(root)]) == 0
    for name in SMALL_ROBOTS:
        for path in (GENERATED / name).rglob("*"):
            if path.is_file():
                relative = path.relative_to(GENERATED)
                assert (root / relative).read_bytes() == path.read_bytes(), relative


@pytest.mark.slow
def test_rendering_is_independent_of_the_hash_seed():
    processes = [
        subprocess.Popen(
            [sys.executable, "-c", RENDER_DIGEST, *DETERMINISM_ROBOTS],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            env={**os.environ, "PYTHONHASHSEED": seed},
            cwd=ROOT,
        )
        for seed in ("1", "987654")
    ]
    digests = set()
    for process in processes:
        out, err = process.communicate(timeout=300)
        assert process.returncode == 0, err
        digests.add(out.strip())
    assert len(digests) == 1, digests


@pytest.mark.parametrize(
    "path", generated_files(), ids=lambda p: p.relative_to(GENERATED).as_posix()
)
def test_generated_file_has_no_dates_or_machine_paths(path):
    text = path.read_text(encoding="utf-8")
    assert not re.search(r"\b(19|20)\d\d-[01]\d-[0-3]\d\b", text), "date in generated file"
    assert not re.search(r"\b\d\d:\d\d:\d\d\b", text), "time of day in generated file"
    for fragment in ("/work", "/tmp", "/home", "/root", "/Users", "C:\\", str(ROOT)):
        assert fragment not in text, f"machine path {fragment!r} in generated file"
    assert "\r" not in text
    assert text.endswith("\n") and not text.endswith("\n\n\n")


def header_of(path: Path) -> str:
    return "\n".join(path.read_text(encoding="utf-8").splitlines()[:HEADER_LINES])


SUPPORT_FILES = ("example.c", "Makefile")  # written next to the kernels, not kernels themselves
MANIFEST = ".symkin-files"  # the list of what symkin wrote (docs/security.md)
KERNEL_FILES = [p for p in generated_files() if p.name not in (*SUPPORT_FILES, MANIFEST)]


@pytest.mark.parametrize("path", KERNEL_FILES, ids=lambda p: p.relative_to(GENERATED).as_posix())
def test_kernel_file_header_names_source_and_command(path):
    robot = path.relative_to(GENERATED).parts[0]
    header = header_of(path)
    assert f"Generated by symkin from robots/{robot}.toml; do not edit." in header
    assert "Regenerate with: symkin generate" in header


def test_example_and_makefile_headers_name_source_and_command():
    """example.c and Makefile are generated too: they say so, from what, and how to redo it."""
    missing = []
    for path in generated_files():
        if path.name in SUPPORT_FILES:
            robot = path.relative_to(GENERATED).parts[0]
            header = header_of(path)
            for needed in ("Generated by symkin", f"robots/{robot}.toml", "symkin generate"):
                if needed not in header:
                    missing.append(f"{path.relative_to(GENERATED)}: no {needed!r}")
    assert not missing, "\n".join(missing)


# ---------------------------------------------------------------- derive options


def test_manifest_lists_exactly_the_robot_folder_files():
    for name in symkin.catalogue_names():
        folder = GENERATED / name
        listed = (folder / MANIFEST).read_text(encoding="utf-8").splitlines()[1:]
        on_disk = sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file())
        assert listed == sorted(listed)
        assert set(on_disk) == {*listed, MANIFEST}


def test_derive_latex_backend_writes_only_the_document_files(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["derive", "scara", "--out", str(out), "--emit", "latex"]) == 0
    written = {p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file()}
    assert ".symkin-files" in written  # the manifest of what derive wrote
    written.remove(".symkin-files")
    assert "latex/scara.tex" in written
    assert all(path.startswith("latex/") for path in written)
    document = (out / "latex" / "scara.tex").read_text()
    assert "\\documentclass" in document and "\\end{document}" in document


def test_derive_with_an_unknown_backend_names_the_choices(tmp_path, capsys):
    assert main(["derive", "scara", "--out", str(tmp_path), "--emit", "fortran"]) == 2
    err = capsys.readouterr().err
    assert "'fortran'" in err
    for backend in BACKENDS:
        assert backend in err


def test_derive_emits_only_the_chosen_backend_in_float(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["derive", "scara", "--out", str(out), "--emit", "c", "--precision", "float"]) == 0
    written = sorted(p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file())
    assert written == [
        ".symkin-files",
        "c/Makefile",
        "c/example.c",
        "c/scara.c",
        "c/scara.h",
        "c/scara_ik.c",
        "c/scara_ik.h",
        "c/scara_ik_closed.c",
        "c/scara_ik_closed.h",
    ]
    source = (out / "c" / "scara.c").read_text(encoding="utf-8")
    header = (out / "c" / "scara.h").read_text(encoding="utf-8")
    assert "void scara_fk(const float q[3], const float *p, float T[SYMKIN_RESTRICT 16]);" in header
    assert "void scara_fk(const float q[3], const float *p, float T[restrict 16])" in source
    assert "C kinematics (float)" in source
    assert "sinf(" in source and "cosf(" in source
    assert not re.search(r"\bdouble\b", source)
    assert "{ 0.325F, 0.225F }" in header
    stdout = capsys.readouterr().out
    assert f"wrote 8 files to {out}/" in stdout


def test_derive_default_precision_is_double_and_matches_generated(tmp_path):
    out = tmp_path / "out"
    assert main(["derive", "scara", "--out", str(out)]) == 0
    for path in (GENERATED / "scara").rglob("*"):
        if path.is_file() and path.name != ".symkin-files":  # derive's also lists the build
            relative = path.relative_to(GENERATED / "scara")
            assert (out / relative).read_bytes() == path.read_bytes(), relative


def test_derive_rejects_an_unknown_precision(tmp_path):
    with pytest.raises(SystemExit) as raised:
        main(["derive", "scara", "--out", str(tmp_path), "--precision", "half"])
    assert raised.value.code == 2
