"""Derivation time as arms grow: symkin against SymPyBotics and Pinocchio (issue 15).

Robots: seeded random revolute arms from ``bench/random_arms.py`` (every ``a`` and ``d``
non-zero; twists from {0, +-90 deg} or generic angles; lengths as numbers or as named
parameters; rod-like inertial data), 2 to 12 joints, several seeds per size, plus the
catalogue PUMA 560 and Panda and the issue's Jaco-like 6R.  One *round* is one robot; in it
every measurement below runs in a fresh process, symkin's and the peers' one after the other,
so that load on the shared machine falls on both alike:

* ``symkin derive ROBOT --out DIR``, the whole command as a user runs it (default backends:
  NumPy, C, the compiled Python extension, CasADi): *cold* with a fresh empty
  ``XDG_CACHE_HOME``, then *warm*, the same command again on that cache.  Wall time, CPU time
  (user + system) and peak RSS of the process and of the processes it waited for (the
  compiler), from ``os.wait4``;
* in-process phases, CPU seconds of the timed section only (imports and loading the file
  are not timed): FK + geometric Jacobian; tau, the Newton–Euler recursion and its kernel;
  full dynamics, the M, G, c, C and tau kernels emitted as NumPy, C and CasADi.  Both
  dynamics phases run with symbolic inertia (the file's link data removed), as SymPyBotics has
  it;
* SymPyBotics, from a checkout given by ``--sympybotics DIR`` (it is not on PyPI; without it
  the columns say "not run"): tau (geometry, Newton–Euler with its incremental CSE, the C
  function printed) and its full set (``RobotDynCode``: tau, g, c, C, M and the regressor, each
  printed as C), on the same DH table; afterwards its last-link pose is checked against the
  numeric DH product (``tests/numeric_dh.py``);
* Pinocchio's ``rnea`` per call from Python, the model built with Pinocchio's API from the
  same DH table and inertial data (``tests/test_dynamics_oracles.pinocchio_model``), checked
  first against the inverse dynamics of the NumPy module the cold run wrote.

Every process has a CPU-time limit (``--timeout``, polled) and a wall-time backstop;
one that reaches either is reported as "> T s (timeout)", and the same measurement is not run
on larger arms of the same kind.  Medians over the seeds.  The script prints a Markdown
section and writes it into ``docs/benchmarks.md`` between ``<!-- derivation-scaling:begin -->``
and ``<!-- derivation-scaling:end -->`` (``--out FILE`` writes it to FILE instead).

Usage::

    .venv/bin/python bench/derivation_scaling.py --sympybotics /work/peers/SymPyBotics
    .venv/bin/python bench/derivation_scaling.py --quick --out /tmp/scaling.md
    .venv/bin/python bench/derivation_scaling.py --max-joints 8 --seeds 2 --timeout 120
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import os
import platform
import re
import resource
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

from codegen_speed import write_docs
from derivation_time import CLOCK, cpu_model, seconds_text, version
from random_arms import LENGTH_CHOICES, TWIST_CHOICES, jaco_like_toml, random_arm_toml

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs" / "benchmarks.md"
BEGIN = "<!-- derivation-scaling:begin -->"
END = "<!-- derivation-scaling:end -->"
HEADING = "Scaling on generic arms"
QUICK_SIZES = (2, 4, 6)
# Named arms: (catalogue name or "jaco_like", joints).
NAMED = (("puma560", 6), ("panda", 7), ("jaco_like", 6))
WALL_FACTOR = 4  # wall-time backstop = WALL_FACTOR x the CPU limit + 60 s (2 shared cores)
RNEA_STATES = 1000  # distinct states one timing pass of Pinocchio's rnea walks through
RNEA_PASSES = 5
CHECK_TOLERANCE = 1e-8  # Pinocchio vs symkin torques, relative to the largest torque

# What one round measures, in order: (key, column heading).
KINDS = (
    ("cold", "derive cold"),
    ("warm", "derive warm"),
    ("fkj", "FK + J"),
    ("tau", "tau"),
    ("full", "full dynamics"),
    ("sb-tau", "SymPyBotics tau"),
    ("sb-full", "SymPyBotics full set"),
    ("pin", "Pinocchio rnea"),
)
PEER_KINDS = ("sb-tau", "sb-full")


def _progress(text: str) -> None:
    print(text, file=sys.stderr, flush=True)


# --------------------------------------------------------------------------- children
# A child prints one JSON object on the last line of its stdout.


def _load(source: str, symbolic_inertia: bool = False):
    """The robot (catalogue name or file), optionally without its link data."""
    import dataclasses
    import warnings

    import symkin
    from symkin.errors import RobotWarning

    with warnings.catch_warnings():  # the PUMA's documented triangle-inequality warning
        warnings.simplefilter("ignore", RobotWarning)
        robot = symkin.load_robot(source)
    if symbolic_inertia:
        joints = tuple(dataclasses.replace(j, link=None) for j in robot.joints)
        robot = dataclasses.replace(robot, joints=joints)
    return robot


def _child_fkj(source: str) -> dict:
    import symkin

    robot = _load(source)
    start = CLOCK()
    model = symkin.derive(robot)
    model.forward_kinematics  # noqa: B018 - cached properties: reading them derives them
    model.geometric_jacobian  # noqa: B018
    return {"seconds": CLOCK() - start}


def _child_dynamics(kind: str, source: str) -> dict:
    from dynamics_speed import _child_full, _child_tau

    robot = _load(source, symbolic_inertia=True)
    return (_child_tau if kind == "tau" else _child_full)(robot)


def _sympybotics_definition(source: str):
    """SymPyBotics' ``RobotDef`` of the robot's DH table (alpha, a, d, theta per joint)."""
    import sympy
    import sympybotics

    robot = _load(source)
    rows = []
    for joint in robot.joints:
        if joint.type != "revolute":
            raise SystemExit(f"{source}: SymPyBotics rows here are revolute only")
        angle = "-q" if getattr(joint, "flip", False) else "q"
        rows.append((str(joint.alpha), str(joint.a), str(joint.d), f"{angle} + ({joint.theta})"))
    definition = sympybotics.RobotDef(robot.name, rows, dh_convention=robot.convention)
    definition.frictionmodel = None
    definition.gravityacc = sympy.Matrix([float(g) for g in robot.gravity])
    return definition


def _child_sympybotics(kind: str, source: str, directory: str) -> dict:
    sys.path.insert(0, directory)
    import sympybotics
    from sympybotics.symcode import Subexprs

    definition = _sympybotics_definition(source)
    to_c = sympybotics.robot_code_to_func
    start = CLOCK()
    if kind == "sb-tau":  # what RobotDynCode does for tau, alone
        geometry = sympybotics.Geometry(definition)
        dynamics = sympybotics.Dynamics(definition, geometry)
        collector = Subexprs()
        dynamics.gen_invdyn(collector.collect)
        to_c("C", collector.get(dynamics.invdyn), "tau_out", "tau", definition)
    else:
        model = sympybotics.RobotDynCode(definition)
        geometry = model.geo
        for name in ("invdyn", "g", "c", "C", "M", "H"):
            to_c("C", getattr(model, f"{name}_code"), f"{name}_out", name, definition)
    seconds = CLOCK() - start
    return {"seconds": seconds, "checked": _sympybotics_pose_error(source, definition, geometry)}


def _sympybotics_pose_error(source: str, definition, geometry) -> float:
    """Largest difference of SymPyBotics' last-link pose and the numeric DH product of the
    robot's table (``tests/numeric_dh.py``) at three random configurations: the same arm?"""
    import numpy as np
    import sympy

    sys.path.insert(0, str(ROOT / "tests"))
    from numeric_dh import modified_dh, standard_dh

    robot = _load(source)
    values = {s: robot.parameter_values()[s.name] for s in robot.parameter_symbols}
    link = modified_dh if robot.convention == "modified" else standard_dh
    rng, worst = np.random.default_rng(17), 0.0
    for _ in range(3):
        q = rng.uniform(-math.pi, math.pi, robot.dof)
        pose = np.eye(4)
        for joint, angle in zip(robot.joints, q, strict=True):
            d, a, alpha, theta = (float(sympy.sympify(v).subs(values)) for v in
                                  (joint.d, joint.a, joint.alpha, joint.theta))  # fmt: skip
            pose = pose @ link(theta + (-angle if getattr(joint, "flip", False) else angle),
                               d, a, alpha)  # fmt: skip
        theirs = geometry.T[-1].subs(dict(zip(definition.q, q, strict=True)))
        # SymPyBotics makes its own symbols from the names: substitute by name.
        by_name = {s.name: v for s, v in values.items()}
        theirs = theirs.subs({s: by_name[s.name] for s in theirs.free_symbols}).evalf()
        worst = max(worst, float(np.abs(np.array(theirs, dtype=float) - pose).max()))
    return worst


