"""The one writer of output folders (symkin.output_folder): links, manifests, interruptions.

Each test plants what the fuzzing run planted (a symlink where a file goes, a symlinked
folder, a user's file) or interrupts a run, and checks the files on disk afterwards.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

import symkin.output_folder as output_folder
from symkin.cli import main
from symkin.errors import SymkinError
from symkin.output_folder import read_manifest, write_folder

FILES = {"c/arm.c": "int x;\n", "c/arm.h": "extern int x;\n", "numpy/arm.py": "X = 1\n"}


def tree(root: Path) -> dict[str, str]:
    """Every file under ``root`` (links not followed) with its text, links as ``-> target``."""
    found = {}
    for path in sorted(root.rglob("*")):
        relative = path.relative_to(root).as_posix()
        if path.is_symlink():
            found[relative] = f"-> {os.readlink(path)}"
        elif path.is_file():
            found[relative] = path.read_text(encoding="utf-8")
    return found


def test_writes_the_files_and_a_manifest_of_them(tmp_path):
    write_folder(tmp_path / "out", FILES)
    assert tree(tmp_path / "out") == {
        **FILES,
        ".symkin-files": "\n".join([output_folder.MANIFEST_HEADER, *sorted(FILES)]) + "\n",
    }
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no staging left


def test_a_link_planted_at_a_file_is_replaced_and_its_target_untouched(tmp_path):
    secret = tmp_path / "secret.txt"
    secret.write_text("precious\n", encoding="utf-8")
    out = tmp_path / "out"
    write_folder(out, FILES)
    (out / "c" / "arm.c").unlink()
    (out / "c" / "arm.c").symlink_to(secret)
    (out / "mine.txt").write_text("the user's\n", encoding="utf-8")  # forces file-by-file
    write_folder(out, FILES)
    assert secret.read_text(encoding="utf-8") == "precious\n"
    assert not (out / "c" / "arm.c").is_symlink()
    assert (out / "c" / "arm.c").read_text(encoding="utf-8") == FILES["c/arm.c"]


def test_a_symlinked_folder_inside_the_output_is_refused(tmp_path):
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    out = tmp_path / "out"
    out.mkdir()
    (out / "c").symlink_to(elsewhere, target_is_directory=True)
    with pytest.raises(SymkinError, match="symbolic link"):
        write_folder(out, FILES)
    assert list(elsewhere.iterdir()) == []


def test_a_symlinked_output_folder_is_refused(tmp_path):
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "thesis.tex").write_text("chapter 1\n", encoding="utf-8")
    (tmp_path / "out").symlink_to(elsewhere, target_is_directory=True)
    with pytest.raises(SymkinError, match="symbolic link"):
        write_folder(tmp_path / "out", FILES)
    assert tree(elsewhere) == {"thesis.tex": "chapter 1\n"}


def test_only_files_of_the_manifest_are_deleted(tmp_path):
    out = tmp_path / "out"
    write_folder(out, FILES)
    (out / "c" / "notes.txt").write_text("mine\n", encoding="utf-8")
    write_folder(out, {"numpy/arm.py": "X = 2\n"})
    assert tree(out) == {
        ".symkin-files": f"{output_folder.MANIFEST_HEADER}\nnumpy/arm.py\n",
        "c/notes.txt": "mine\n",
        "numpy/arm.py": "X = 2\n",
    }


def test_an_emptied_folder_of_ours_is_removed_but_not_one_of_the_user(tmp_path):
    out = tmp_path / "out"
    write_folder(out, FILES)
    (out / "empty_of_mine").mkdir()
    write_folder(out, {"numpy/arm.py": "X = 2\n"})
    assert not (out / "c").exists()
    assert (out / "empty_of_mine").is_dir()


def test_a_failure_while_building_leaves_the_old_folder_untouched(tmp_path):
    out = tmp_path / "out"
    write_folder(out, FILES)
    before = tree(out)

    def failing_build(staging: Path) -> list[str]:
        assert (staging / "c" / "arm.c").read_text(encoding="utf-8") == "int y;\n"
        raise KeyboardInterrupt  # Ctrl-C during the compile

    with pytest.raises(KeyboardInterrupt):
        write_folder(out, {**FILES, "c/arm.c": "int y;\n"}, finish=failing_build)
    assert tree(out) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]  # the staging folder is gone


def test_an_interrupted_file_by_file_commit_is_marked_incomplete(tmp_path, monkeypatch):
    out = tmp_path / "out"
    write_folder(out, FILES)
    (out / "mine.txt").write_text("the user's\n", encoding="utf-8")
    replace = output_folder._replace_file
    calls = []

    def replace_then_die(source: Path, root: Path, relative: str) -> None:
        calls.append(relative)
        if len(calls) == 2:
            raise KeyboardInterrupt
        replace(source, root, relative)

    monkeypatch.setattr(output_folder, "_replace_file", replace_then_die)
    with pytest.raises(KeyboardInterrupt):
        write_folder(out, {**FILES, "c/arm.c": "int y;\n"})
    listed, complete = read_manifest(out, ".symkin-files")
    assert not complete and listed == set(FILES)
    monkeypatch.setattr(output_folder, "_replace_file", replace)
    write_folder(out, {**FILES, "c/arm.c": "int y;\n"})
    assert read_manifest(out, ".symkin-files") == (frozenset(FILES), True)
    assert (out / "mine.txt").read_text(encoding="utf-8") == "the user's\n"


@pytest.mark.parametrize("relative", ["../escape.c", "/etc/passwd", "c/../../x", ""])
def test_paths_that_leave_the_folder_are_refused(tmp_path, relative):
    with pytest.raises(SymkinError, match="plain relative path"):
        write_folder(tmp_path / "out", {relative: "x"})


def test_derive_without_build_removes_the_previous_extension(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["derive", "planar_2r", "--out", str(out), "--emit", "c,python"]) == 0
    built = [p for p in (out / "python").iterdir() if p.suffix == ".so"]
    assert len(built) == 1
    assert main(["derive", "planar_2r", "--out", str(out), "--emit", "c,python", "--no-build"]) == 0
    assert not built[0].exists()
    assert (out / "python" / "planar_2r_ext.c").is_file()
    capsys.readouterr()


def test_derive_never_writes_through_a_planted_link(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["derive", "planar_2r", "--out", str(out), "--emit", "c"]) == 0
    target = tmp_path / "victim.txt"
    target.write_text("precious\n", encoding="utf-8")
    planted = out / "c" / "planar_2r.c"
    planted.unlink()
    planted.symlink_to(target)
    assert main(["derive", "planar_2r", "--out", str(out), "--emit", "c"]) == 0
    assert target.read_text(encoding="utf-8") == "precious\n"
    assert not planted.is_symlink() and "planar_2r_fk" in planted.read_text(encoding="utf-8")
    capsys.readouterr()


def test_a_planted_manifest_cannot_delete_files_outside_the_folder(tmp_path):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious\n", encoding="utf-8")
    out = tmp_path / "out"
    out.mkdir()
    (out / "mine.txt").write_text("the user's\n", encoding="utf-8")
    (out / ".symkin-files").write_text(
        f"{output_folder.MANIFEST_HEADER}\n../victim.txt\n{victim}\n", encoding="utf-8"
    )
    write_folder(out, {"a.txt": "hi\n"})
    assert victim.read_text(encoding="utf-8") == "precious\n"
    assert read_manifest(out, ".symkin-files") == (frozenset({"a.txt"}), True)


def test_an_interrupt_between_the_swap_renames_puts_the_old_folder_back(tmp_path, monkeypatch):
    out = tmp_path / "out"
    write_folder(out, FILES)
    before = tree(out)
    rename = os.rename
    calls = []

    def second_rename_interrupted(source, target):
        calls.append(source)
        if len(calls) == 2:
            raise KeyboardInterrupt
        rename(source, target)

    monkeypatch.setattr(output_folder.os, "rename", second_rename_interrupted)
    with pytest.raises(KeyboardInterrupt):
        write_folder(out, {**FILES, "c/arm.c": "int y;\n"})
    assert tree(out) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


@pytest.mark.parametrize("value", ["inf", "nan", "-1", "1e12", "soon"])
def test_time_limit_must_be_a_finite_number_of_seconds(value, capsys):
    with pytest.raises(SystemExit) as raised:
        main(["--time-limit", value, "list"])
    assert raised.value.code == 2
    assert "--time-limit" in capsys.readouterr().err


@pytest.mark.parametrize("kind", ["fifo", "link to a fifo"])
def test_a_pipe_or_a_link_to_one_is_not_replaced_by_a_file(tmp_path, kind, capsys):
    """``-o /dev/null`` or ``--csv /dev/stdout`` as root would rename a regular file over the
    device or its link; a FIFO stands in for them here (no privileges needed)."""
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    target = fifo if kind == "fifo" else tmp_path / "link"
    if target != fifo:
        target.symlink_to(fifo)
    assert main(["workspace", "planar_2r", "--samples", "100", "--csv", str(target)]) == 2
    err = capsys.readouterr().err
    assert "not a regular file" in err and str(target) in err
    assert target.is_symlink() == (kind != "fifo") and fifo.is_fifo()
    with pytest.raises(SymkinError, match="not a regular file"):
        output_folder.replace_file(tmp_path, target.name, "text\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted({"pipe", target.name})


@pytest.mark.parametrize(
    "command",
    [
        ["derive", "planar_2r", "--emit", "c", "--out", "/"],
        ["trajopt", "planar_2r", "--from", "0,0", "--to", "1,1", "--time", "2", "--out", "/"],
    ],
)
def test_the_file_system_root_is_refused_as_an_output_folder(command, capsys):
    assert main(command) == 2
    assert "file system's root" in capsys.readouterr().err
    assert not Path("/c").exists() and not Path("/trajectory.csv").exists()


def test_a_file_named_in_the_root_folder_is_written_beside_the_others(tmp_path, monkeypatch):
    """Only an output *folder* at the root is refused: a single file named relative to a
    working folder (any folder, the root of a container among them) is written there."""
    monkeypatch.chdir(tmp_path)
    assert output_folder.replace_file(Path("."), "one.txt", "text\n") == Path("one.txt")
    assert (tmp_path / "one.txt").read_text(encoding="utf-8") == "text\n"


def test_a_link_into_proc_is_refused_even_when_it_ends_at_a_regular_file(tmp_path, capsys):
    """``--csv /dev/stdout > out.csv``: the chain /dev/stdout -> /proc/self/fd/1 ends at the
    regular file out.csv, and renaming over the link would replace /dev/stdout itself."""
    real = tmp_path / "real.csv"
    real.write_text("mine\n", encoding="utf-8")
    link = tmp_path / "stdout"
    with open(real, "a", encoding="utf-8") as handle:
        fd = f"proc/{os.getpid()}/fd/{handle.fileno()}"
        # absolute, and relative with ".." up to the root (not normalised by the link)
        for text in (f"/{fd}", "../" * len(tmp_path.parts) + fd):
            link.unlink(missing_ok=True)
            link.symlink_to(text)
            argv = ["workspace", "planar_2r", "--samples", "100", "--csv", str(link)]
            assert main(argv) == 2, text
            assert "not a regular file" in capsys.readouterr().err
            assert link.is_symlink() and real.read_text(encoding="utf-8") == "mine\n"
