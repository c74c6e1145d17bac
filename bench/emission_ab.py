"""A/B of two symkin source trees on one robot: whole ``symkin derive`` and its emission.

Usage::

    python bench/emission_ab.py --tree before=/path/to/old/src --tree after=src \\
        [--robot random:6:1:generic:numeric | FILE] [--rounds 3]

Each round runs ``symkin derive ROBOT --out DIR --no-cache --no-build`` once per tree, each a
fresh process (``PYTHONPATH`` set to the tree's ``src``), the order of the trees alternating
from round to round (A B, B A, ...).  The child (this file with ``child``) wraps the emitters
``symkin.generate`` calls (NumPy, C, IK C, Python extension, CasADi) with
``time.process_time``; the kernels are built before an emitter is called, so the wrapped time
is emission alone (printing, layout and templates, plus the kernels' operation counts the file
preambles ask for).  The parent reads the child's CPU time (user + system) and peak RSS from
``os.wait4`` and the 1-minute load average after each run.  Prints one line per run and the
medians per tree; no timing is ever a pass/fail test.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
EMITTERS = (
    "emit_numpy",
    "emit_c",
    "emit_ik_c",
    "emit_ik_closed_c",
    "emit_python_extension",
    "emit_casadi",
)


def child(robot: str, out: str, report: str) -> None:
    """Run the command in this process with timed emitters; write the times to ``report``."""
    import symkin.generate as generate
    from symkin.cli import main

    spent: dict[str, float] = {}

    def timed(name: str, emit: object) -> object:
        def run(*args: object, **kwargs: object) -> object:
            start = time.process_time()
            try:
                return emit(*args, **kwargs)
            finally:
                spent[name] = spent.get(name, 0.0) + time.process_time() - start

        return run

    for name in EMITTERS:
        setattr(generate, name, timed(name, getattr(generate, name)))
    code = main(["derive", robot, "--out", out, "--no-cache", "--no-build"])
    Path(report).write_text(json.dumps({"code": code, "emission": spent}))


def robot_file(spec: str, folder: Path) -> str:
    """A file path as it is; ``random:N:SEED:TWISTS:LENGTHS`` written from bench/random_arms."""
    if not spec.startswith("random:"):
        return spec
    sys.path.insert(0, str(HERE))
    import random_arms

    _, n, seed, twists, lengths = spec.split(":")
    path = folder / "robot.toml"
    path.write_text(random_arms.random_arm_toml(int(n), int(seed), twists, lengths, dynamics=True))
    return str(path)


def run_once(src: str, robot: str, folder: Path, tag: str) -> dict[str, float]:
    out, report = folder / f"out-{tag}", folder / f"report-{tag}.json"
    env = {**os.environ, "PYTHONPATH": str(Path(src).resolve())}
    command = [sys.executable, str(Path(__file__).resolve()), "child", robot, str(out), str(report)]
    process = subprocess.Popen(command, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(process.pid, 0)
    stderr = process.stderr.read().decode() if process.stderr else ""
    if status != 0 or not report.exists():
        raise SystemExit(f"{tag}: the command failed (status {status}):\n{stderr[-2000:]}")
    emission = json.loads(report.read_text())["emission"]
    return {
        "cpu": usage.ru_utime + usage.ru_stime,
        "emission": sum(emission.values()),
        "numpy": emission.get("emit_numpy", 0.0),
        "c": emission.get("emit_c", 0.0),
        "casadi": emission.get("emit_casadi", 0.0),
        "rss_mb": usage.ru_maxrss / 1024,
        "load": os.getloadavg()[0],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tree", action="append", required=True, help="NAME=SRC_DIR (twice)")
    parser.add_argument("--robot", default="random:6:1:generic:numeric")
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    trees = [tuple(t.split("=", 1)) for t in args.tree]
    results: dict[str, list[dict[str, float]]] = {name: [] for name, _ in trees}
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        robot = robot_file(args.robot, folder)
        print(f"robot {args.robot}; load at start {os.getloadavg()[0]:.2f}")
        for round_ in range(args.rounds):
            order = trees if round_ % 2 == 0 else trees[::-1]
            for name, src in order:
                row = run_once(src, robot, folder, f"{name}-{round_}")
                results[name].append(row)
                print(
                    f"round {round_ + 1} {name:>8}: command {row['cpu']:.2f} s CPU, emission "
                    f"{row['emission']:.2f} s (numpy {row['numpy']:.2f}, c {row['c']:.2f}, "
                    f"casadi {row['casadi']:.2f}), peak RSS {row['rss_mb']:.0f} MB, "
                    f"load {row['load']:.2f}",
                    flush=True,
                )
    for name, rows in results.items():
        medians = {k: statistics.median(r[k] for r in rows) for k in rows[0]}
        print(
            f"median {name:>8}: command {medians['cpu']:.2f} s CPU, emission "
            f"{medians['emission']:.2f} s, peak RSS {medians['rss_mb']:.0f} MB"
        )


if __name__ == "__main__":
    if len(sys.argv) == 5 and sys.argv[1] == "child":
        child(*sys.argv[2:])
    else:
        main()