def _generated_inverse_dynamics(out: Path, name: str):
    from codegen_speed import load_module

    return load_module(out / "numpy" / f"{name}_kinematics.py").inverse_dynamics


def _child_pinocchio(source: str, out: str) -> dict:
    import numpy as np

    sys.path.insert(0, str(ROOT / "tests"))
    from test_dynamics_oracles import pinocchio_model

    robot = _load(source)
    if any(j.link is None for j in robot.joints):
        return {"error": "no inertial data"}
    pin, model = pinocchio_model(robot)
    data = model.createData()
    rng = np.random.default_rng(15)
    n = robot.dof
    q, dq, ddq = (rng.uniform(-r, r, (RNEA_STATES, n)) for r in (math.pi, 2.0, 5.0))
    rotor = np.array([float(j.link.motor_inertia or 0) for j in robot.joints])
    worst = None
    if out and (Path(out) / "numpy").is_dir():  # the same arm as symkin's? (before timing)
        ours = _generated_inverse_dynamics(Path(out), robot.name)
        worst = 0.0
        for i in range(10):
            theirs = pin.rnea(model, data, q[i], dq[i], ddq[i]) + rotor * ddq[i]
            mine = np.asarray(ours(q[i], dq[i], ddq[i]), dtype=float).ravel()
            scale = max(1.0, float(np.abs(theirs).max()))
            worst = max(worst, float(np.abs(mine - theirs).max()) / scale)
        if worst > CHECK_TOLERANCE:
            return {"error": f"disagrees with symkin's tau by {worst:.1e} (relative)"}
    rnea, passes = pin.rnea, []
    for _ in range(RNEA_PASSES):
        start = CLOCK()
        for i in range(RNEA_STATES):
            rnea(model, data, q[i], dq[i], ddq[i])
        passes.append((CLOCK() - start) / RNEA_STATES)
    return {"seconds": statistics.median(passes), "checked": worst}


