"""A/B of the whole ``symkin derive`` command, and of its emission, between source trees
(issue 15 measurements).

Usage: ``python bench/derive_ab.py ROBOT TREE [TREE ...] [--rounds 3]`` from the repository.
``ROBOT`` is a robot file, a catalogue name, ``jaco`` or ``random:N:SEED:TWISTS:LENGTHS``
(with dynamics, :mod:`random_arms`).  Each ``TREE`` is a ``src`` directory, ``WORKTREE`` (this
checkout's own) or a git revision, exported with ``git archive`` into a temporary directory.
Every round runs ``symkin derive ROBOT --out DIR --no-cache --no-build`` once per tree, each a
fresh process (``PYTHONPATH`` the tree's ``src``) on an empty ``XDG_CACHE_HOME``, the trees in
turn and in reverse order every other round, so load from other work falls on all of them.
The child (this file with ``child``) wraps the emitters ``symkin.generate`` calls with
``time.process_time``; the kernels are built before an emitter is called, so the wrapped time
is emission alone (printing, layout and templates, and the operation counts the file
preambles ask for).  Reports per run the command's CPU seconds (user + system, ``os.wait4``),
the emission's, peak RSS and the load average (``os.getloadavg``, 1 min) after it, then the
medians per tree and the command's ratio to the first tree's.  No timing is a pass/fail test.
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

sys.path.insert(0, str(Path(__file__).parent))

import random_arms

ROOT = Path(__file__).resolve().parent.parent
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


def robot_argument(spec: str, folder: Path) -> str:
    """A path or catalogue name for the command line (shorthand arms written to ``folder``)."""
    text = random_arms.toml_from_spec(spec)
    if text is None:
        return spec
    path = folder / "robot.toml"
    path.write_text(text)
    return str(path)


def exported(tree: str, folder: Path) -> Path:
    """The ``src`` directory of ``tree``: a directory as it is, ``WORKTREE`` this checkout's,
    else a git revision exported with its templates."""
    if Path(tree).is_dir():
        return Path(tree).resolve()
    if tree == "WORKTREE":
        return ROOT / "src"
    target = folder / tree.replace("/", "_")
    target.mkdir()
    archive = subprocess.run(
        ["git", "-C", str(ROOT), "archive", tree, "src", "templates"],
        check=True,
        capture_output=True,
    ).stdout
    subprocess.run(["tar", "-x", "-C", str(target)], input=archive, check=True)
    templates = target / "src" / "symkin" / "templates"
    if not templates.exists():  # a tree whose templates live beside src
        templates.symlink_to(Path("../../templates"))
    return target / "src"


def run_once(source: Path, robot: str, folder: Path, tag: str) -> dict[str, float]:
    """CPU seconds of the command and of its emission, peak RSS (MB) and the load after it."""
    out, report = folder / f"out-{tag}", folder / f"report-{tag}.json"
    env = dict(os.environ, PYTHONPATH=str(source), XDG_CACHE_HOME=str(folder / f"cache-{tag}"))
    command = [sys.executable, str(Path(__file__).resolve()), "child", robot, str(out), str(report)]
    process = subprocess.Popen(
        command, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, cwd=folder
    )
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
    parser.add_argument("robot")
    parser.add_argument("trees", nargs="+", help="src directories, WORKTREE or git revisions")
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    results: dict[str, list[dict[str, float]]] = {tree: [] for tree in args.trees}
    with tempfile.TemporaryDirectory() as temporary:
        folder = Path(temporary)
        robot = robot_argument(args.robot, folder)
        sources = {tree: exported(tree, folder) for tree in args.trees}
        print(f"robot {args.robot}; load at start {os.getloadavg()[0]:.2f}")
        for k in range(args.rounds):
            order = args.trees if k % 2 == 0 else args.trees[::-1]
            for n, tree in enumerate(order):
                row = run_once(sources[tree], robot, folder, f"{k}-{n}")
                results[tree].append(row)
                print(
                    f"round {k + 1}  {tree}: command {row['cpu']:.2f} s CPU, emission "
                    f"{row['emission']:.2f} s (numpy {row['numpy']:.2f}, c {row['c']:.2f}, "
                    f"casadi {row['casadi']:.2f}), peak RSS {row['rss_mb']:.0f} MB, "
                    f"load {row['load']:.2f}",
                    flush=True,
                )
    first = statistics.median(r["cpu"] for r in results[args.trees[0]])
    for tree, rows in results.items():
        medians = {key: statistics.median(r[key] for r in rows) for key in rows[0]}
        print(
            f"{tree}: median command {medians['cpu']:.2f} s CPU "
            f"({medians['cpu'] / first:.2f}x of the first), emission {medians['emission']:.2f} s, "
            f"peak RSS {medians['rss_mb']:.0f} MB"
        )


if __name__ == "__main__":
    if len(sys.argv) == 5 and sys.argv[1] == "child":
        child(*sys.argv[2:])
    else:
        main()
