"""Trajectory optimisation around obstacles: IPOPT started from the first guess detoured around
the obstacles (``symkin.solve.trajopt.detour``) against the straight joint-space line.

In one run, on the same machine, each case is solved ``--repeat`` times from each guess
(``TrajectoryProblem.clear_guess`` True and False), the two alternated round by round, a fresh
``casadi.Opti`` each time; the robot's generated functions are built once per robot first.
Cases: the 2R swing of docs/trajopt.md past a ball of 0.15 m at (0.55, 0.55, 0) with the three
transcriptions; the same swing past a ball of 0.2 m at (0.7, 0.7, 0) that only the tool end of
the straight swing touches; the PUMA 560 transfer of the worked example past a ball of 0.1 m on
its forearm half-way.  Reported per case and guess: whether the guess was clear, its vias, the
CPU time of the detour search alone (``clear_knots``, median), IPOPT's iterations in the first
round and over all refinement rounds, the median CPU time of ``Opti.solve`` summed over the
rounds (``SolverStats.cpu_times``), the cost, whether the result is consistent to the
tolerance, and the smallest clearance along the re-simulated path.  Iteration counts do not
depend on the load; the CPU times do, a little.  The table goes into ``docs/benchmarks.md``
between ``<!-- trajopt-guess:begin -->`` and ``<!-- trajopt-guess:end -->``.  No test passes
or fails on it.

Usage::

    .venv/bin/python bench/trajopt_guess.py               # 3 rounds, about 5 minutes
    .venv/bin/python bench/trajopt_guess.py --quick --no-write     # 1 round, print only
"""

from __future__ import annotations

import argparse
import math
import os
import resource
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from codegen_speed import write_docs
from derivation_time import measured_line, version

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs" / "benchmarks.md"
MARKERS = ("<!-- trajopt-guess:begin -->", "<!-- trajopt-guess:end -->")
DEG = math.pi / 180


def cases(symkin, trajopt) -> list[tuple[str, object, object]]:
    """(label, model, problem with the detour on) for every case."""
    arm = symkin.derive(symkin.load_robot(ROOT / "examples" / "arm_2r.toml"))
    swing = {"start": (0.0, 0.0), "goal": (90 * DEG, 0.0), "final_time": 2.0}
    swing |= {"torque_limits": (30.0, 30.0), "max_refinements": 2}
    ball = trajopt.Obstacle((0.55, 0.55, 0.0), 0.15)
    found = [
        (f"2R, ball 0.15 m, {method}", arm, trajopt.TrajectoryProblem(
            **swing, obstacles=(ball,), method=method))
        for method in ("multiple-shooting", "collocation", "inverse-dynamics")
    ]  # fmt: skip
    tip = trajopt.Obstacle((0.7, 0.7, 0.0), 0.2)
    found.append(
        ("2R, ball 0.2 m at the tool, multiple-shooting", arm,
         trajopt.TrajectoryProblem(**swing, obstacles=(tip,)))
    )  # fmt: skip
    puma = symkin.derive(symkin.load_robot("puma560"))
    start = np.array([0, 90, -90, 0, 0, 0]) * DEG
    goal = np.array([90, 45, -135, 45, 45, 90]) * DEG
    functions = trajopt.robot_functions(puma)
    from symkin.solve.trajopt.accuracy import origins_function

    middle = origins_function(functions)(((start + goal) / 2)[:, None])[0]
    forearm = trajopt.Obstacle(tuple((middle[3] + middle[4]) / 2), 0.1)
    problem = trajopt.TrajectoryProblem(
        start=tuple(start), goal=tuple(goal), final_time=2.0, obstacles=(forearm,),
        torque_limits=(100, 180, 90, 25, 20, 20), velocity_limits=(3.0,) * 6,
        max_refinements=2,
    )  # fmt: skip
    found.append(("PUMA 560, ball 0.1 m on the forearm, multiple-shooting", puma, problem))
    return found


def search_time(trajopt, model, problem, functions) -> float:
    """CPU seconds of the detour search alone."""
    from symkin.solve.trajopt.detour import clear_knots
    from symkin.solve.trajopt.initial_guess import polyline_knots

    knots = polyline_knots(model, problem, [])
    began = time.process_time()
    clear_knots(functions, problem, knots)
    return time.process_time() - began