def _child(argv: list[str]) -> None:
    kind, source, extra = argv[0], argv[1], argv[2]
    if kind == "fkj":
        result = _child_fkj(source)
    elif kind in ("tau", "full"):
        result = _child_dynamics(kind, source)
    elif kind in PEER_KINDS:
        result = _child_sympybotics(kind, source, extra)
    elif kind == "pin":
        result = _child_pinocchio(source, extra)
    else:
        raise SystemExit(f"unknown child kind {kind!r}")
    print(json.dumps(result))


# --------------------------------------------------------------------------- processes


@dataclass
class Sample:
    """One process: wall and CPU seconds, peak RSS, the child's JSON, or why it has none."""

    wall: float | None = None
    cpu: float | None = None
    rss_mb: float | None = None
    result: dict = field(default_factory=dict)
    stderr: str = ""
    timeout: float | None = None  # the limit it reached
    error: str | None = None


def _cpu_seconds(pid: int) -> float:
    """CPU seconds of a running process and of the children it has waited for."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except (OSError, IndexError):
        return 0.0
    return sum(int(f) for f in fields[11:15]) / os.sysconf("SC_CLK_TCK")


def _reap(pid: int, limit: float, deadline: float) -> tuple[int, resource.struct_rusage, bool]:
    """Wait for ``pid``; kill its process group past ``limit`` CPU seconds or at ``deadline``.

    The limit is polled from ``/proc`` rather than set with ``RLIMIT_CPU``: on this machine's
    kernel an armed ``RLIMIT_CPU`` makes the child's process CPU clock tick-coarse, which would
    spoil its own timings.  Returns the wait status, the rusage and whether it was killed.
    """
    while True:
        done, status, usage = os.wait4(pid, os.WNOHANG)
        if done:
            return status, usage, False
        if time.perf_counter() > deadline or _cpu_seconds(pid) > limit:
            os.killpg(pid, signal.SIGKILL)
            _, status, usage = os.wait4(pid, 0)
            return status, usage, True
        time.sleep(0.05)


def run_process(command: list[str], limit: float, env: dict[str, str]) -> Sample:
    """Run ``command`` under a CPU limit of ``limit`` s (and a wall backstop) and measure it.

    CPU time and peak RSS are the child's and its waited-for descendants' (``os.wait4``).
    """
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        start = time.perf_counter()
        process = subprocess.Popen(
            command, stdout=out, stderr=err, env=env, cwd=ROOT, start_new_session=True
        )
        status, usage, killed = _reap(process.pid, limit, start + WALL_FACTOR * limit + 60)
        wall = time.perf_counter() - start
        process.returncode = code = os.waitstatus_to_exitcode(status)  # reaped here, not by Popen
        out.seek(0)
        err.seek(0)
        stdout, stderr = out.read().decode(errors="replace"), err.read().decode(errors="replace")
    cpu = usage.ru_utime + usage.ru_stime
    sample = Sample(wall, cpu, usage.ru_maxrss / 1024, stderr=stderr)
    if killed:
        sample.timeout = limit
    elif code != 0:
        tail = (stderr.strip().splitlines() or ["no output"])[-1]
        sample.error = f"exit {code}: {tail[:120]}"
    else:
        lines = stdout.strip().splitlines()
        if lines and lines[-1].startswith("{"):
            sample.result = json.loads(lines[-1])
            sample.error = sample.result.get("error")
    return sample


def symkin_command() -> list[str]:
    """The ``symkin`` console script next to this interpreter (else on PATH)."""
    script = Path(sys.executable).with_name("symkin")
    return [str(script if script.exists() else shutil.which("symkin") or "symkin")]


def cli_options() -> set[str]:
    """Which of the optional flags this build's ``symkin derive`` has (cache, timings)."""
    text = subprocess.run(
        [*symkin_command(), "derive", "--help"], capture_output=True, text=True, check=False
    ).stdout
    text += subprocess.run(
        [*symkin_command(), "--help"], capture_output=True, text=True, check=False
    ).stdout
    return {flag for flag in ("--no-cache", "--verbose", "--time-limit") if flag in text}


