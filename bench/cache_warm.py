"""Cold and warm runs of ``symkin show``, ``derive --out`` and ``latex`` through the derivation
cache, each command a fresh process (as a user runs them).

For each run: wall time of the process, and its CPU time split into importing symkin and
running the command (``main``).  On a shared machine the wall time waits for a core; the CPU
time is what symkin itself costs.  Robots: the catalogue PUMA 560 and Panda, and
bench/random_arms.py's Jaco-like 6R (60-degree wrist twists, wrist offsets).

    python bench/cache_warm.py                      # cold into a fresh cache, then warm
    python bench/cache_warm.py --cache DIR --warm   # only warm runs on a filled cache DIR
    python bench/cache_warm.py --robots puma560 --commands show   # a subset
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from random_arms import jaco_like_toml

# Runs in the child: times the import of symkin and the command separately.
CHILD = """
import json, sys, time
w0, c0 = time.perf_counter(), time.process_time()
from symkin.cli import main
w1, c1 = time.perf_counter(), time.process_time()
status = main(sys.argv[1:])
w2, c2 = time.perf_counter(), time.process_time()
sys.stderr.write("BENCH " + json.dumps({"import_cpu": c1 - c0, "run_cpu": c2 - c1,
                                        "run_wall": w2 - w1, "status": status}) + "\\n")
"""
COMMANDS = {
    "show": lambda robot, out: ["show", robot],
    "derive": lambda robot, out: ["derive", robot, "--out", str(out / "code"), "--no-build"],
    "latex": lambda robot, out: ["latex", robot, "-o", str(out / "tex" / "robot.tex")],
}


def timed_run(argv: list[str], cache: Path, out: Path) -> dict:
    env = os.environ | {"XDG_CACHE_HOME": str(cache)}
    env.pop("SYMKIN_NO_CACHE", None)
    # Python's bytecode cache on, as in a user's install (a warm run would else recompile
    # symkin's sources on every start).
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-c", CHILD, "--time-limit", "0", *argv],
        env=env,
        capture_output=True,
        text=True,
        cwd=out,
        timeout=3600,
    )
    wall = time.perf_counter() - start
    lines = [line for line in done.stderr.splitlines() if line.startswith("BENCH ")]
    if done.returncode != 0 or not lines:
        raise RuntimeError(f"{' '.join(argv)} failed:\n{done.stderr[-2000:]}")
    return json.loads(lines[-1][6:]) | {"wall": wall}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--robots", default="puma560,panda,jaco_like")
    parser.add_argument("--commands", default=",".join(COMMANDS), help="show,derive,latex")
    parser.add_argument("--cache", type=Path, help="cache folder (default: a fresh one)")
    parser.add_argument("--warm", action="store_true", help="only warm runs (a filled --cache)")
    args = parser.parse_args()
    work = Path(tempfile.mkdtemp(prefix="symkin-cache-bench-"))
    cache = args.cache or work / "xdg"
    (work / "jaco_like.toml").write_text(jaco_like_toml())
    passes = ("warm",) if args.warm else ("cold", "warm")
    print(f"load average {os.getloadavg()[0]:.2f} at start, {os.cpu_count()} cores")
    print("| robot | command | pass | wall s | CPU import s | CPU command s |")
    print("|---|---|---|---:|---:|---:|")
    for name in args.robots.split(","):
        robot = str(work / "jaco_like.toml") if name == "jaco_like" else name
        for command in args.commands.split(","):
            for run in passes:
                out = work / f"{name}-{command}-{run}"
                out.mkdir()
                result = timed_run(COMMANDS[command](robot, out), cache, out)
                print(
                    f"| {name} | {command} | {run} | {result['wall']:.2f} | "
                    f"{result['import_cpu']:.2f} | {result['run_cpu']:.2f} |",
                    flush=True,
                )
    print(f"load average {os.getloadavg()[0]:.2f} at end")


if __name__ == "__main__":
    main()
