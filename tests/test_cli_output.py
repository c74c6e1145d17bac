"""The command's own output streams: a terminal encoding that lacks a title's characters, and
a standard output the system refuses to take (the real command in a subprocess)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

SYMKIN = [sys.executable, "-m", "symkin.cli"]


def test_a_title_the_encoding_lacks_is_escaped_not_a_crash(tmp_path: Path):
    robot = tmp_path / "uni.toml"
    robot.write_text(
        'name = "uni"\ntitle = "Größe ∑"\n[[joints]]\ntype = "revolute"\n', encoding="utf-8"
    )
    done = subprocess.run(
        [*SYMKIN, "show", str(robot)],
        capture_output=True,
        env=os.environ | {"PYTHONIOENCODING": "ascii"},
        check=False,
    )
    assert done.returncode == 0, done.stderr
    # ö is U+00F6, ß U+00DF, ∑ U+2211: Python's backslashreplace escapes
    assert b"Gr\\xf6\\xdfe \\u2211" in done.stdout


def test_a_full_disk_on_standard_output_is_one_error_line(tmp_path: Path):
    with open("/dev/full", "wb") as full:
        done = subprocess.run(
            [*SYMKIN, "show", "planar_2r"], stdout=full, stderr=subprocess.PIPE, check=False
        )
    err = done.stderr.decode()
    assert done.returncode == 2, err
    assert err.strip().splitlines() == [
        "symkin: error: show planar_2r: cannot write the output: No space left on device"
    ]