# --------------------------------------------------------------------------- one round


@dataclass(frozen=True)
class Arm:
    """A robot to measure: ``group`` is "twists/lengths" for random arms, "named" otherwise."""

    label: str
    group: str
    joints: int
    source: str  # catalogue name or path of a robot file
    seed: int = 0


@dataclass
class Settings:
    timeout: float
    sympybotics: Path | None
    options: set[str]
    workdir: Path
    budget_end: float | None = None


@dataclass
class Results:
    """Samples by (group, joints or label, kind), and which measurements stopped at a size."""

    samples: dict[tuple[str, object, str], list[Sample]] = field(default_factory=dict)
    stopped: dict[tuple[str, str], int] = field(default_factory=dict)  # -> joints that timed out
    not_run: dict[tuple[str, object, str], str] = field(default_factory=dict)

    def add(self, arm: Arm, kind: str, sample: Sample) -> None:
        self.samples.setdefault(_key(arm, kind), []).append(sample)
        if sample.timeout is not None and arm.group != "named":
            previous = self.stopped.get((arm.group, kind), arm.joints)
            self.stopped[(arm.group, kind)] = min(previous, arm.joints)


def _key(arm: Arm, kind: str) -> tuple[str, object, str]:
    return (arm.group, arm.label if arm.group == "named" else arm.joints, kind)


def _env(cache: Path) -> dict[str, str]:
    """The environment of every child: its own cache directory, this script's imports."""
    path = os.pathsep.join(p for p in (os.environ.get("PYTHONPATH"), str(ROOT / "bench")) if p)
    return dict(os.environ, XDG_CACHE_HOME=str(cache), PYTHONPATH=path)


def _derive(arm: Arm, settings: Settings, cache: Path, out: Path, verbose: bool) -> Sample:
    command = symkin_command()
    if "--time-limit" in settings.options:
        command += ["--time-limit", "0"]  # this script's limit governs
    command += ["derive", arm.source, "--out", str(out)]
    if verbose and "--verbose" in settings.options:
        command.append("--verbose")
    return run_process(command, settings.timeout, _env(cache))


def _child_sample(arm: Arm, kind: str, settings: Settings, extra: str) -> Sample:
    cache = Path(tempfile.mkdtemp(dir=settings.workdir, prefix="cache-"))
    command = [sys.executable, str(Path(__file__).resolve()), "--child", kind, arm.source, extra]
    return run_process(command, settings.timeout, _env(cache))


