"""Derivation time and peak memory of symkin's kinematics per catalogue robot, against Robotics
Toolbox like with like, and the whole ``symkin derive`` command against whole peer processes.

Every repetition runs in a fresh Python process, so neither :func:`symkin.derive`'s model
cache nor SymPy's caches carry over from one repetition to the next, and the contenders
alternate round by round (every robot's symkin child, then its peer's; again), so that load
drifting during the run falls on all of them alike.  A child imports its library (not timed),
builds the robot object (not timed), then times:

* symkin: ``m = symkin.derive(robot); m.forward_kinematics; m.geometric_jacobian`` (readable),
  then ``sympy.cse`` of those entries, and separately ``m.determinant()`` (factored
  determinant of the task Jacobian);
* Robotics Toolbox (roboticstoolbox-python, the ``bench`` extra): ``fkine(q)`` + ``jacob0(q)``
  with SymPy symbols ``q`` (its raw output), then ``sympy.cse`` of those entries, the same
  call as for symkin's: the same quantities, made ready to print as code, by both.

Times are CPU seconds of the child (``time.process_time``), which other load on the shared
machine barely moves; peak RSS (``ru_maxrss``) is read in the child right after the CSE, so
it covers the library's import and the derivation; the load average at the start and end is
recorded with the table.  Size is ``sympy.count_ops`` summed over every entry of the 4x4 pose
and the 6xn Jacobian, and after CSE over the common subexpressions and the reduced entries.

``bench/derivation_whole.py`` adds the whole command (``symkin derive puma560 --out DIR``)
against whole peer processes.  The script prints Markdown tables and writes them into
``docs/benchmarks.md`` between ``<!-- derivation-time:begin -->`` and
``<!-- derivation-time:end -->``.

Usage::

    .venv/bin/python bench/derivation_time.py                 # 5 rounds, all robots
    .venv/bin/python bench/derivation_time.py --quick         # 3 rounds, 3 whole-command rounds
    .venv/bin/python bench/derivation_time.py --robots puma560 panda --no-whole --no-write
    .venv/bin/python bench/derivation_time.py --sympybotics /somewhere/SymPyBotics
"""

from __future__ import annotations

import argparse
import contextlib
import datetime
import json
import math
import os
import platform
import signal
import statistics
import subprocess
import sys
import time
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs" / "benchmarks.md"
BEGIN = "<!-- derivation-time:begin -->"
END = "<!-- derivation-time:end -->"

# Catalogue robot -> (Robotics Toolbox model of the same arm, how the table names it).
PEERS = {
    "puma560": ("Puma560", "RTB `DH.Puma560(symbolic=True)`"),
    "panda": ("Panda", "RTB `DH.Panda` table with exact twists"),
}
# The targets for readable FK + Jacobian, in seconds.
TARGETS = {"puma560": 1.0, "panda": 3.0}
# The clock of every timing: CPU seconds of the child process.  For these single-threaded
# computations it equals wall time on an idle machine, and unlike wall time it is barely
# moved by other programs sharing the machine's two cores.
CLOCK = time.process_time


def backstop(limit: float) -> float:
    """Wall seconds after which the parent kills a child whose CPU limit is ``limit``."""
    return 10 * limit + 300


# --------------------------------------------------------------------------- children
# Each child prints exactly one JSON object on its last line of stdout.


class _TimeLimit(BaseException):
    """Raised in a child when its timed section runs out of time (not an ``Exception``, so
    that no ``except Exception`` inside a library swallows it)."""


