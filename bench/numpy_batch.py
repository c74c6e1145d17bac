"""Batch FK from Python: the generated NumPy module against SymEngine's LLVM ``Lambdify``,
time and peak memory at 10^5 and 10^6 configurations of the PUMA 560.

Contenders (all return the (N, 4, 4) poses of an (N, 6) array of joint values):

* symkin's generated NumPy module, ``generated/puma560/numpy/puma560_kinematics.py``, ``fk(Q)``;
* the module as it was before the batch path was rewritten (issue 17): that file at commit
  ``--before-rev`` (715cbe7), read with ``git show`` into a temporary file, or any other
  version given with ``--before FILE``; left out (and said so) outside a git checkout;
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
start and end.  A second table times single configurations (``fk(q)`` on 2,000 distinct
``q`` per round, the same alternation), the path of per-call users.  The tables go into
``docs/benchmarks.md`` between ``<!-- numpy-batch:begin -->`` and ``<!-- numpy-batch:end -->``.

Usage::

    .venv/bin/python bench/numpy_batch.py [--quick] [--before FILE | --before-rev REV] [--no-write]
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
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
MODULE = ROOT / "generated" / "puma560" / "numpy" / "puma560_kinematics.py"
DOCS = ROOT / "docs" / "benchmarks.md"
BEGIN, END = "<!-- numpy-batch:begin -->", "<!-- numpy-batch:end -->"
SIZES = (100_000, 1_000_000)
SINGLE = 2_000  # distinct configurations per round in the per-call table
BEFORE_REV = "715cbe7"  # the last commit before the blocked batch path
TOLERANCE = 1e-12
LABELS = {
    "symkin": "symkin NumPy module `fk(Q)`",
    "before": "symkin NumPy module `fk(Q)` before the change (715cbe7)",
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


def single_timings(fks: dict[str, Callable], rounds: int) -> dict[str, list[float]]:
    """CPU seconds per single-configuration call, alternated as in :func:`timings`."""
    qs = list(configurations(SINGLE, seed=11))
    names = list(fks)
    times: dict[str, list[float]] = {name: [] for name in names}
    for r in range(rounds):
        for name in names[r % len(names) :] + names[: r % len(names)]:
            fk = fks[name]
            start = time.thread_time_ns()
            for q in qs:
                fk(q)
            times[name].append((time.thread_time_ns() - start) * 1e-9 / SINGLE)
    return times


def single_table(times: dict[str, list[float]]) -> str:
    llvm = statistics.median(times["llvm"])
    lines = [
        "| how | time per call [µs], median | ratio to SymEngine LLVM |",
        "| --- | ---: | ---: |",
    ]
    for name, values in times.items():
        median = statistics.median(values)
        label = LABELS[name].replace("fk(Q)", "fk(q)")
        label = f"**{label}**" if name == "symkin" else label
        lines.append(f"| {label} | {median * 1e6:.1f} | {median / llvm:.2f}× |")
    return "\n".join(lines)


def table(results: dict) -> str:
    lines = [
        "### Batches",
        "",
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
    return "\n".join(lines)


def footer(loads: tuple, rounds: int, before: str) -> str:
    when = datetime.date.today().isoformat()
    return (
        f"Measured on {when}: {_cpu()}, {os.cpu_count()} cores shared with other jobs; Python "
        f"{platform.python_version()}, NumPy {np.__version__}, SymEngine {_version('symengine')}. "
        f"{rounds} rounds per table and size; {before}. Load average (1 min) at the start and "
        f"end: {loads[0]:.1f} and {loads[1]:.1f}. The output is N × 128 bytes (128 MB at 10^6). "
        "Generated by `bench/numpy_batch.py`."
    )


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


def before_file(args: argparse.Namespace) -> Path | None:
    """``--before``, or the module at ``--before-rev`` written to a temporary file."""
    if args.before:
        return args.before
    path = "generated/puma560/numpy/puma560_kinematics.py"
    command = ["git", "-C", str(ROOT), "show", f"{args.before_rev}:{path}"]
    try:
        text = subprocess.run(command, capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    file = Path(tempfile.mkdtemp(prefix="numpy_batch_")) / "before.py"
    file.write_text(text)
    return file


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", type=Path, help="another version of the module")
    parser.add_argument("--before-rev", default=BEFORE_REV, help="git revision of 'before'")
    parser.add_argument("--quick", action="store_true", help="5 rounds instead of 9")
    parser.add_argument("--rounds", type=int)
    parser.add_argument("--no-write", action="store_true")
    parser.add_argument("--child", nargs=2, metavar=("NAME", "N"))
    args = parser.parse_args()
    if args.child:
        print(json.dumps(child(args.child[0], int(args.child[1]), args.before)))
        return
    rounds = args.rounds or (5 if args.quick else 9)
    before = before_file(args)
    names = ["symkin", *(["before"] if before else []), "llvm"]
    loads = [os.getloadavg()[0]]
    fks = {name: build(name, before) for name in names}
    print("largest difference to symkin:", check(fks))
    results = {}
    for n in SIZES:
        times = timings(fks, n, rounds)
        results[n] = {
            name: {"times": times[name], "memory": memory(name, n, before)} for name in names
        }
    single = single_timings(fks, rounds)
    loads.append(os.getloadavg()[0])
    said = f"before: {args.before or args.before_rev}" if before else "before: not run (no git)"
    text = "\n\n".join(
        [
            table(results),
            "### Single configurations",
            single_table(single),
            footer(tuple(loads), rounds, said),
        ]
    )
    print(text)
    if not args.no_write:
        write(text)


if __name__ == "__main__":
    main()