def _why_not(arm: Arm, kind: str, settings: Settings, results: Results) -> str | None:
    if kind in PEER_KINDS and settings.sympybotics is None:
        return "no `--sympybotics DIR` given"
    stopped = results.stopped.get((arm.group, kind))
    if stopped is not None and arm.joints > stopped:
        return f"timed out at {stopped} joints"
    cold = results.samples.get(_key(arm, "cold"), [None])[-1]
    if kind == "warm" and (cold is None or cold.timeout is not None):
        return "the cold run did not finish, so there is no warm cache"
    if settings.budget_end is not None and time.perf_counter() > settings.budget_end:
        return "`--budget` spent"
    return None


def measure_arm(arm: Arm, settings: Settings, results: Results) -> None:
    """One round: every measurement of ``arm``, one process after another."""
    tag = arm.label.replace(" ", "_").replace("#", "s")
    cache = settings.workdir / f"cache-{tag}"
    out = settings.workdir / f"out-{tag}"
    for kind, _ in KINDS:
        reason = _why_not(arm, kind, settings, results)
        if reason is not None:
            results.not_run[_key(arm, kind)] = reason
            continue
        if kind in ("cold", "warm"):
            target = out if kind == "cold" else settings.workdir / f"out-{tag}-warm"
            sample = _derive(arm, settings, cache, target, verbose=kind == "cold")
        elif kind in PEER_KINDS:
            sample = _child_sample(arm, kind, settings, str(settings.sympybotics))
        else:
            sample = _child_sample(arm, kind, settings, str(out))
        results.add(arm, kind, sample)
        _progress(f"{arm.label:34} {kind:8} {_sample_text(kind, sample)}")


def _sample_text(kind: str, sample: Sample) -> str:
    if sample.timeout is not None:
        return f"> {sample.timeout:g} s (timeout)"
    if sample.error is not None:
        return sample.error
    if kind in ("cold", "warm"):
        return f"wall {sample.wall:.2f} s, CPU {sample.cpu:.2f} s, {sample.rss_mb:.0f} MB"
    if kind == "pin":
        return f"{sample.result['seconds'] * 1e6:.2f} us/call"
    return f"{sample.result['seconds']:.3f} s"


# --------------------------------------------------------------------------- table


def _values(samples: list[Sample], what: str) -> list[float]:
    """One number per sample; a timeout counts as infinitely long, an error not at all."""
    values = []
    for s in samples:
        if s.timeout is not None:
            values.append(math.inf)
        elif s.error is None and (what in ("wall", "cpu", "rss_mb") or "seconds" in s.result):
            values.append(getattr(s, what) if what != "seconds" else s.result["seconds"])
    return values


def median_of(samples: list[Sample], what: str) -> float | None:
    values = _values(samples, what)
    return statistics.median(values) if values else None


def _limit(samples: list[Sample]) -> float:
    """The limit the timed-out samples reached."""
    return next(s.timeout for s in samples if s.timeout is not None)


def _number(value: float, what: str) -> str:
    if what == "rnea":
        return f"{value * 1e6:.2f}"
    if what == "rss_mb":
        return f"{value:.0f}"
    return seconds_text(value)


def cell(results: Results, key: tuple, what: str = "seconds") -> str:
    """Median over the seeds, "> T s (timeout)", the error, or why it was not run."""
    samples = results.samples.get(key, [])
    if not samples:
        return "not run" if key in results.not_run else "—"
    value = median_of(samples, "seconds" if what == "rnea" else what)
    timeouts = sum(s.timeout is not None for s in samples)
    if value is None:
        return samples[-1].error or "—"
    if math.isinf(value):
        return "—" if what == "rss_mb" else f"> {_limit(samples):g} s (timeout)"
    text = _number(value, what)
    if timeouts:
        text += f" ({timeouts} of {len(samples)} timed out)"
    return text


def pair_cell(results: Results, key: tuple) -> str:
    """``wall (CPU)`` of a ``symkin derive`` run."""
    wall = cell(results, key, "wall")
    if not results.samples.get(key) or median_of(results.samples[key], "wall") in (None, math.inf):
        return wall
    return f"{wall} ({cell(results, key, 'cpu')})"


def ratio(results: Results, peer: tuple, ours: tuple) -> str:
    """Peer median / symkin median (how many times longer the peer takes)."""
    theirs, mine = (median_of(results.samples.get(k, []), "seconds") for k in (peer, ours))
    if theirs is None or mine is None or mine <= 0 or math.isinf(mine):
        return "—"
    if math.isinf(theirs):
        return f"> {_limit(results.samples[peer]) / mine:.1f}×"
    return f"{theirs / mine:.2f}×" if theirs / mine < 10 else f"{theirs / mine:.0f}×"


