"""Logged data for identification: CSV columns by header name, and velocities and
accelerations from positions by a zero-phase filter.

With all states logged the columns are ``q1..qn, dq1..dqn, ddq1..ddqn, tau1..taun`` (any
order, other columns such as ``t`` ignored).  With positions and torques only
(:func:`filtered_samples`) the file has ``t, q1..qn, tau1..taun``: ``q`` and ``tau`` are
low-passed by a Butterworth filter of order :data:`FILTER_ORDER` run forwards and backwards
(``scipy.signal.filtfilt``: zero phase, so the filtered torques stay aligned with the
filtered states; Swevers et al., IEEE Trans. Robot. Autom. 13(5), 1997), then ``dq`` and
``ddq`` are central differences of the filtered ``q`` (``numpy.gradient``, second order);
the samples within :data:`EDGE_PERIODS` cut-off periods of either end are dropped.
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from symkin.errors import SymkinError
from symkin.io.robot_file import read_limited

FILTER_ORDER = 4
# A data file is read whole and parsed in memory (about ten times its size): 256 MiB holds
# over an hour of a 7-joint arm's q, dq, ddq, tau at 100 Hz.
MAX_DATA_BYTES = 256 * 1024 * 1024
DATA_FILE_KIND = f"a data file is a CSV file of at most {MAX_DATA_BYTES // 2**20} MiB"
# Samples within this many cut-off periods of either end are dropped: the filter's start-up
# (filtfilt pads by odd extension, which bends the second derivative) and the one-sided
# differences there (measured: the acceleration error falls below 1e-3 of its size after 4).
EDGE_PERIODS = 4.0


@dataclass(frozen=True)
class Samples:
    """N logged samples (arrays N x n)."""

    q: np.ndarray
    dq: np.ndarray
    ddq: np.ndarray
    tau: np.ndarray


def read_columns(path: Path, names: list[str]) -> dict[str, np.ndarray]:
    """The named columns of a CSV file with a header row, as float arrays.

    Raises :class:`~symkin.errors.SymkinError` naming the file and what is wrong: not a
    regular file or over :data:`MAX_DATA_BYTES`, not UTF-8, a column name repeated in the
    header, missing columns, a cell that is not a number, a row of the wrong length, or the
    rows holding NaN.
    """
    rows = list(csv.reader(io.StringIO(_data_text(path))))
    if not rows:
        raise SymkinError(f"{path}: the data file is empty (a header row is needed)")
    header = [h.strip() for h in rows[0]]
    repeated = sorted({h for h in header if h and header.count(h) > 1})
    if repeated:
        raise SymkinError(
            f"{path}: the header repeats the column {', '.join(repeated)} (each column "
            "name may appear once)"
        )
    missing = [name for name in names if name not in header]
    if missing:
        raise SymkinError(
            f"{path}: wrong columns: missing {', '.join(missing)} (the header has "
            f"{len(header)} columns: {', '.join(header) or 'none'}; expected {', '.join(names)})"
        )
    body = [r for r in rows[1:] if any(cell.strip() for cell in r)]
    for line, row in enumerate(body, start=2):
        if len(row) != len(header):
            raise SymkinError(
                f"{path}: row {line} has {len(row)} values, the header {len(header)} columns"
            )
    index = [header.index(name) for name in names]
    try:
        values = np.array([[float(r[k]) for k in index] for r in body], dtype=float)
    except ValueError as error:
        raise SymkinError(f"{path}: a value is not a number ({error})") from None
    values = values.reshape(len(body), len(names))
    bad = np.flatnonzero(~np.isfinite(values).all(axis=1))
    if bad.size:
        lines = ", ".join(str(b + 2) for b in bad[:5]) + (" ..." if bad.size > 5 else "")
        raise SymkinError(f"{path}: {bad.size} rows hold NaN or infinite values (lines {lines})")
    return {name: values[:, k] for k, name in enumerate(names)}


def _data_text(path: Path) -> str:
    """The text of a data file, read by the robot-file reader's size and file-type check."""
    try:
        data = read_limited(path, str(path), MAX_DATA_BYTES, DATA_FILE_KIND)
    except OSError as error:
        raise SymkinError(f"{path}: cannot read the data file ({error.strerror})") from None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        raise SymkinError(f"{path}: the data file is not UTF-8 text") from None


def _joint_names(prefix: str, dof: int) -> list[str]:
    return [f"{prefix}{i}" for i in range(1, dof + 1)]


def logged_samples(path: Path, dof: int) -> Samples:
    """``q, dq, ddq, tau`` as logged (module docstring)."""
    names = {p: _joint_names(p, dof) for p in ("q", "dq", "ddq", "tau")}
    columns = read_columns(path, [n for group in names.values() for n in group])

    def stack(prefix: str) -> np.ndarray:
        return np.column_stack([columns[n] for n in names[prefix]])

    return Samples(stack("q"), stack("dq"), stack("ddq"), stack("tau"))


def filtered_samples(path: Path, dof: int, cutoff: float) -> Samples:
    """``q, tau`` low-passed at ``cutoff`` Hz and ``dq, ddq`` differentiated (module
    docstring); the time column ``t`` must be uniformly spaced."""
    from scipy.signal import butter, filtfilt  # scipy: only this path needs it

    q_names, tau_names = _joint_names("q", dof), _joint_names("tau", dof)
    columns = read_columns(path, ["t", *q_names, *tau_names])
    t = columns["t"]
    steps = np.diff(t)
    if len(t) < 3 * (FILTER_ORDER + 1) * 2 or steps.min() <= 0:
        raise SymkinError(
            f"{path}: --filter needs at least {6 * (FILTER_ORDER + 1)} samples with "
            "increasing times t"
        )
    dt = float(np.mean(steps))
    if np.max(np.abs(steps - dt)) > 1e-6 * dt + 1e-12:
        raise SymkinError(f"{path}: --filter needs uniformly spaced times t")
    nyquist = 0.5 / dt
    if not 0.0 < cutoff < nyquist:
        raise SymkinError(
            f"--filter cut-off {cutoff:g} Hz must lie between 0 and the Nyquist frequency "
            f"{nyquist:g} Hz of {path}"
        )
    b, a = butter(FILTER_ORDER, cutoff / nyquist)
    q = filtfilt(b, a, np.column_stack([columns[n] for n in q_names]), axis=0)
    tau = filtfilt(b, a, np.column_stack([columns[n] for n in tau_names]), axis=0)
    dq = np.gradient(q, dt, axis=0)
    ddq = np.gradient(dq, dt, axis=0)
    edge = int(np.ceil(EDGE_PERIODS / (cutoff * dt)))
    if len(t) <= 2 * edge:
        raise SymkinError(
            f"{path}: --filter {cutoff:g} drops {EDGE_PERIODS:g} cut-off periods "
            f"({edge} samples) at either end, which leaves none of the {len(t)} samples"
        )
    inner = slice(edge, -edge)
    return Samples(q[inner], dq[inner], ddq[inner], tau[inner])
