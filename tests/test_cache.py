"""The derivation cache on disk (:mod:`symkin.cache`) and the progress lines of the command.

Evidence that a run did not derive is timing-free: the command's report function is wrapped
with a call counter, the in-process model cache is cleared between runs, and ``--verbose``
lists every derivation phase that ran.
"""

from __future__ import annotations

import io
import json
import multiprocessing
import os
import re
import subprocess
import sys
from collections.abc import Callable
from contextlib import closing
from pathlib import Path

import pytest

import symkin.cli.commands as commands
from symkin.cache import FORMAT, cache_directory, entry_key, remembered, user_cache
from symkin.cli import main
from symkin.cli.reporter import CommandReporter
from symkin.derive import derive
from symkin.errors import BudgetWarning, RobotWarning
from symkin.io import load_robot
from symkin.progress import note, phase, reporting

ROBOT = """\
name = "two_link"
title = "Planar 2R arm for the cache tests"
convention = "standard"

[parameters]
L1 = {L1}
L2 = 0.5

[[joints]]
type = "revolute"
a = "L1"

[[joints]]
type = "revolute"
a = "L2"
"""
PHASE_LINE = re.compile(r"^symkin: +\d+\.\d\d s  the geometric Jacobian$", re.MULTILINE)


@pytest.fixture
def cache_root(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """The cache turned on, in a folder of this test only; the folder ``symkin`` uses."""
    monkeypatch.delenv("SYMKIN_NO_CACHE", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    derive.cache_clear()
    return tmp_path / "xdg" / "symkin"


def robot_file(folder: Path, L1: float = 1.0, name: str = "robot.toml") -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / name
    path.write_text(ROBOT.format(L1=L1))
    return path


def counted(monkeypatch: pytest.MonkeyPatch, name: str) -> list[int]:
    """Count the calls of ``symkin.cli.commands.<name>`` (runs only when the cache misses)."""
    calls: list[int] = []
    original: Callable = getattr(commands, name)

    def wrapper(*args: object, **kwargs: object) -> object:
        calls.append(1)
        return original(*args, **kwargs)

    monkeypatch.setattr(commands, name, wrapper)
    return calls


@pytest.fixture
def shown(cache_root: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> tuple[str, list]:
    """A robot file for ``show`` (cache on) and the call counter of show's report."""
    return str(robot_file(tmp_path)), counted(monkeypatch, "show_text")


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[str, str]:
    derive.cache_clear()  # an in-process model would hide a second derivation
    assert main(list(argv)) == 0
    return capsys.readouterr()


def entries(root: Path) -> list[Path]:
    return sorted(root.glob("*.json"))


def test_directory_follows_xdg(tmp_path: Path) -> None:
    assert cache_directory({"XDG_CACHE_HOME": str(tmp_path)}) == tmp_path / "symkin"
    # The XDG spec: a relative XDG_CACHE_HOME is invalid and ignored.
    assert cache_directory({"XDG_CACHE_HOME": "rel"}) == Path.home() / ".cache" / "symkin"
    assert cache_directory({}) == Path.home() / ".cache" / "symkin"
    assert user_cache({"XDG_CACHE_HOME": str(tmp_path), "SYMKIN_NO_CACHE": "1"}) is None
    cache = user_cache({"XDG_CACHE_HOME": str(tmp_path / "new")})
    assert cache is not None and cache.directory == tmp_path / "new" / "symkin"
    assert cache.directory.stat().st_mode & 0o777 == 0o700


def test_key_follows_content_not_path(tmp_path: Path) -> None:
    first = load_robot(str(robot_file(tmp_path / "a")))
    moved = load_robot(str(robot_file(tmp_path / "b", name="other.toml")))
    changed = load_robot(str(robot_file(tmp_path / "c", L1=1.25)))
    assert first.file != moved.file
    assert entry_key("show", first, {}) == entry_key("show", moved, {})
    assert entry_key("show", first, {}) != entry_key("show", changed, {})
    assert entry_key("show", first, {}) != entry_key("show", first, {"json": True})
    assert entry_key("show", first, {}) != entry_key("latex", first, {})


def test_second_show_reads_the_cache(
    shown: tuple[str, list], cache_root: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path, calls = shown
    cold, cold_err = run(capsys, "show", path, "--verbose")
    assert PHASE_LINE.search(cold_err), cold_err
    warm, warm_err = run(capsys, "show", path, "--verbose")
    assert warm == cold and len(calls) == 1
    assert "cache: show of two_link from" in warm_err
    assert "s  the " not in warm_err  # no derivation phase ran
    assert len(entries(cache_root)) == 1
    # The same content under another path is the same entry.
    run(capsys, "show", str(robot_file(tmp_path / "elsewhere")))
    assert len(calls) == 1
    # One parameter value changed: a new entry.
    run(capsys, "show", str(robot_file(tmp_path / "longer", L1=2.0)))
    assert len(calls) == 2 and len(entries(cache_root)) == 2


@pytest.mark.slow
def test_derive_files_come_from_the_cache(
    cache_root: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch
) -> None:
    path = str(robot_file(tmp_path))
    calls = counted(monkeypatch, "files_for_robot")
    errors = [
        run(capsys, "derive", path, "--emit", "numpy", "--out", str(tmp_path / out), "--verbose")[1]
        for out in ("cold", "warm")
    ]
    assert len(calls) == 1
    assert re.search(r"^symkin: +\d+\.\d\d s  the dynamics kernels", errors[0], re.MULTILINE)
    assert "s  the " not in errors[1]
    cold, warm = tmp_path / "cold", tmp_path / "warm"
    written = sorted(p.relative_to(cold) for p in cold.rglob("*") if p.is_file())
    assert written == sorted(p.relative_to(warm) for p in warm.rglob("*") if p.is_file())
    for relative in written:
        assert (cold / relative).read_bytes() == (warm / relative).read_bytes()
    # Another backend set is another product.
    run(capsys, "derive", path, "--emit", "casadi", "--out", str(tmp_path / "casadi"))
    assert len(calls) == 2


def test_no_cache_neither_reads_nor_writes(
    shown: tuple[str, list], cache_root: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path, calls = shown
    run(capsys, "show", path, "--no-cache")
    assert entries(cache_root) == []
    run(capsys, "show", path)
    run(capsys, "show", path, "--no-cache")
    assert len(calls) == 3


def _truncated(text: str) -> str:
    return text[: len(text) // 2]


def _other_format(text: str) -> str:
    return json.dumps(json.loads(text) | {"format": FORMAT + 1, "value": "stale"})


def _not_text(text: str) -> str:
    return json.dumps(json.loads(text) | {"value": {"a": 1}})


@pytest.mark.parametrize(
    "spoil",
    [_truncated, lambda _: "\x00\xff garbage", lambda _: "", _other_format, _not_text],
    ids=["truncated", "garbage", "empty", "other-format", "not-text"],
)
def test_spoilt_entry_is_rebuilt(
    spoil: Callable[[str], str],
    shown: tuple[str, list],
    cache_root: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    path, calls = shown
    good, _ = run(capsys, "show", path)
    (entry,) = entries(cache_root)
    valid = entry.read_text()
    entry.write_text(spoil(valid), errors="surrogateescape")
    again, err = run(capsys, "show", path, "--verbose")
    assert again == good and len(calls) == 2
    assert "not a valid entry" in err
    assert entry.read_text() == valid  # rebuilt


@pytest.mark.parametrize("target", ["directory", "entry"])
def test_writable_by_others_is_not_trusted(
    target: str,
    shown: tuple[str, list],
    cache_root: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    path, calls = shown
    run(capsys, "show", path)
    (entry,) = entries(cache_root)
    (cache_root if target == "directory" else entry).chmod(0o777)
    _, err = run(capsys, "show", path, "--verbose")
    assert len(calls) == 2
    assert err.count("writable by group or others") == 1, err  # said once
    _, err = run(capsys, "show", path)
    assert "cache" not in err  # only with --verbose


def test_entry_of_another_user_is_not_read(
    shown: tuple[str, list],
    cache_root: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    path, calls = shown
    run(capsys, "show", path)
    (entry,) = entries(cache_root)
    # Giving the file away needs root; the same test without root: the entry keeps its owner
    # and the reader runs as another user (the folder is checked when first opened, so the
    # cache is made before the user changes).
    owner = entry.stat().st_uid
    real_fstat = os.fstat

    def fstat_of_another_owner(descriptor: int) -> os.stat_result:
        status = real_fstat(descriptor)
        if status.st_ino != entry.stat().st_ino:
            return status
        fields = list(status)
        fields[4] = owner + 4242  # st_uid
        return os.stat_result(fields)

    monkeypatch.setattr(os, "fstat", fstat_of_another_owner)
    _, err = run(capsys, "show", path, "--verbose")
    assert len(calls) == 2 and "not owned by you" in err


def test_warnings_are_given_again_on_a_hit(cache_root: Path, tmp_path: Path) -> None:
    robot = load_robot(str(robot_file(tmp_path)))
    cache = user_cache()

    def compute() -> str:
        import warnings

        warnings.warn("link 2: odd inertia", UserWarning, stacklevel=1)
        return "text"

    for _ in range(2):
        with pytest.warns(UserWarning, match="link 2: odd inertia"):
            assert remembered(cache, "show", robot, {}, compute) == "text"


def _store_many(directory: str, robot_path: str, rounds: int) -> None:
    os.environ["XDG_CACHE_HOME"] = directory
    os.environ.pop("SYMKIN_NO_CACHE", None)
    robot = load_robot(robot_path)
    for _ in range(rounds):
        value = remembered(user_cache(), "derive", robot, {}, lambda: {"a.py": "x = 1\n" * 5000})
        assert value == {"a.py": "x = 1\n" * 5000}


def test_concurrent_writers_leave_one_valid_entry(tmp_path: Path) -> None:
    robot_path = str(robot_file(tmp_path))
    context = multiprocessing.get_context("fork")
    workers = [
        context.Process(target=_store_many, args=(str(tmp_path / "xdg"), robot_path, 30))
        for _ in range(4)
    ]
    for worker in workers:
        worker.start()
    for worker in workers:
        worker.join(60)
    assert [w.exitcode for w in workers] == [0] * 4
    folder = tmp_path / "xdg" / "symkin"
    (entry,) = entries(folder)
    assert json.loads(entry.read_text())["value"] == {"a.py": "x = 1\n" * 5000}
    assert [p.name for p in folder.iterdir()] == [entry.name]  # no temporary file left


@pytest.mark.slow
def test_two_commands_at_once(tmp_path: Path) -> None:
    """Two ``symkin show`` processes on the same robot at the same time: both succeed with
    the same text, one valid entry remains."""
    path = str(robot_file(tmp_path))
    env = os.environ | {"XDG_CACHE_HOME": str(tmp_path / "xdg")}
    env.pop("SYMKIN_NO_CACHE")
    command = [sys.executable, "-m", "symkin.cli", "show", path, "--dynamics"]
    running = [subprocess.Popen(command, env=env, stdout=subprocess.PIPE, text=True) for _ in "ab"]
    outputs = [p.communicate(timeout=300)[0] for p in running]
    assert [p.returncode for p in running] == [0, 0]
    assert outputs[0] == outputs[1] and "two_link" in outputs[0]
    (entry,) = entries(tmp_path / "xdg" / "symkin")
    assert json.loads(entry.read_text())["value"] == outputs[0].rstrip("\n")


def test_verbose_prints_phases_and_json_stays_pure(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = str(robot_file(tmp_path))
    out, err = run(capsys, "show", path, "--json", "--verbose", "--no-cache")
    assert json.loads(out)["robot"] == "two_link"
    assert PHASE_LINE.search(err), err
    # Not a terminal and not --verbose: no phase lines at all.
    _, err = run(capsys, "show", path, "--no-cache")
    assert err == ""


def test_live_reporter_nests_phases_and_ends_clean() -> None:
    """The terminal reporter (rich) shows nested phases, prints notes and timings through its
    console, and stops its live display when the outermost phase ends."""
    stream = io.StringIO()
    reporter = CommandReporter(verbose=True, live=True, stream=stream)
    with reporting(reporter), phase("outer"):
        with phase("inner"):
            note("halfway")
        assert reporter.display is not None and len(reporter.running) == 1
    assert reporter.display is None and reporter.running == []
    lines = [line for line in stream.getvalue().splitlines() if line.startswith("symkin:")]
    assert lines[0] == "symkin: halfway"
    assert re.fullmatch(r"symkin: +\d+\.\d\d s  inner", lines[1])
    assert re.fullmatch(r"symkin: +\d+\.\d\d s  outer", lines[2])


def test_derived_files_name_their_own_robot_file(
    cache_root: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The files' preamble names the robot file ("Generated by symkin from a/robot.toml"), so
    the same content under another path must not be served the first path's files."""
    first, moved = robot_file(tmp_path / "a"), robot_file(tmp_path / "b")
    for path, out in ((first, "one"), (moved, "two")):
        run(capsys, "derive", str(path), "--emit", "numpy", "--out", str(tmp_path / out))
    text = (tmp_path / "two" / "numpy" / "two_link_kinematics.py").read_text()
    assert f"from {moved};" in text and str(first) not in text


def test_budget_warning_keeps_its_kind_on_a_hit(cache_root: Path, tmp_path: Path) -> None:
    """A replayed warning is the same class with the same template, so the command spells
    its parameter as on the cold run ("--budget SECONDS", not the library's "budget")."""
    robot = load_robot(str(robot_file(tmp_path)))

    def compute() -> str:
        import warnings

        warnings.warn(BudgetWarning("no closed form within {budget}"), stacklevel=1)
        warnings.warn(RobotWarning("joint 2: odd inertia"), stacklevel=1)
        return "text"

    for _ in range(2):
        with pytest.warns(Warning) as said:
            assert remembered(user_cache(), "show", robot, {}, compute) == "text"
        budget, odd = (w.message for w in said)
        assert isinstance(budget, BudgetWarning) and isinstance(odd, RobotWarning)
        assert budget.message_for({"budget": "--budget S"}) == "no closed form within --budget S"


def test_interrupted_store_leaves_no_temporary_file(
    cache_root: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Ctrl-C (or the --time-limit alarm) while an entry is written leaves no ``.tmp`` file."""
    cache = user_cache()
    assert cache is not None

    def interrupted(*_: object, **__: object) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(json, "dump", interrupted)
    with pytest.raises(KeyboardInterrupt):
        cache.store("show", "0" * 64, "text", [])
    assert list(cache.directory.iterdir()) == []


def test_cache_folder_that_is_a_symlink_is_not_used(tmp_path: Path) -> None:
    """``$XDG_CACHE_HOME/symkin`` as a symbolic link (in a shared ``XDG_CACHE_HOME`` whoever
    made the link can point it elsewhere after the check) is refused, as output folders are."""
    (tmp_path / "mine").mkdir(mode=0o700)
    (tmp_path / "xdg").mkdir()
    (tmp_path / "xdg" / "symkin").symlink_to(tmp_path / "mine")
    assert user_cache({"XDG_CACHE_HOME": str(tmp_path / "xdg")}) is None


def test_entry_that_is_a_symlink_is_not_followed(
    shown: tuple[str, list], cache_root: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path, calls = shown
    good, _ = run(capsys, "show", path)
    (entry,) = entries(cache_root)
    elsewhere = tmp_path / "elsewhere.json"
    entry.rename(elsewhere)
    entry.symlink_to(elsewhere)
    again, err = run(capsys, "show", path, "--verbose")
    assert again == good and len(calls) == 2 and "cannot read" in err


@pytest.mark.parametrize("relative", ["../../escaped.py", "/tmp/absolute.py", "numpy/../../x.py"])
def test_entry_with_a_path_out_of_the_folder_is_rebuilt(
    relative: str, cache_root: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A ``derive`` entry whose file map leaves the output folder is not a valid entry: it is
    ignored and rebuilt (not written, and not an error that blocks the command)."""
    path = str(robot_file(tmp_path))
    run(capsys, "derive", path, "--emit", "numpy", "--out", str(tmp_path / "cold"))
    (entry,) = entries(cache_root)
    data = json.loads(entry.read_text())
    data["value"][relative] = "import os\n"
    entry.write_text(json.dumps(data))
    _, err = run(
        capsys, "derive", path, "--emit", "numpy", "--out", str(tmp_path / "warm"), "--verbose"
    )
    assert "not a valid entry" in err
    assert not (tmp_path / "escaped.py").exists() and not Path("/tmp/absolute.py").exists()
    assert sorted(p.name for p in (tmp_path / "warm").rglob("*.py")) == sorted(
        p.name for p in (tmp_path / "cold").rglob("*.py")
    )


def test_closing_the_reporter_stops_a_display_left_running(monkeypatch: pytest.MonkeyPatch) -> None:
    """Ctrl-C inside ``started`` (the display begun, the phase not yet recorded) leaves no
    phase to end it; the command closes its reporter, which stops the display anyway."""
    from rich.progress import Progress

    def interrupted(*_: object, **__: object) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(Progress, "add_task", interrupted)
    reporter = CommandReporter(verbose=False, live=True, stream=io.StringIO())
    with pytest.raises(KeyboardInterrupt), closing(reporter), reporting(reporter), phase("x"):
        pass
    assert reporter.display is None


@pytest.mark.parametrize("package", ["numpy", "jinja2"])
def test_key_follows_the_packages_that_shape_the_text(
    package: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """NumPy prints the emitters' number literals and Jinja2 renders the templates: a new
    version may change the text, so it must change the key (no stale entry after upgrading)."""
    import symkin.cache as cache_module

    robot = load_robot(str(robot_file(tmp_path)))
    cache_module._software.cache_clear()
    before = entry_key("derive", robot, {})
    real = cache_module.metadata.version
    monkeypatch.setattr(
        cache_module.metadata, "version", lambda name: "0.0" if name == package else real(name)
    )
    cache_module._software.cache_clear()
    try:
        assert entry_key("derive", robot, {}) != before
    finally:
        monkeypatch.undo()
        cache_module._software.cache_clear()


def test_a_cold_run_shows_its_warnings_as_they_come(
    cache_root: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A budget warning early in a long cold derivation is shown then (above the live lines),
    not held back until the derivation ends; it is still stored for the warm runs."""
    import warnings

    robot = load_robot(str(robot_file(tmp_path)))
    shown: list[str] = []
    monkeypatch.setattr(
        warnings, "showwarning", lambda message, *_, **__: shown.append(str(message))
    )

    def compute() -> str:
        warnings.warn(RobotWarning("joint 2: odd inertia"), stacklevel=1)
        assert shown == ["joint 2: odd inertia"]  # already shown, mid-derivation
        return "text"

    with warnings.catch_warnings():
        warnings.simplefilter("always")
        assert remembered(user_cache(), "show", robot, {}, compute) == "text"
        assert remembered(user_cache(), "show", robot, {}, compute) == "text"
    assert shown == ["joint 2: odd inertia"] * 2


def test_a_dangling_link_in_the_package_does_not_break_the_key(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The source digest reads symkin's files; a broken symbolic link among them (a removed
    template in a development checkout) is named, not read, instead of failing every command."""
    import symkin.cache as cache_module

    (tmp_path / "package").mkdir()
    (tmp_path / "package" / "cache.py").write_text("# a stand-in\n")
    (tmp_path / "package" / "gone.j2").symlink_to(tmp_path / "missing")
    monkeypatch.setattr(cache_module, "__file__", str(tmp_path / "package" / "cache.py"))
    cache_module._software.cache_clear()
    try:
        assert len(cache_module._software()["source"]) == 64
    finally:
        monkeypatch.undo()
        cache_module._software.cache_clear()


@pytest.mark.slow
def test_a_budget_fallback_is_not_served_to_a_larger_budget(
    cache_root: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The budget is part of the key: the over-budget answer of a tiny budget is kept for that
    budget only, and a larger one derives again and finds the closed form (the PUMA's
    determinant needs about 0.1 s of CPU)."""
    tiny, tiny_err = run(capsys, "show", "puma560", "--json", "--budget", "0.0014")
    assert json.loads(tiny)["det_status"] == "over budget" and "--budget" in tiny_err
    again, again_err = run(capsys, "show", "puma560", "--json", "--budget", "0.0014", "--verbose")
    assert again == tiny and "cache: show of puma560 from" in again_err
    larger, _ = run(capsys, "show", "puma560", "--json", "--budget", "30")
    assert json.loads(larger)["det_status"] == "found"
    assert len(entries(cache_root)) == 2