def measure(repeat: int) -> tuple[list[dict], tuple[float, float], int]:
    import dataclasses

    import symkin
    import symkin.solve.trajopt as trajopt

    load = os.getloadavg()[0]
    found = cases(symkin, trajopt)
    functions = {id(m): trajopt.robot_functions(m) for _, m, _ in found}
    rows = {(label, clear): [] for label, _, _ in found for clear in (True, False)}
    for _ in range(repeat):
        for label, model, problem in found:
            for clear in (True, False):  # alternated within the round
                p = dataclasses.replace(problem, clear_guess=clear)
                search = search_time(trajopt, model, p, functions[id(model)]) if clear else 0.0
                try:
                    result = trajopt.optimal_trajectory(model, p, functions=functions[id(model)])
                except trajopt.InfeasibleTrajectoryError as error:
                    rows[label, clear].append({"failed": str(error)[:60]})
                    continue
                rows[label, clear].append({"result": result, "search": search})
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss // 1024
    summary = [summarise(label, clear, runs) for (label, clear), runs in rows.items()]
    return summary, (load, os.getloadavg()[0]), peak


def summarise(label: str, clear: bool, runs: list[dict]) -> dict:
    done = [run for run in runs if "result" in run]
    if not done:
        return {"case": label, "guess": "detour" if clear else "line", "failed": runs[0]}
    result = done[0]["result"]
    cpu = [run["result"].stats.cpu_times[1] for run in done]
    return {
        "case": label,
        "guess": "detour" if clear else "line",
        "clear": result.guess.clear,
        "vias": result.guess.vias,
        "search": statistics.median(run["search"] for run in done),
        "first": result.rounds[0].iterations,
        "total": sum(r.iterations for r in result.rounds),
        "cpu": statistics.median(cpu),
        "cpu_range": (min(cpu), max(cpu)),
        "cost": result.cost,
        "consistent": result.consistent,
        "clearance": result.accuracy.min_clearance,
    }


def table(summary: list[dict], load: tuple[float, float], peak: int, repeat: int) -> str:
    import casadi

    what = (
        f"Python {sys.version.split()[0]}, CasADi {casadi.__version__}, NumPy "
        f"{np.__version__}, symkin {version('symkin')}. Median (min–max) of {repeat} rounds, "
        f"the two guesses alternated within each round; peak RSS of the process {peak} MB."
    )
    lines = [
        measured_line(what, load, "trajopt_guess.py"),
        "",
        "| case | first guess | clear | vias | search CPU [s] | iterations (first round) "
        "| iterations (all rounds) | solve CPU [s] | cost | consistent | clearance [m] |",
        "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | --- | ---: |",
    ]
    lines += [row_text(row) for row in summary]
    return "\n".join(lines)


def row_text(row: dict) -> str:
    """One table row: a case solved from one guess (or why it failed)."""
    if "failed" in row:
        return f"| {row['case']} | {row['guess']} | failed: {row['failed']} |"
    yes = {True: "yes", False: "no"}
    low, high = row["cpu_range"]
    cells = [
        row["case"],
        row["guess"],
        yes[bool(row["clear"])],
        str(row["vias"]),
        f"{row['search']:.3f}" if row["guess"] == "detour" else "—",
        str(row["first"]),
        str(row["total"]),
        f"{row['cpu']:.2f} ({low:.2f}–{high:.2f})",
        f"{row['cost']:.4g}",
        yes[row["consistent"]],
        f"{row['clearance']:.3g}",
    ]
    return "| " + " | ".join(cells) + " |"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="one round")
    parser.add_argument("--repeat", type=int, default=3, help="rounds (3)")
    parser.add_argument("--no-write", action="store_true", help="print only")
    args = parser.parse_args(argv)
    repeat = 1 if args.quick else max(args.repeat, 1)
    text = table(*measure(repeat), repeat)
    print(text)
    if not args.no_write:
        write_docs(text, DOCS, MARKERS, "Trajectory optimisation: the first guess around obstacles")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