@contextlib.contextmanager
def _time_limit(seconds: float):
    """Interrupt the block after ``seconds`` of CPU time (as :data:`CLOCK` counts it)."""

    def expire(signum, frame):
        raise _TimeLimit

    previous = signal.signal(signal.SIGPROF, expire)
    signal.setitimer(signal.ITIMER_PROF, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.signal(signal.SIGPROF, previous)


def peak_rss_mb() -> float:
    """Peak resident set size of this process's own memory so far, in MB: ``VmHWM`` of
    ``/proc/self/status``.  Not ``ru_maxrss``: Linux carries the parent's peak through
    ``fork``/``vfork`` and ``exec`` into the child's ``ru_maxrss`` (a bare ``python -c pass``
    started from a 150 MB parent reports 150 MB), while ``VmHWM`` belongs to the address space
    made by ``exec``.  Without ``/proc`` (macOS), ``ru_maxrss`` (bytes there)."""
    import resource

    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20


def _cse(entries: list) -> tuple[float, int]:
    """CPU seconds of ``sympy.cse`` over ``entries`` and the size of its result (operations
    of the common subexpressions plus those of the reduced entries)."""
    import sympy

    start = CLOCK()
    replacements, reduced = sympy.cse(entries)
    seconds = CLOCK() - start
    return seconds, int(sympy.count_ops([v for _, v in replacements]) + sympy.count_ops(reduced))


def _child_symkin(name: str, limit: float) -> dict:
    import sympy

    import symkin

    robot = symkin.load_robot(name)
    try:
        with _time_limit(limit):
            start = CLOCK()
            model = symkin.derive(robot)
            fk = model.forward_kinematics
            jac = model.geometric_jacobian
            fk_jac_s = CLOCK() - start
            cse_s, cse_ops = _cse([*fk, *jac])
    except _TimeLimit:
        return {"timeout": limit}
    result = {
        "dof": robot.dof,
        "fk_jac_s": fk_jac_s,
        "det_s": None,
        "cse_s": cse_s,
        "cse_ops": cse_ops,
        "rss_mb": peak_rss_mb(),
    }
    try:
        with _time_limit(limit):
            start = CLOCK()
            det = model.determinant()
            det_s = CLOCK() - start
        if det is not None:
            result["det_s"] = det_s
    except _TimeLimit:
        result["det_timeout"] = limit
    result["ops"] = int(sympy.count_ops([*fk, *jac]))
    return result


def _rtb_robot(model: str):
    """The Robotics Toolbox arm, with exact (SymPy) twist angles."""
    import roboticstoolbox as rtb
    import spatialmath.base.symbolic as sym
    import sympy

    if model == "Puma560":
        return rtb.models.DH.Puma560(symbolic=True)
    if model == "Panda":
        # models.DH.Panda has no ``symbolic`` option: its twists are floats (np.pi / 2), which
        # leave terms like 6.1e-17*sin(q1) in every product.  Rebuild its DH table with the
        # twists as exact multiples of pi, as Puma560(symbolic=True) does, and without the
        # gripper tool it adds, so that the pose is the flange's, like symkin's panda.
        shipped = rtb.models.DH.Panda()
        links = [
            rtb.RevoluteMDH(
                a=link.a, d=link.d, alpha=sympy.nsimplify(link.alpha / math.pi) * sym.pi()
            )
            for link in shipped.links
        ]
        return rtb.DHRobot(links, name="Panda (exact twists)")
    raise ValueError(model)


def _disagreement(robot, catalogue_name: str) -> float:
    """Largest difference of RTB's and symkin's Jacobian and tool rotation at random ``q``.

    (Positions are left out: RTB's PUMA 560 stands on a 0.672 m pedestal.)
    """
    import numpy as np

    import symkin

    model = symkin.derive(symkin.load_robot(catalogue_name))
    rng = np.random.default_rng(560)
    worst = 0.0
    for _ in range(3):
        q = rng.uniform(-np.pi, np.pi, robot.n)
        state = symkin.kinematic_state(model, q=list(q))
        jacobian = np.asarray(robot.jacob0(q), dtype=float)
        rotation = np.asarray(robot.fkine(q).A, dtype=float)[:3, :3]
        worst = max(
            worst,
            float(np.abs(np.asarray(state.jacobian, dtype=float) - jacobian).max()),
            float(np.abs(np.asarray(state.transform, dtype=float)[:3, :3] - rotation).max()),
        )
    return worst


def _child_rtb(model: str, limit: float) -> dict:
    try:
        import roboticstoolbox  # noqa: F401
        import spatialmath.base.symbolic as sym
        import sympy
    except ModuleNotFoundError:
        return {"error": "not installed"}
    except Exception as error:  # an install that is broken, e.g. by a numpy mismatch
        return {"error": f"not importable ({type(error).__name__}: {error})"}

    robot = _rtb_robot(model)
    q = sym.symbol(f"q1:{robot.n + 1}")
    try:
        with _time_limit(limit):
            start = CLOCK()
            entries = [*robot.fkine(q).A.flat, *robot.jacob0(q).flat]
            seconds = CLOCK() - start
            entries = [sympy.sympify(e) for e in entries]
            cse_s, cse_ops = _cse(entries)
    except _TimeLimit:
        return {"timeout": limit}
    result = {
        "dof": robot.n,
        "seconds": seconds,
        "ops": int(sympy.count_ops(entries)),
        "cse_s": cse_s,
        "cse_ops": cse_ops,
        "rss_mb": peak_rss_mb(),
    }
    # After the timing: is it the same arm as symkin's?
    (catalogue_name,) = (name for name, (m, _) in PEERS.items() if m == model)
    result["disagreement"] = _disagreement(robot, catalogue_name)
    return result


def _child(argv: list[str]) -> None:
    kind, name, limit = argv[0], argv[1], float(argv[2])
    if kind == "symkin":
        result = _child_symkin(name, limit)
    elif kind == "rtb":
        result = _child_rtb(name, limit)
    else:
        raise SystemExit(f"unknown child kind {kind!r}")
    print(json.dumps(result))


# --------------------------------------------------------------------------- parent


@dataclass
class Runs:
    """The repetitions of one measurement."""

    results: list[dict] = field(default_factory=list)
    timeout: float | None = None  # set when a run hit the time limit
    error: str | None = None

    def values(self, key: str) -> list[float]:
        return [r[key] for r in self.results if r.get(key) is not None]

    def median(self, key: str) -> float | None:
        values = self.values(key)
        return statistics.median(values) if values else None

    def last(self, key: str):
        return self.results[-1][key] if self.results else None


def run_child(kind: str, name: str, timeout: float, script: Path = Path(__file__)) -> dict:
    """One fresh process; ``{"timeout": s}`` or ``{"error": ...}`` when it does not finish.

    The child is ``script --child KIND NAME TIMEOUT`` (this script's by default).  It applies
    ``timeout`` to its timed sections itself (imports and checks are not counted); the parent
    kills it only after :func:`backstop` seconds of wall time.
    """
    command = [sys.executable, str(script.resolve()), "--child", kind, name, f"{timeout}"]
    try:
        done = subprocess.run(
            command,
            capture_output=True,
            text=True,
            timeout=backstop(timeout),
            cwd=ROOT,
            check=False,
        )
    except subprocess.TimeoutExpired:
        return {"error": f"killed after {backstop(timeout):g} s of wall time"}
    lines = done.stdout.strip().splitlines()
    if done.returncode != 0 or not lines:
        tail = (done.stderr.strip().splitlines() or ["no output"])[-1]
        return {"error": f"failed (exit {done.returncode}: {tail})"}
    return json.loads(lines[-1])


def measure(
    kind: str, name: str, repeat: int, timeout: float, script: Path = Path(__file__)
) -> Runs:
    """``repeat`` cold runs; stops early after a timeout or error (the next would do the same)."""
    runs = Runs()
    for i in range(repeat):
        result = run_child(kind, name, timeout, script)
        if "timeout" in result:
            runs.timeout = result["timeout"]
            _progress(
                f"{kind:13} {name:22} run {i + 1}/{repeat}: did not finish in "
                f"{timeout:g} s, not repeated"
            )
            break
        if "error" in result:
            runs.error = result["error"]
            _progress(f"{kind:13} {name:22} {runs.error}")
            break
        runs.results.append(result)
        seconds = result.get("fk_jac_s", result.get("seconds"))
        _progress(f"{kind:13} {name:22} run {i + 1}/{repeat}: {seconds:.3f} s")
    return runs


def alternate(jobs: list[tuple[str, str, float]], repeat: int) -> dict[tuple[str, str], Runs]:
    """``repeat`` rounds of every ``(kind, name, timeout)`` job in turn, one fresh process each;
    a job that timed out or failed is not run again (the next run would do the same)."""
    runs = {(kind, name): Runs() for kind, name, _ in jobs}
    for i in range(repeat):
        for kind, name, timeout in jobs:
            done = runs[kind, name]
            if done.timeout is not None or done.error is not None:
                continue
            result = run_child(kind, name, timeout)
            if "timeout" in result:
                done.timeout = result["timeout"]
                _progress(
                    f"{kind:8} {name:22} round {i + 1}/{repeat}: did not finish in "
                    f"{timeout:g} s, not repeated"
                )
            elif "error" in result:
                done.error = result["error"]
                _progress(f"{kind:8} {name:22} {done.error}")
            else:
                done.results.append(result)
                seconds = result.get("fk_jac_s", result.get("seconds"))
                _progress(
                    f"{kind:8} {name:22} round {i + 1}/{repeat}: {seconds:.3f} s, "
                    f"{result['rss_mb']:.0f} MB"
                )
    return runs


def _progress(text: str) -> None:
    print(text, file=sys.stderr, flush=True)


def cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def version(package: str) -> str:
    try:
        return metadata.version(package)
    except metadata.PackageNotFoundError:
        return "not installed"


def measured_line(what: str, load: tuple[float, float], script: str) -> str:
    """The first line of a table: date, machine, ``what`` (versions, method), the load average
    at the start and end of the run and the script that wrote it."""
    today = datetime.datetime.now(datetime.UTC).date().isoformat()
    return (
        f"Measured on {today}: {cpu_model()}, {os.cpu_count()} cores shared with other jobs; "
        f"{what} Load average (1 min) at the start and end of the run: {load[0]:.1f} and "
        f"{load[1]:.1f}. Generated by `bench/{script}`."
    )


# --------------------------------------------------------------------------- table


def seconds_text(value: float) -> str:
    return f"{value:.3f}" if value < 10 else f"{value:.1f}"


def timing_cell(runs: Runs, key: str) -> str:
    """``median (min–max)`` or why there is none."""
    if runs.timeout is not None:
        return f"did not finish in {runs.timeout:g} s"
    if runs.error is not None:
        return runs.error
    values = runs.values(key)
    if not values:
        return "—"
    median = seconds_text(statistics.median(values))
    if len(values) == 1:
        return median
    return f"{median} ({seconds_text(min(values))}–{seconds_text(max(values))})"


def ratio_cell(peer: Runs, key: str, reference: float | None) -> str:
    """Peer median / symkin median: how many times longer the peer takes."""
    if reference is None or reference <= 0:
        return "—"
    if peer.timeout is not None:
        return f"> {peer.timeout / reference:.0f}×"
    median = peer.median(key)
    if median is None:
        return "—"
    ratio = median / reference
    return f"{ratio:.1f}×" if ratio < 100 else f"{ratio:.0f}×"


def _rss_cell(runs: Runs) -> str:
    median = runs.median("rss_mb")
    return "—" if median is None else f"{median:.0f}"


def _symkin_table(symkin_runs: dict[str, Runs]) -> list[str]:
    lines = [
        "### symkin, every catalogue robot",
        "",
        "| robot | DOF | FK + Jacobian [s] | determinant [s] | FK + Jacobian size [ops] "
        "| peak RSS [MB] |",
        "| --- | ---: | ---: | ---: | ---: | ---: |",
    ]
    for name, runs in symkin_runs.items():
        dof = runs.last("dof")
        if runs.values("det_timeout"):
            det = f"did not finish in {runs.values('det_timeout')[0]:g} s"
        elif runs.results and not runs.values("det_s"):
            det = "— (not square)"
        else:
            det = timing_cell(runs, "det_s")
        ops = runs.last("ops")
        lines.append(
            f"| {name} | {dof if dof is not None else '—'} | {timing_cell(runs, 'fk_jac_s')} "
            f"| {det} | {ops if ops is not None else '—'} | {_rss_cell(runs)} |"
        )
    targets = []
    for name, limit in TARGETS.items():
        if name in symkin_runs:
            median = symkin_runs[name].median("fk_jac_s")
            if median is None:
                verdict = "not measured"
            else:
                verdict = f"{seconds_text(median)} s, {'met' if median < limit else 'NOT met'}"
            targets.append(f"{name} < {limit:g} s: {verdict}")
    if targets:
        lines += ["", "Targets for readable FK + Jacobian: " + "; ".join(targets) + "."]
    return lines


def _total(runs: Runs, key: str) -> list[float]:
    """Per run: the derivation (``key``) plus the CSE, CPU seconds."""
    return [r[key] + r["cse_s"] for r in runs.results if r.get(key) is not None]


def _peer_row(name: str, label: str, runs: Runs, key: str, ours: float | None) -> str:
    totals = _total(runs, key)
    if runs.timeout is not None or runs.error is not None or not totals:
        why = timing_cell(runs, key)
        return f"| {name} | {label} | {why} | — | — | — | — | — | — |"
    total = statistics.median(totals)
    ratio = "1" if ours is None else f"{ours / total:.2f}"
    total_text = f"{seconds_text(total)} ({seconds_text(min(totals))}–{seconds_text(max(totals))})"
    return (
        f"| {name} | {label} | {timing_cell(runs, key)} | {timing_cell(runs, 'cse_s')} "
        f"| {total_text if len(totals) > 1 else seconds_text(total)} | {runs.last('ops')} "
        f"| {runs.last('cse_ops')} | {_rss_cell(runs)} | {ratio} |"
    )


def _peer_table(symkin_runs: dict[str, Runs], peer_runs: dict[str, Runs]) -> list[str]:
    lines = [
        "### Like with like: the same quantities from Robotics Toolbox (same run)",
        "",
        "Both sides: the 4×4 pose and the 6×n geometric Jacobian, then one `sympy.cse` over "
        "their entries (what a code printer needs). Derivation and CSE in CPU seconds, "
        "median (min–max); sizes in `sympy.count_ops`, before and after CSE; peak RSS of the "
        "child after the CSE (import included). The ratio is symkin's median derivation + "
        "CSE time over the peer's (below 1: symkin is faster).",
        "",
        "| robot | how | derivation [s] | CSE [s] | derivation + CSE [s] | size [ops] "
        "| after CSE [ops] | peak RSS [MB] | symkin / RTB |",
        "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    for name, peer in peer_runs.items():
        ours = symkin_runs.get(name, Runs())
        totals = _total(ours, "fk_jac_s")
        reference = statistics.median(totals) if totals else None
        lines.append(_peer_row(name, "symkin `derive` (readable)", ours, "fk_jac_s", None))
        theirs = _total(peer, "seconds")
        ratio = reference / statistics.median(theirs) if theirs and reference else None
        row = _peer_row(name, f"{PEERS[name][1]}: `fkine` + `jacob0`", peer, "seconds", None)
        lines.append(row if ratio is None else row.rsplit("| 1 |", 1)[0] + f"| {ratio:.2f} |")
    checks = [
        f"{name} {max(runs.values('disagreement')):.0e}"
        for name, runs in peer_runs.items()
        if runs.values("disagreement")
    ]
    if checks:
        lines += [
            "",
            "Same arms: largest difference between RTB's and symkin's Jacobian and tool "
            "rotation at random joint angles, in this run: " + ", ".join(checks) + ".",
        ]
    return lines


def render(
    symkin_runs: dict[str, Runs],
    peer_runs: dict[str, Runs],
    args: argparse.Namespace,
    load: tuple[float, float],
    whole: list[str] | None = None,
) -> str:
    today = datetime.datetime.now(datetime.UTC).date().isoformat()
    runs_text = f"{args.repeat} round{'s' if args.repeat > 1 else ''}"
    lines = [
        f"Measured on {today}: {cpu_model()}, {os.cpu_count()} cores shared with other jobs; "
        f"Python {platform.python_version()}, SymPy {version('sympy')}, symkin "
        f"{version('symkin')}, roboticstoolbox-python {version('roboticstoolbox-python')}, "
        f"spatialmath-python {version('spatialmath-python')}. Times are CPU seconds, median "
        f"(min–max) of {runs_text} alternated between the contenders, each run in a fresh "
        f"Python process; peer time limit {args.peer_timeout:g} s. Load average (1 min) at the "
        f"start and end of the run: {load[0]:.1f} and {load[1]:.1f}. Generated by "
        "`bench/derivation_time.py`.",
        "",
        *_symkin_table(symkin_runs),
    ]
    if peer_runs:
        lines += ["", *_peer_table(symkin_runs, peer_runs)]
    if whole:
        lines += ["", *whole]
    return "\n".join(lines)


def write_docs(table: str, path: Path) -> None:
    """Put ``table`` between the markers in ``path`` (creating either when missing)."""
    block = f"{BEGIN}\n{table}\n{END}"
    text = path.read_text() if path.exists() else "# Benchmarks\n"
    if BEGIN in text and END in text:
        head, rest = text.split(BEGIN, 1)
        _, tail = rest.split(END, 1)
        text = head + block + tail
    else:
        text = text.rstrip("\n") + f"\n\n## Derivation time\n\n{block}\n"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=5, help="rounds (5; 3 with --quick)")
    parser.add_argument("--quick", action="store_true", help="3 rounds, whole command 3 rounds")
    parser.add_argument(
        "--peer-timeout",
        type=float,
        default=300.0,
        help="time limit of one Robotics Toolbox run, CPU seconds (300)",
    )
    parser.add_argument(
        "--timeout",
        type=float,
        default=600.0,
        help="time limit of one symkin run, CPU seconds (600)",
    )
    parser.add_argument(
        "--robots", nargs="+", metavar="NAME", help="catalogue robots to measure (default: all)"
    )
    parser.add_argument("--no-peers", action="store_true", help="skip Robotics Toolbox")
    parser.add_argument("--no-whole", action="store_true", help="skip the whole-command table")
    parser.add_argument(
        "--sympybotics",
        type=Path,
        metavar="DIR",
        help="SymPyBotics checkout for the whole-command table",
    )
    parser.add_argument("--docs", type=Path, default=DOCS, help=f"file to update ({DOCS})")
    parser.add_argument("--no-write", action="store_true", help="print only")
    parser.add_argument("--child", nargs=3, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.quick and "--repeat" not in (argv if argv is not None else sys.argv):
        args.repeat = 3
    if args.repeat < 1:
        parser.error("--repeat must be at least 1")
    if args.sympybotics is not None and not (args.sympybotics / "sympybotics").is_dir():
        parser.error(f"--sympybotics {args.sympybotics}: no sympybotics package in it")
    return args


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    if args.child:
        _child(args.child)
        return 0

    # The catalogue's names, from a child too: the parent never imports SymPy.
    names = args.robots or json.loads(
        subprocess.run(
            [
                sys.executable,
                "-c",
                "import json, symkin; print(json.dumps(symkin.catalogue_names()))",
            ],
            capture_output=True,
            text=True,
            check=True,
            cwd=ROOT,
        ).stdout
    )

    load_start = os.getloadavg()[0]
    jobs = []
    for name in names:
        jobs.append(("symkin", name, args.timeout))
        if not args.no_peers and name in PEERS:
            jobs.append(("rtb", PEERS[name][0], args.peer_timeout))
    runs = alternate(jobs, args.repeat)
    symkin_runs = {name: runs["symkin", name] for name in names}
    peer_runs = {
        n: runs["rtb", PEERS[n][0]] for n in names if ("rtb", PEERS.get(n, ("",))[0]) in runs
    }
    whole = None
    if not args.no_whole:
        from derivation_whole import measure_whole, render_whole

        samples = measure_whole(args.repeat, args.timeout, args.sympybotics, _progress)
        whole = render_whole(samples, args.sympybotics)

    table = render(symkin_runs, peer_runs, args, (load_start, os.getloadavg()[0]), whole)
    print(table)
    if not args.no_write:
        write_docs(table, args.docs)
        _progress(f"wrote {args.docs}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
