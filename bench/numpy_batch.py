"""Batch FK from Python: the generated NumPy module against SymEngine's LLVM ``Lambdify``,
time and peak memory at 10^5 and 10^6 configurations of the PUMA 560.

Contenders (all return the (N, 4, 4) poses of an (N, 6) array of joint values):

* symkin's generated NumPy module, ``generated/puma560/numpy/puma560_kinematics.py``, ``fk(Q)``;
* with ``--before FILE``, another version of that module (for example the one before a change:
  ``git show REV:generated/puma560/numpy/puma560_kinematics.py > FILE``), ``fk(Q)``;
* SymEngine ``Lambdify(q, T, backend="llvm", cse=True)`` of symkin's FK matrix with the
  parameters substituted as numbers (the same expression; SymEngine compiles it with LLVM).

Before timing, every contender's poses are compared with symkin's at 1,000 configurations
(largest difference below 1e-12).  Time: the contenders alternate call by call within each round,
in an order that rotates from round to round; each call is timed by the CPU clock of the calling
thread (``time.thread_time_ns``; every contender computes in that thread); medians over the
rounds, configurations per second from the median.  Memory: each contender runs alone in a fresh
child process per batch size, which builds the contender and the inputs, calls it once on 1,000
configurations, resets its peak resident set (``/proc/self/clear_refs``), calls it on the batch
and reports its peak (``VmHWM``) minus its resident set just before the call; this is shown in MB
and over the size of the output (N * 16 doubles).  The load average (1 min) is recorded at the
start and end.  The table goes into ``docs/benchmarks.md`` between
``<!-- numpy-batch:begin -->`` and ``<!-- numpy-batch:end -->``.

Usage::

    .venv/bin/python bench/numpy_batch.py [--before FILE] [--rounds 9] [--no-write]
"""

from __future__ import annotations

import argparse
import datetime
import importlib.util
import json
import os
import platform
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
MODULE = ROOT / "generated" / "puma560" / "numpy" / "puma560_kinematics.py"
DOCS = ROOT / "docs" / "benchmarks.md"
BEGIN, END = "<!-- numpy-batch:begin -->", "<!-- numpy-batch:end -->"
SIZES = (100_000, 1_000_000)
TOLERANCE = 1e-12
LABELS = {
    "symkin": "symkin NumPy module `fk(Q)`",
    "before": "symkin NumPy module `fk(Q)`, before (`--before`)",
    "llvm": 'SymEngine `Lambdify(..., backend="llvm", cse=True)`',
}