COLUMNS = (
    "derive cold, wall (CPU) [s]",
    "derive warm, wall (CPU) [s]",
    "peak RSS cold [MB]",
    "FK + J [s]",
    "tau [s]",
    "full dynamics [s]",
    "SymPyBotics tau [s]",
    "SymPyBotics full set [s]",
    "tau: SymPyBotics / symkin",
    "full: SymPyBotics / symkin",
    "Pinocchio rnea [µs/call]",
)


def row_cells(results: Results, group: str, which: object) -> list[str]:
    def k(kind: str) -> tuple:
        return (group, which, kind)

    return [
        pair_cell(results, k("cold")),
        pair_cell(results, k("warm")),
        cell(results, k("cold"), "rss_mb"),
        cell(results, k("fkj")),
        cell(results, k("tau")),
        cell(results, k("full")),
        cell(results, k("sb-tau")),
        cell(results, k("sb-full")),
        ratio(results, k("sb-tau"), k("tau")),
        ratio(results, k("sb-full"), k("full")),
        cell(results, k("pin"), "rnea"),
    ]


def growth_exponent(points: list[tuple[int, float]]) -> str:
    """Least-squares slope of log(time) over log(joints): time ~ joints^k."""
    points = [(n, t) for n, t in points if t is not None and 0 < t < math.inf]
    if len(points) < 3:
        return "—"
    xs, ys = [math.log(n) for n, _ in points], [math.log(t) for _, t in points]
    mx, my = statistics.fmean(xs), statistics.fmean(ys)
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys, strict=True))
    slope /= sum((x - mx) ** 2 for x in xs)
    return f"n^{slope:.1f}"


def growth_row(results: Results, group: str, sizes: list[int]) -> list[str]:
    def fit(kind: str, what: str = "seconds") -> str:
        medians = [(n, median_of(results.samples.get((group, n, kind), []), what)) for n in sizes]
        return growth_exponent(medians)

    kinds = ("fkj", "tau", "full", "sb-tau", "sb-full")
    return [fit("cold", "cpu"), fit("warm", "cpu"), "", *(fit(kind) for kind in kinds), "", "", ""]


def _table(header: str, rows: list[list[str]]) -> list[str]:
    return [
        f"| {header} | " + " | ".join(COLUMNS) + " |",
        "| --- | " + " | ".join("---:" for _ in COLUMNS) + " |",
        *("| " + " | ".join(row) + " |" for row in rows),
    ]


def targets(results: Results, groups: list[str]) -> list[str]:
    """The issue's targets for ``symkin derive``, judged on median CPU time."""
    lines = []
    for n, limit in ((6, 10.0), (7, 20.0), (12, 120.0)):
        for group in groups:
            samples = results.samples.get((group, n, "cold"), [])
            value = median_of(samples, "cpu")
            if value is None:
                continue
            verdict = "met" if value < limit else "NOT met"
            shown = "timeout" if math.isinf(value) else f"{seconds_text(value)} s CPU"
            lines.append(f"- {n} joints, {group}: cold < {limit:g} s: {shown}, {verdict}")
    warm = [
        (median_of(s, "cpu"), key)
        for key, s in results.samples.items()
        if key[2] == "warm" and median_of(s, "cpu") is not None
    ]
    if warm:
        slowest, key = max(warm, key=lambda item: item[0])
        verdict = "met" if slowest < 1.0 else "NOT met"
        shown = "timeout" if math.isinf(slowest) else f"{seconds_text(slowest)} s CPU"
        lines.append(
            f"- warm command < 1 s: slowest median {shown} ({key[0]}, {key[1]}), {verdict}"
        )
    return lines


GROUP_TITLES = {
    "right/numeric": "Twists from {0, ±90°}, numeric lengths",
    "right/symbolic": "Twists from {0, ±90°}, symbolic lengths",
    "generic/numeric": "Generic twists, numeric lengths",
    "generic/symbolic": "Generic twists, symbolic lengths",
}

# A ``--verbose`` line giving a phase's elapsed time: "<phase> ... 1.23 s" (any punctuation).
PHASE_LINE = re.compile(
    r"^\W*(?P<name>[A-Za-z].*?)[\s:.,(—-]+(?P<seconds>\d+(?:\.\d+)?)\s*s\)?\s*$"
)


