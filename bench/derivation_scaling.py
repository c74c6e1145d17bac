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
import json
import math
import os
import resource
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from codegen_speed import write_docs
from random_arms import LENGTH_CHOICES, TWIST_CHOICES, jaco_like_toml, random_arm_toml
from scaling_children import PEER_KINDS, RUSAGE_TAG
from scaling_report import KINDS, Arm, Results, Sample, key_of, render

ROOT = Path(__file__).resolve().parent.parent
CHILDREN = ROOT / "bench" / "scaling_children.py"
DOCS = ROOT / "docs" / "benchmarks.md"
BEGIN = "<!-- derivation-scaling:begin -->"
END = "<!-- derivation-scaling:end -->"
HEADING = "Scaling on generic arms"
QUICK_SIZES = (2, 4, 6)
# Named arms: (catalogue name or "jaco_like", joints).
NAMED = (("puma560", 6), ("panda", 7), ("jaco_like", 6))
WALL_FACTOR = 4  # wall-time backstop = WALL_FACTOR x the CPU limit + 60 s (2 shared cores)


def _progress(text: str) -> None:
    print(text, file=sys.stderr, flush=True)


# --------------------------------------------------------------------------- processes


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


def run_process(
    command: list[str], limit: float, env: dict[str, str], cut_at: float | None = None
) -> Sample:
    """Run ``command`` under a CPU limit of ``limit`` s (and a wall backstop) and measure it.

    CPU time and peak RSS are the child's and its waited-for descendants' (``os.wait4``).
    ``cut_at`` (a ``time.perf_counter()`` value) ends the run earlier, as an error, not a
    timeout: the ``--budget`` of the whole benchmark is spent.
    """
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        start = time.perf_counter()
        process = subprocess.Popen(
            command, stdout=out, stderr=err, env=env, cwd=ROOT, start_new_session=True
        )
        deadline = start + WALL_FACTOR * limit + 60
        try:
            status, usage, killed = _reap(process.pid, limit, min(deadline, cut_at or deadline))
        except BaseException:  # interrupted: leave no child running
            os.killpg(process.pid, signal.SIGKILL)
            raise
        wall = time.perf_counter() - start
        process.returncode = code = os.waitstatus_to_exitcode(status)  # reaped here, not by Popen
        out.seek(0)
        err.seek(0)
        stdout, stderr = out.read().decode(errors="replace"), err.read().decode(errors="replace")
    cpu = usage.ru_utime + usage.ru_stime
    sample = Sample(wall, cpu, usage.ru_maxrss / 1024, stderr=stderr)
    if killed and cut_at is not None and start + wall >= cut_at:
        sample.error = "cut off (`--budget`)"
    elif killed:
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
    """The ``symkin`` command as its console script runs it, through :func:`scaling_children.cli`
    (which also reports symkin's own CPU time apart from the compiler's)."""
    return [sys.executable, str(CHILDREN), "cli"]


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


@dataclass
class Settings:
    timeout: float
    sympybotics: Path | None
    options: set[str]
    workdir: Path
    budget_end: float | None = None  # start no process after this (time.perf_counter())

    @property
    def cut_at(self) -> float | None:
        """When a process still running is stopped: a minute after the budget."""
        return None if self.budget_end is None else self.budget_end + 60


def _env(cache: Path) -> dict[str, str]:
    """The environment of every child: its own, empty cache directory, and Python's bytecode
    cache on, as in a user's install (a warm run would else recompile symkin's sources)."""
    env = dict(os.environ, XDG_CACHE_HOME=str(cache))
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    return env


def _derive(arm: Arm, settings: Settings, cache: Path, out: Path) -> Sample:
    command = symkin_command()
    if "--time-limit" in settings.options:
        command += ["--time-limit", "0"]  # this script's limit governs
    command += ["derive", arm.source, "--out", str(out)]
    if "--verbose" in settings.options:  # phase times, and whether the cache was read
        command.append("--verbose")
    sample = run_process(command, settings.timeout, _env(cache), settings.cut_at)
    for line in reversed(sample.stderr.splitlines()):
        if line.startswith(RUSAGE_TAG):
            sample.result = json.loads(line.removeprefix(RUSAGE_TAG))
            break
    return sample


def _child_sample(arm: Arm, kind: str, settings: Settings, extra: str) -> Sample:
    cache = Path(tempfile.mkdtemp(dir=settings.workdir, prefix="cache-"))
    command = [sys.executable, str(CHILDREN), kind, arm.source, extra]
    return run_process(command, settings.timeout, _env(cache), settings.cut_at)


def _why_not(arm: Arm, kind: str, settings: Settings, results: Results) -> str | None:
    if kind in PEER_KINDS and settings.sympybotics is None:
        return "no `--sympybotics DIR` given"
    stopped = results.stopped.get((arm.group, kind))
    if stopped is not None and arm.joints > stopped:
        return f"timed out at {stopped} joints"
    cold = results.samples.get(key_of(arm, "cold"), [None])[-1]
    if kind == "warm" and (cold is None or cold.timeout is not None):
        return "the cold run did not finish, so there is no warm cache"
    if settings.budget_end is not None and time.perf_counter() > settings.budget_end:
        return "`--budget` spent"
    return None


def measure_arm(arm: Arm, settings: Settings, results: Results) -> None:
    """One round: every measurement of ``arm``, one process after another."""
    folder = Path(tempfile.mkdtemp(dir=settings.workdir, prefix="round-"))
    cache, out = folder / "cache", folder / "cold"  # a fresh, empty cache every round
    for kind, _ in KINDS:
        reason = _why_not(arm, kind, settings, results)
        if reason is not None:
            results.not_run[key_of(arm, kind)] = reason
            continue
        if kind in ("cold", "warm"):
            target = out if kind == "cold" else folder / "warm"
            sample = _derive(arm, settings, cache, target)
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
        own = sample.result.get("own_cpu", math.nan)
        return f"wall {sample.wall:.2f} s, CPU {sample.cpu:.2f} s (symkin {own:.2f} s), " + (
            f"{sample.rss_mb:.0f} MB"
        )
    if kind == "pin":
        return f"{sample.result['seconds'] * 1e6:.2f} us/call"
    return f"{sample.result['seconds']:.3f} s"


# --------------------------------------------------------------------------- main


def arms_to_run(args: argparse.Namespace, workdir: Path, seed: int) -> list[Arm]:
    """One round per arm: the named arms, then every size and group for this seed (so that a
    ``--budget`` cuts the largest random arms, not the named ones)."""
    arms = []
    for name, joints in NAMED:
        if name in args.named:
            source = name
            if name == "jaco_like":
                source = str(workdir / "jaco_like.toml")
                Path(source).write_text(jaco_like_toml())
            arms.append(Arm(name, "named", joints, source))
    for n in args.sizes:
        for group in args.groups:
            twists, lengths = group.split("/")
            text = random_arm_toml(n, seed, twists=twists, lengths=lengths, dynamics=True)
            path = workdir / f"random_{n}_{twists}_{lengths}_{seed}.toml"
            path.write_text(text)
            arms.append(Arm(f"{n}R {twists} {lengths} #{seed}", group, n, str(path)))
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
    if args.sympybotics is not None and not (args.sympybotics / "sympybotics").is_dir():
        raise SystemExit(f"--sympybotics {args.sympybotics}: no sympybotics package there")
    # A terminated run raises SystemExit, so run_process kills the child it is waiting for.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(128 + signal.SIGTERM))
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
