"""A/B of the whole ``symkin derive`` command between source trees (issue 15 measurements).

Usage: ``python bench/derive_ab.py ROBOT REV [REV ...] [--rounds 3]`` from the repository.
``ROBOT`` is a robot file, a catalogue name or ``random:N:SEED:TWISTS:LENGTHS`` (with
dynamics, :mod:`random_arms`); each ``REV`` is a git revision, exported with ``git archive``
into a temporary directory (``WORKTREE`` for the files as they are now).  Every round runs
``symkin derive ROBOT --out DIR --no-cache --no-build`` once per tree, each a fresh process
on an empty ``XDG_CACHE_HOME``, the trees in turn and in reverse order every other round, so
load from other work falls on all of them.  Reports per run the CPU seconds (user + system,
``os.wait4``), peak RSS and the load average (``os.getloadavg``, 1 min) after it, then the
median CPU per tree and its ratio to the first tree's.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

import random_arms

ROOT = Path(__file__).resolve().parent.parent


def robot_argument(spec: str, folder: Path) -> str:
    """A path or catalogue name for the command line (random arms written to ``folder``)."""
    if not spec.startswith("random:"):
        return spec
    _, n, seed, twists, lengths = spec.split(":")
    path = folder / f"random_{n}_{seed}_{twists}_{lengths}.toml"
    path.write_text(random_arms.random_arm_toml(int(n), int(seed), twists, lengths, True))
    return str(path)


def exported(revision: str, folder: Path) -> Path:
    """The ``src`` directory of ``revision`` (``WORKTREE``: this checkout's own)."""
    if revision == "WORKTREE":
        return ROOT / "src"
    target = folder / revision.replace("/", "_")
    target.mkdir()
    archive = subprocess.run(
        ["git", "-C", str(ROOT), "archive", revision, "src", "templates"],
        check=True,
        capture_output=True,
    ).stdout
    subprocess.run(["tar", "-x", "-C", str(target)], input=archive, check=True)
    templates = target / "src" / "symkin" / "templates"
    if not templates.exists():  # a tree whose templates live beside src
        templates.symlink_to(Path("../../templates"))
    return target / "src"


def run_once(source: Path, robot: str, folder: Path) -> tuple[float, float, int]:
    """CPU seconds, peak RSS (MB) and exit status of one cold ``symkin derive``."""
    out = Path(tempfile.mkdtemp(dir=folder))
    env = dict(os.environ, PYTHONPATH=str(source), XDG_CACHE_HOME=str(out / "cache"))
    command = [sys.executable, "-m", "symkin.cli", "derive", robot, "--out", str(out / "o")]
    process = subprocess.Popen(
        [*command, "--no-cache", "--no-build"],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        cwd=folder,
    )
    _, status, usage = os.wait4(process.pid, 0)
    shutil.rmtree(out)
    return usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024, status


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("robot")
    parser.add_argument("revisions", nargs="+")
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as temporary:
        folder = Path(temporary)
        robot = robot_argument(args.robot, folder)
        trees = {rev: exported(rev, folder) for rev in args.revisions}
        cpu: dict[str, list[float]] = {rev: [] for rev in trees}
        for k in range(args.rounds):
            order = list(trees) if k % 2 == 0 else list(trees)[::-1]
            for rev in order:
                seconds, rss, status = run_once(trees[rev], robot, folder)
                cpu[rev].append(seconds)
                load = os.getloadavg()[0]
                print(
                    f"round {k + 1}  {rev}: {seconds:.2f} s CPU, peak RSS {rss:.0f} MB, "
                    f"exit status {status}, load {load:.2f}",
                    flush=True,
                )
    first = statistics.median(cpu[args.revisions[0]])
    for rev, values in cpu.items():
        median = statistics.median(values)
        print(f"{rev}: median {median:.2f} s CPU ({median / first:.2f}x of the first)")


if __name__ == "__main__":
    main()