def phases_of(stderr: str) -> dict[str, float]:
    """Elapsed seconds by phase from ``symkin derive --verbose`` (summed over repeats)."""
    phases: dict[str, float] = {}
    for line in stderr.splitlines():
        match = PHASE_LINE.match(line.strip())
        if match:
            name = match["name"].strip()
            phases[name] = phases.get(name, 0.0) + float(match["seconds"])
    return phases


def phase_lines(results: Results, keys: list[tuple]) -> list[str]:
    """The slowest phases of the cold runs (first seed), when ``--verbose`` reports them."""
    lines = []
    for key in keys:
        samples = [s for s in results.samples.get(key, []) if s.error is None and not s.timeout]
        phases = phases_of(samples[0].stderr) if samples else {}
        if phases:
            top = sorted(phases.items(), key=lambda item: -item[1])[:4]
            shown = ", ".join(f"{name} {seconds_text(s)} s" for name, s in top)
            lines.append(f"- {key[0]}, {key[1]}: {shown}")
    return lines


# The same-arm checks the children make before (Pinocchio) or after (SymPyBotics) timing.
CHECKS = (
    (
        ("pin",),
        "- Pinocchio's torques matched the inverse dynamics of symkin's generated NumPy module "
        "on 10 random states in each of {count} runs: largest difference {worst:.0e} of the "
        "largest torque.",
    ),
    (
        PEER_KINDS,
        "- SymPyBotics' last-link pose matched the numeric product of the DH table "
        "(`tests/numeric_dh.py`) at 3 random configurations in each of {count} runs: largest "
        "difference {worst:.0e}.",
    ),
)


def notes(results: Results) -> list[str]:
    """Why cells say "not run", and the same-arm checks of the peers."""
    names = dict(KINDS)
    reasons: dict[tuple[str, str], dict[str, list[str]]] = {}
    for (group, which, kind), reason in results.not_run.items():
        reasons.setdefault((kind, reason), {}).setdefault(group, []).append(str(which))
    lines = [
        f"- {names[kind]}: not run ({reason}): "
        + "; ".join(f"{group} {', '.join(which)}" for group, which in groups.items())
        for (kind, reason), groups in reasons.items()
    ]
    for kinds, text in CHECKS:
        checks = [
            s.result["checked"]
            for key, samples in results.samples.items()
            if key[2] in kinds
            for s in samples
            if s.result.get("checked") is not None
        ]
        if checks:
            lines.append(text.format(count=len(checks), worst=max(checks)))
    return lines


def render(results: Results, args: argparse.Namespace, run: dict) -> str:
    today = datetime.datetime.now(datetime.UTC).date().isoformat()
    sb = run["sympybotics"]
    lines = [
        f"Measured on {today}: {cpu_model()}, {os.cpu_count()} cores; Python "
        f"{platform.python_version()}, symkin {version('symkin')}, SymPy {version('sympy')}, "
        f"SymEngine {version('symengine')}, Pinocchio (`pin`) {version('pin')}, SymPyBotics {sb}. "
        f"Load average (1 min) at the start and end: {run['load'][0]:.1f} and "
        f"{run['load'][1]:.1f} (2 cores shared with other work); the run took "
        f"{run['minutes']:.0f} min. Sizes {', '.join(map(str, run['sizes']))} joints, "
        f"{run['seeds']} seed{'s' if run['seeds'] > 1 else ''} per size (medians), CPU limit "
        f"{args.timeout:g} s per process. This build's `symkin derive` "
        + ("has `--no-cache`" if "--no-cache" in run["options"] else "has no disk cache")
        + (" and `--verbose`" if "--verbose" in run["options"] else "")
        + ". Generated by `bench/derivation_scaling.py`.",
    ]
    for group in run["groups"]:
        rows = [[str(n), *row_cells(results, group, n)] for n in run["sizes"]]
        rows.append(["growth", *growth_row(results, group, run["sizes"])])
        lines += ["", f"### {GROUP_TITLES[group]}", "", *_table("joints", rows)]
    if run["named"]:
        rows = [[name, *row_cells(results, "named", name)] for name in run["named"]]
        lines += ["", "### Named arms", "", *_table("robot", rows)]
    goals = targets(results, run["groups"])
    if goals:
        lines += ["", "Targets of issue 15 (median CPU time of the whole command):", "", *goals]
    keys = [(g, 6, "cold") for g in run["groups"]] + [("named", n, "cold") for n in run["named"]]
    phases = phase_lines(results, keys)
    if phases:
        lines += ["", "Slowest phases of the cold run (`--verbose`, wall seconds):", "", *phases]
    remarks = notes(results)
    if remarks:
        lines += ["", "Notes:", "", *remarks]
    return "\n".join(lines)


