"""Ctrl-C and the time limit, on the real command in a subprocess (the issue's reproductions:
a KeyboardInterrupt traceback during ``derive``, a 20-joint chain that hangs ``show``)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow

SYMKIN = [sys.executable, "-m", "symkin.cli"]


def test_ctrl_c_during_derive_is_one_line_exit_130_and_leaves_the_folder(tmp_path: Path):
    out = tmp_path / "out"
    assert subprocess.run([*SYMKIN, "derive", "planar_2r", "--out", str(out), "--emit", "c"],
                          capture_output=True, check=False).returncode == 0  # fmt: skip
    before = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}
    # A 12-joint chain derives for tens of seconds (the Panda now takes about five, so a fixed
    # sleep could land after its derivation, in the compile step).
    robot = _chain_file(tmp_path, 12)
    process = subprocess.Popen(
        [*SYMKIN, "derive", str(robot), "--out", str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    first = process.stderr.readline()  # the derivation has started
    time.sleep(2)
    process.send_signal(signal.SIGINT)
    _, rest = process.communicate(timeout=60)
    err = first + rest
    assert process.returncode == 130, err
    assert "Traceback" not in err
    # Progress lines end with "..." and the size guards warn (one line each, before Ctrl-C);
    # the interruption itself is one line.
    lines = [
        line
        for line in err.splitlines()
        if not line.endswith("...") and not line.startswith("symkin: warning: chain12: ")
    ]
    assert len(lines) == 1 and "interrupted" in lines[0], err
    assert {p: p.read_bytes() for p in out.rglob("*") if p.is_file()} == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["chain12.toml", "out"]  # no staging


def test_time_limit_stops_a_derivation_too_large_for_it(tmp_path: Path):
    robot = _chain_file(tmp_path, 20)
    started = time.monotonic()
    done = subprocess.run(
        [*SYMKIN, "--time-limit", "3", "show", str(robot)],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert time.monotonic() - started < 60
    assert done.returncode == 2, done.stderr
    *warnings, error = done.stderr.strip().splitlines()
    assert error == (
        f"symkin: error: show {robot}: stopped at the time limit of 3 s (--time-limit SECONDS, "
        "0 for none); the derivation or the task is too large for it"
    )
    # Before the limit, the size guards may say what they skipped (one line each).
    assert all(line.startswith("symkin: warning: chain20: ") for line in warnings), warnings


def _chain_file(folder: Path, joints: int) -> Path:
    """A chain of alternating right-angle twists: far too large to derive in seconds."""
    lines = [
        f'name = "chain{joints}"',
        "[parameters]",
        *(f"L{i} = 0.1" for i in range(1, joints + 1)),
    ]
    for i in range(1, joints + 1):
        lines += ["[[joints]]", 'type = "revolute"', f'a = "L{i}"', f"alpha = {90 * (i % 2)}"]
    robot = folder / f"chain{joints}.toml"
    robot.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return robot


def _read_terminal(descriptor: int, seconds: float) -> bytes:
    """What the command wrote to its terminal, until it closes or ``seconds`` pass."""
    import select

    out, end = b"", time.monotonic() + seconds
    while time.monotonic() < end:
        if select.select([descriptor], [], [], 0.2)[0]:
            try:
                data = os.read(descriptor, 65536)
            except OSError:  # the child closed the terminal
                break
            if not data:
                break
            out += data
    return out


def test_ctrl_c_during_the_live_display_restores_the_terminal(tmp_path: Path):
    """On a terminal the phases are live lines (rich hides the cursor meanwhile); Ctrl-C in the
    middle exits 130 and shows the cursor again, after the last time it was hidden."""
    import pty

    robot = _chain_file(tmp_path, 20)
    pid, descriptor = pty.fork()
    if pid == 0:  # the child: the command on the pseudo-terminal
        os.environ["SYMKIN_NO_CACHE"] = "1"
        os.execv(sys.executable, [*SYMKIN, "show", str(robot)])
    head = _read_terminal(descriptor, 4)
    os.kill(pid, signal.SIGINT)
    out = head + _read_terminal(descriptor, 60)
    _, status = os.waitpid(pid, 0)
    assert os.waitstatus_to_exitcode(status) == 130, out
    hide, show = b"\x1b[?25l", b"\x1b[?25h"
    assert hide in head, head  # the live display was running when Ctrl-C came
    assert out.rfind(show) > out.rfind(hide), out
    assert b"interrupted" in out and b"Traceback" not in out
