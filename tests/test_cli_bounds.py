"""Hostile sizes and data on the command line: each is one ``symkin: error:`` line and exit 2.

Found by a red-team run: ``--data /dev/zero`` read until the OOM killer, a FIFO blocked, a
repeated CSV column was silently read as its first copy, ``--rate``/``--period``/``--samples``
asked for tables that cannot fit in memory (exit 3 or killed), and a negative ``--noise`` was
accepted; so was ``--harmonics`` above what the optimiser's instants resolve.  The limits are
the documented caps: 256 MiB of data file
(:data:`symkin.solve.identify_data.MAX_DATA_BYTES`), 10^6 sampled rows
(:data:`symkin.cli.values.MAX_ROWS`), 10^6 configurations a workspace chunk and 10^5 chunks.
"""

from __future__ import annotations

import contextlib
import os
import threading
import time
from pathlib import Path

import pytest

from symkin.cli import main
from symkin.errors import SymkinError

# planar_2r's logged columns; the values do not matter, every case fails before the fit.
LOG_COLUMNS = "q1,q2,dq1,dq2,ddq1,ddq2,tau1,tau2"
ROW = "0.1,0.2,0.3,0.4,0.5,0.6,0.7,0.8"


def one_error(capsys: pytest.CaptureFixture[str], *argv: str) -> str:
    """Run ``symkin argv``; assert exit 2, no output, one stderr line; return that line."""
    code = main(list(argv))
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert code == 2, err
    assert out == "" and "Traceback" not in err
    assert len(lines) == 1 and lines[0].startswith("symkin: error: "), err
    return lines[0]


def test_data_from_a_device_is_refused(capsys):
    line = one_error(capsys, "identify", "planar_2r", "--data", "/dev/zero")
    assert "/dev/zero: not a regular file" in line and "256 MiB" in line


def test_data_from_a_fifo_is_refused_without_blocking(tmp_path, capsys):
    fifo = tmp_path / "log.csv"
    os.mkfifo(fifo)

    def release() -> None:
        # Had the reader opened the FIFO, it would wait for a writer: give it one (an empty
        # file, a different message) after 5 s, so a regression fails instead of hanging.
        time.sleep(5.0)
        with contextlib.suppress(OSError):  # no reader: the FIFO was refused, as it should
            os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))

    threading.Thread(target=release, daemon=True).start()
    line = one_error(capsys, "identify", "planar_2r", "--data", str(fifo))
    assert "not a regular file" in line


def test_data_over_the_size_cap_is_refused(tmp_path, capsys):
    big = tmp_path / "log.csv"
    with big.open("wb") as handle:  # sparse: no disk used
        handle.write(f"{LOG_COLUMNS}\n{ROW}\n".encode())
        handle.truncate(256 * 1024 * 1024 + 1)
    line = one_error(capsys, "identify", "planar_2r", "--data", str(big))
    assert "larger than 262,144 KiB" in line and "256 MiB" in line


@pytest.mark.parametrize(
    ("header", "named"),
    [("q1,q1,q2,dq1,dq2,ddq1,ddq2,tau1", "q1"), ("q1,q2,dq1,dq2,ddq1,ddq2,tau1,tau1", "tau1")],
)
def test_a_repeated_column_is_an_error_naming_it(tmp_path, capsys, header, named):
    path = tmp_path / "log.csv"
    path.write_text(f"t,{header}\n0,{ROW}\n", encoding="utf-8")
    line = one_error(capsys, "identify", "planar_2r", "--data", str(path))
    assert f"repeats the column {named} " in line


def test_braces_in_a_header_are_data_not_a_message_template(tmp_path, capsys):
    path = tmp_path / "log.csv"
    path.write_text("{0},{x}\n1,2\n", encoding="utf-8")
    line = one_error(capsys, "identify", "planar_2r", "--data", str(path))
    assert "missing q1" in line and "{0}, {x}" in line


@pytest.mark.parametrize(
    ("options", "words"),
    [
        (("--rate", "1e12"), ("--rate 1e+12 over --period 10 s", "at most 1,000,000")),
        (("--period", "1e12"), ("--rate 100 over --period 1e+12 s", "at most 1,000,000")),
        (("--rate", "0"), ("--rate: expected a positive finite number",)),
        (("--period", "-1"), ("--period: a positive number of seconds", "got -1")),
        (("--simulate", "--noise", "-1"), ("--noise", ">= 0", "got -1")),
        (("--simulate", "--noise", "nan"), ("--noise", ">= 0", "got nan")),
        # 60 optimiser instants a period resolve 30 harmonics (Nyquist).
        (("--harmonics", "31"), ("--harmonics: 1 to 30", "got 31")),
        (("--harmonics", "0"), ("--harmonics: 1 to 30", "got 0")),
    ],
    ids=[
        "rate",
        "period",
        "zero-rate",
        "negative-period",
        "negative-noise",
        "nan-noise",
        "harmonics",
        "no-harmonics",
    ],
)
def test_excitation_sizes_and_noise_are_checked_first(tmp_path, capsys, options, words):
    out = tmp_path / "ex.csv"
    line = one_error(capsys, "identify", "planar_2r", "--excite", "--out", str(out), *options)
    assert all(word in line for word in words), line
    assert not out.exists()


def test_trajopt_resampling_rows_are_capped(tmp_path, capsys):
    argv = ["trajopt", "planar_2r", "--from", "0,0", "--to", "1,1", "--time", "2"]
    line = one_error(capsys, *argv, "--out", str(tmp_path / "tj"), "--rate", "1e12")
    assert "--rate 1e+12 over --time 2 s is 2,000,000,000,000 samples; at most 1,000,000" in line
    assert not Path(tmp_path / "tj").exists()


@pytest.mark.parametrize(
    ("options", "words"),
    [
        (("--samples", "1e20"), ("--samples 1e+20", "1e+15 chunks", "at most 1e+11")),
        (("--samples", "1e7", "--chunk", "1"), ("--samples 1e+07", "at most 100,000 chunks")),
        (("--chunk", "1e9"), ("--chunk 1e+09", "1,000,000")),
    ],
    ids=["samples", "chunks", "chunk"],
)
def test_workspace_sizes_are_capped(capsys, options, words):
    line = one_error(capsys, "workspace", "planar_2r", *options)
    assert all(word in line for word in words), line


def test_trajopt_rows_over_a_free_time_are_checked_before_anything_is_written(tmp_path, capsys):
    """Minimum time: T is known after the solve; the cap is checked before any output."""
    argv = ["trajopt", "planar_2r", "--from", "0,0", "--to", "1,1", "--min-time"]
    argv += ["--objective", "time", "--torque-limit", "50"]
    code = main([*argv, "--out", str(tmp_path / "tj"), "--rate", "1e12"])
    out, err = capsys.readouterr()
    errors = [line for line in err.splitlines() if "error" in line]
    assert code == 2 and out == "" and "Traceback" not in err
    assert len(errors) == 1 and "--rate 1e+12 over the optimal time" in errors[0]
    assert "samples; at most 1,000,000" in errors[0]
    assert not (tmp_path / "tj").exists()


def test_the_row_cap_allows_what_the_docs_promise() -> None:
    """The docs: --period x --rate (or --rate x T) at most 10^6 samples; the table has one row
    more (both ends), and that is allowed."""
    from symkin.cli.values import sampled_rows

    assert sampled_rows(100.0, 10_000.0, "--rate", "--period") == 1_000_001
    with pytest.raises(SymkinError, match="is 1,000,100 samples; at most 1,000,000"):
        sampled_rows(100.0, 10_001.0, "--rate", "--period")