# --------------------------------------------------------------------------- main


def arms_to_run(args: argparse.Namespace, workdir: Path, seed: int) -> list[Arm]:
    """One round per arm, every size and group for this seed, then the named arms."""
    arms = []
    for n in args.sizes:
        for group in args.groups:
            twists, lengths = group.split("/")
            text = random_arm_toml(n, seed, twists=twists, lengths=lengths, dynamics=True)
            path = workdir / f"random_{n}_{twists}_{lengths}_{seed}.toml"
            path.write_text(text)
            arms.append(Arm(f"{n}R {twists} {lengths} #{seed}", group, n, str(path), seed))
    for name, joints in NAMED:
        if name in args.named:
            source = name
            if name == "jaco_like":
                source = str(workdir / "jaco_like.toml")
                Path(source).write_text(jaco_like_toml())
            arms.append(Arm(name, "named", joints, source))
    return arms


def sympybotics_version(directory: Path | None) -> str:
    if directory is None:
        return "not run (no `--sympybotics DIR`)"
    commit = subprocess.run(
        ["git", "-C", str(directory), "rev-parse", "--short", "HEAD"],
        capture_output=True, text=True, check=False,
    ).stdout.strip()  # fmt: skip
    return f"checkout {commit or directory.name}"


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="sizes 2, 4, 6, one seed, PUMA only")
    parser.add_argument("--max-joints", type=int, default=12)
    parser.add_argument("--sizes", type=int, nargs="+", help="joint counts (default 2..max)")
    parser.add_argument("--seeds", type=int, default=3, help="random arms per size and kind")
    parser.add_argument("--timeout", type=float, default=300, help="CPU seconds per process")
    parser.add_argument("--budget", type=float, help="start nothing new after this many s")
    parser.add_argument("--twists", nargs="+", choices=TWIST_CHOICES, default=TWIST_CHOICES)
    parser.add_argument("--lengths", nargs="+", choices=LENGTH_CHOICES, default=LENGTH_CHOICES)
    parser.add_argument("--named", nargs="*", choices=[n for n, _ in NAMED])
    parser.add_argument("--sympybotics", type=Path, metavar="DIR", help="SymPyBotics checkout")
    parser.add_argument("--out", type=Path, help="write the Markdown here, not into the docs")
    parser.add_argument("--docs", type=Path, default=DOCS)
    parser.add_argument("--no-write", action="store_true", help="only print the section")
    parser.add_argument("--child", nargs=3, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    sizes = args.sizes or (QUICK_SIZES if args.quick else range(2, args.max_joints + 1))
    args.sizes = [n for n in sizes if 1 <= n <= args.max_joints]
    if args.quick:
        args.seeds = 1
    if args.named is None:
        args.named = ["puma560"] if args.quick else [n for n, _ in NAMED]
    args.groups = [f"{t}/{length}" for t in args.twists for length in args.lengths]
    return args


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    if args.child:
        _child(args.child)
        return 0
    if args.sympybotics is not None and not (args.sympybotics / "sympybotics").is_dir():
        raise SystemExit(f"--sympybotics {args.sympybotics}: no sympybotics package there")
    start, load_start = time.perf_counter(), os.getloadavg()[0]
    options = cli_options()
    _progress(f"symkin derive options found: {sorted(options) or 'none'}")
    results = Results()
    with tempfile.TemporaryDirectory(prefix="symkin-scaling-") as work:
        budget_end = start + args.budget if args.budget else None
        settings = Settings(args.timeout, args.sympybotics, options, Path(work), budget_end)
        for seed in range(1, args.seeds + 1):
            for arm in arms_to_run(args, Path(work), seed):
                measure_arm(arm, settings, results)
    run = {
        "sympybotics": sympybotics_version(args.sympybotics),
        "load": (load_start, os.getloadavg()[0]),
        "minutes": (time.perf_counter() - start) / 60,
        "sizes": args.sizes,
        "seeds": args.seeds,
        "options": options,
        "groups": args.groups,
        "named": args.named,
    }
    text = render(results, args, run)
    print(text)
    if args.out is not None:
        args.out.write_text(text + "\n")
    elif not args.no_write:
        write_docs(text, args.docs, (BEGIN, END), HEADING)
    return 0


if __name__ == "__main__":
    sys.exit(main())
