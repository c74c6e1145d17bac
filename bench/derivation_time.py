"""Derivation time of symkin's kinematics per catalogue robot, against Robotics Toolbox.

Every repetition runs in a fresh Python process, so neither :func:`symkin.derive`'s model
cache nor SymPy's caches carry over from one repetition to the next.  A child imports its
library (not timed), builds the robot object (not timed), then times:

* symkin: ``m = symkin.derive(robot); m.forward_kinematics; m.geometric_jacobian`` and,
  separately, ``m.determinant()`` (factored determinant of the task Jacobian);
* Robotics Toolbox (roboticstoolbox-python, the ``bench`` extra): ``fkine(q)`` + ``jacob0(q)``
  with SymPy symbols ``q`` (unsimplified), and in other children the same followed by
  ``sympy.trigsimp`` of every entry, under a limit of ``--peer-timeout`` CPU seconds.

Times are CPU seconds of the child (``time.process_time``), which other load on the shared
machine barely moves; the load average at the start and end is recorded with the table.

Size is ``sympy.count_ops`` summed over every entry of the 4x4 pose and the 6xn Jacobian.
The script prints a Markdown table and writes it into ``docs/benchmarks.md`` between
``<!-- derivation-time:begin -->`` and ``<!-- derivation-time:end -->``.

Usage::

    .venv/bin/python bench/derivation_time.py                 # 5 repetitions, all robots
    .venv/bin/python bench/derivation_time.py --repeat 3 --peer-timeout 120
    .venv/bin/python bench/derivation_time.py --robots puma560 panda --no-write
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
    except _TimeLimit:
        return {"timeout": limit}
    result = {"dof": robot.dof, "fk_jac_s": fk_jac_s, "det_s": None}
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


def _child_rtb(model: str, simplify: bool, limit: float) -> dict:
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
            if simplify:
                entries = [sympy.trigsimp(sympy.sympify(e)) for e in entries]
            seconds = CLOCK() - start
    except _TimeLimit:
        return {"timeout": limit}
    ops = int(sympy.count_ops([sympy.sympify(e) for e in entries]))
    result = {"dof": robot.n, "seconds": seconds, "ops": ops}
    if not simplify:  # after the timing: is it the same arm as symkin's?
        (catalogue_name,) = (name for name, (m, _) in PEERS.items() if m == model)
        result["disagreement"] = _disagreement(robot, catalogue_name)
    return result


def _child(argv: list[str]) -> None:
    kind, name, limit = argv[0], argv[1], float(argv[2])
    if kind == "symkin":
        result = _child_symkin(name, limit)
    elif kind in ("rtb", "rtb-trigsimp"):
        result = _child_rtb(name, kind == "rtb-trigsimp", limit)
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


def render(
    symkin_runs: dict[str, Runs],
    peer_runs: dict[str, dict[str, Runs]],
    args: argparse.Namespace,
    load: tuple[float, float],
) -> str:
    today = datetime.datetime.now(datetime.UTC).date().isoformat()
    cores = os.cpu_count()
    runs_text = f"{args.repeat} run{'s' if args.repeat > 1 else ''}"
    lines = [
        f"Measured on {today}: {cpu_model()}, {cores} cores; Python {platform.python_version()}, "
        f"SymPy {version('sympy')}, symkin {version('symkin')}, roboticstoolbox-python "
        f"{version('roboticstoolbox-python')}, spatialmath-python "
        f"{version('spatialmath-python')}. Times are CPU seconds, median (min–max) of "
        f"{runs_text}, each in a fresh Python process; peer time limit "
        f"{args.peer_timeout:g} s. Load average (1 min) at the start and end of the run: "
        f"{load[0]:.1f} and {load[1]:.1f}. Generated by `bench/derivation_time.py`.",
        "",
        "### symkin, every catalogue robot",
        "",
        "| robot | DOF | FK + Jacobian [s] | determinant [s] | FK + Jacobian size [ops] |",
        "| --- | ---: | ---: | ---: | ---: |",
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
            f"| {det} | {ops if ops is not None else '—'} |"
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

    if peer_runs:
        lines += [
            "",
            "### Against Robotics Toolbox (same run)",
            "",
            "The ratio is the peer's median over symkin's median FK + Jacobian time "
            "(how many times longer it takes).",
            "",
            "| robot | how | FK + Jacobian [s] | size [ops] | ratio to symkin |",
            "| --- | --- | ---: | ---: | ---: |",
        ]
        for name, peers in peer_runs.items():
            ours = symkin_runs.get(name, Runs())
            reference = ours.median("fk_jac_s")
            ops = ours.last("ops")
            lines.append(
                f"| {name} | symkin `derive` (simplified) | {timing_cell(ours, 'fk_jac_s')} "
                f"| {ops if ops is not None else '—'} | 1 |"
            )
            for label, runs in peers.items():
                ops = runs.last("ops")
                lines.append(
                    f"| {name} | {label} | {timing_cell(runs, 'seconds')} "
                    f"| {ops if ops is not None else '—'} "
                    f"| {ratio_cell(runs, 'seconds', reference)} |"
                )
        checks = [
            f"{name} {max(runs.values('disagreement')):.0e}"
            for name, peers in peer_runs.items()
            for runs in list(peers.values())[:1]
            if runs.values("disagreement")
        ]
        if checks:
            lines += [
                "",
                "Same arms: largest difference between RTB's and symkin's Jacobian and tool "
                "rotation at random joint angles, in this run: " + ", ".join(checks) + ".",
            ]
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


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=5, help="runs per measurement (5)")
    parser.add_argument(
        "--peer-timeout",
        type=float,
        default=300.0,
        help="time limit of one Robotics Toolbox run, seconds (300)",
    )
    parser.add_argument(
        "--timeout", type=float, default=600.0, help="time limit of one symkin run, seconds (600)"
    )
    parser.add_argument(
        "--robots", nargs="+", metavar="NAME", help="catalogue robots to measure (default: all)"
    )
    parser.add_argument("--no-peers", action="store_true", help="skip Robotics Toolbox")
    parser.add_argument("--docs", type=Path, default=DOCS, help=f"file to update ({DOCS})")
    parser.add_argument("--no-write", action="store_true", help="print only")
    parser.add_argument("--child", nargs=3, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)

    if args.child:
        _child(args.child)
        return 0
    if args.repeat < 1:
        parser.error("--repeat must be at least 1")

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
    symkin_runs = {name: measure("symkin", name, args.repeat, args.timeout) for name in names}

    peer_runs: dict[str, dict[str, Runs]] = {}
    if not args.no_peers:
        for name, (model, label) in PEERS.items():
            if name not in names:
                continue
            raw = measure("rtb", model, args.repeat, args.peer_timeout)
            if raw.error is None:
                simplified = measure("rtb-trigsimp", model, args.repeat, args.peer_timeout)
            else:  # not installed: say so in both rows
                simplified = Runs(error=raw.error)
            peer_runs[name] = {
                f"{label}: `fkine` + `jacob0`, unsimplified": raw,
                f"{label}: the same + `trigsimp` of every entry": simplified,
            }

    table = render(symkin_runs, peer_runs, args, (load_start, os.getloadavg()[0]))
    print(table)
    if not args.no_write:
        write_docs(table, args.docs)
        _progress(f"wrote {args.docs}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