def _load(path: Path, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _llvm_fk() -> Callable[[np.ndarray], np.ndarray]:
    import symengine

    from symkin import derive, load_robot

    robot = load_robot("puma560")
    model = derive(robot)
    values = dict(zip(robot.parameter_symbols, robot.parameter_values().values(), strict=True))
    matrix = model.forward_kinematics.subs(values)
    return symengine.Lambdify(
        [symengine.sympify(s) for s in model.q],
        symengine.Matrix(matrix.tolist()),
        backend="llvm",
        cse=True,
    )


def build(name: str, before: Path | None) -> Callable[[np.ndarray], np.ndarray]:
    """The contender's batch FK."""
    if name == "symkin":
        return _load(MODULE, "symkin_now").fk
    if name == "before":
        return _load(before, "symkin_before").fk
    return _llvm_fk()


def configurations(n: int, seed: int = 2026) -> np.ndarray:
    return np.random.default_rng(seed).uniform(-np.pi, np.pi, size=(n, 6))


def _status_kb(key: str) -> int:
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith(key + ":"):
            return int(line.split()[1])
    raise RuntimeError(f"no {key} in /proc/self/status")


def child(name: str, n: int, before: Path | None) -> dict[str, int]:
    """Peak memory of one batch call above the resident set before it, in bytes."""
    fk = build(name, before)
    q = configurations(n)
    fk(q[:1000])
    Path("/proc/self/clear_refs").write_text("5")  # resets VmHWM to the current VmRSS
    base = _status_kb("VmRSS")
    poses = fk(q)
    peak = _status_kb("VmHWM")
    return {"extra": (peak - base) * 1024, "output": int(poses.nbytes)}


def memory(name: str, n: int, before: Path | None) -> dict[str, int]:
    command = [sys.executable, __file__, "--child", name, str(n)]
    if before:
        command += ["--before", str(before)]
    done = subprocess.run(command, capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def check(fks: dict[str, Callable]) -> dict[str, float]:
    q = configurations(1000, seed=7)
    reference = fks["symkin"](q)
    errors = {name: float(np.abs(fk(q) - reference).max()) for name, fk in fks.items()}
    bad = {name: e for name, e in errors.items() if not e < TOLERANCE}
    if bad:
        raise SystemExit(f"numpy_batch: contenders disagree with symkin: {bad}")
    return errors


def timings(fks: dict[str, Callable], n: int, rounds: int) -> dict[str, list[float]]:
    """CPU seconds per call, contenders alternated, the order rotating each round."""
    q = configurations(n)
    names = list(fks)
    times: dict[str, list[float]] = {name: [] for name in names}
    for r in range(rounds):
        for name in names[r % len(names) :] + names[: r % len(names)]:
            start = time.thread_time_ns()
            poses = fks[name](q)
            times[name].append((time.thread_time_ns() - start) * 1e-9)
            del poses
    return times


def table(results: dict, loads: tuple, rounds: int) -> str:
    lines = [
        "| how | N | time [ms], median | configurations/s | ratio to SymEngine LLVM "
        "| peak above start [MB] | peak / output |",
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    for n, per in results.items():
        llvm = statistics.median(per["llvm"]["times"])
        for name, r in per.items():
            median = statistics.median(r["times"])
            extra, output = r["memory"]["extra"], r["memory"]["output"]
            label = f"**{LABELS[name]}**" if name == "symkin" else LABELS[name]
            lines.append(
                f"| {label} | {n:,} | {median * 1e3:.1f} | {n / median / 1e6:.2f} M "
                f"| {median / llvm:.2f}× | {extra / 1e6:.0f} | {extra / output:.2f}× |"
            )
    when = datetime.date.today().isoformat()
    lines += [
        "",
        f"Measured on {when}: {_cpu()}, "
        f"{os.cpu_count()} cores shared with other jobs; Python {platform.python_version()}, "
        f"NumPy {np.__version__}, SymEngine {_version('symengine')}. {rounds} rounds per size; "
        f"load average (1 min) at the start and end: {loads[0]:.1f} and {loads[1]:.1f}. "
        "The output is N × 128 bytes (128 MB at 10^6). Generated by `bench/numpy_batch.py`.",
    ]
    return "\n".join(lines)


def _cpu() -> str:
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            return line.split(":", 1)[1].strip()
    return platform.machine()


def _version(package: str) -> str:
    from importlib import metadata

    return metadata.version(package)


def write(text: str) -> None:
    docs = DOCS.read_text()
    start, end = docs.index(BEGIN) + len(BEGIN), docs.index(END)
    DOCS.write_text(docs[:start] + "\n" + text + "\n" + docs[end:])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", type=Path)
    parser.add_argument("--rounds", type=int, default=9)
    parser.add_argument("--no-write", action="store_true")
    parser.add_argument("--child", nargs=2, metavar=("NAME", "N"))
    args = parser.parse_args()
    if args.child:
        print(json.dumps(child(args.child[0], int(args.child[1]), args.before)))
        return
    names = ["symkin", *(["before"] if args.before else []), "llvm"]
    loads = [os.getloadavg()[0]]
    fks = {name: build(name, args.before) for name in names}
    print("largest difference to symkin:", check(fks))
    results = {}
    for n in SIZES:
        times = timings(fks, n, args.rounds)
        results[n] = {
            name: {"times": times[name], "memory": memory(name, n, args.before)} for name in names
        }
    loads.append(os.getloadavg()[0])
    text = table(results, tuple(loads), args.rounds)
    print(text)
    if not args.no_write:
        write(text)


if __name__ == "__main__":
    main()
