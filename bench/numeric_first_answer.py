"""Time to the first numeric answer (issue 15): ``symkin eval``, ``ik`` and ``trajopt`` from a
cold process, the per-call cost of ``kinematic_state`` and the first ``solve_ik`` call.

Each command runs in a fresh interpreter (no derivation cache of any kind carried over) with
``--no-cache`` when the CLI has it, so the figure is what a new user waits for.  Run from the
repository root::

    python bench/numeric_first_answer.py [--src DIR] [--timeout S] [--calls N] [--skip-cli]
        [--skip-api] [ROBOT ...]

``--src`` points at another checkout's ``src`` to measure it (a before/after comparison);
robots are catalogue names or the benchmark arms ``jaco_like``, ``random6`` (seeded right-angle
6R with inertial data) and ``random5``.  Prints one line per measurement: CPU time (user +
system), which hardly depends on the load of a shared machine, and for commands the wall time
too, which does (the load average is printed with it).  Results: docs/benchmarks.md, "Numeric
commands: time to the first answer".
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from random_arms import jaco_like_toml, random_arm_toml

BENCH_ARMS = {
    "jaco_like": jaco_like_toml,
    "random6": lambda: random_arm_toml(6, 1, dynamics=True),
    "random5": lambda: random_arm_toml(5, 1, dynamics=True),
}
# A configuration away from singularities, within the PUMA's and the Panda's joint limits, as
# is Q + 0.2 (the IK target and the trajectory's goal); the first n values.
Q = (0.3, -0.5, 0.5, -1.2, -0.6, 0.8, 0.2)

# Two fresh processes per robot: the first solve_ik (nothing built before it; the target is the
# independent numeric DH product of tests/numeric_dh.py), then kinematic_state's first call and
# its mean per-call CPU time over repeated calls.  Each prints CPU seconds.
IK_PROBE = """
import sys, time
sys.path.insert(0, {tests!r})
import numpy as np
import symkin
from numeric_dh import NumericRobot
robot = symkin.load_robot(sys.argv[1])
model = symkin.derive(robot)
q = np.array({q}[: robot.dof])
target = NumericRobot.from_robot(robot).fk(q + 0.2)
start = time.process_time()
result = symkin.solve_ik(model, target, q0=q)
print(time.process_time() - start, result.success)
"""
STATE_PROBE = """
import sys, time
import symkin
from symkin.solve.evaluate import kinematic_state
model = symkin.derive(symkin.load_robot(sys.argv[1]))
q = {q}[: model.robot.dof]
start = time.process_time()
kinematic_state(model, q)
first = time.process_time() - start
start = time.process_time()
for _ in range({calls}):
    kinematic_state(model, q)
print(first, (time.process_time() - start) / {calls})
"""
TESTS = str(Path(__file__).resolve().parents[1] / "tests")


def api_probes(python: str, environment: dict[str, str], robot: str, calls: int, timeout: float):
    """``(first solve_ik, first kinematic_state, kinematic_state per call)`` CPU seconds as
    text, each "> T s wall (stopped)" when its process ran out of time."""

    def probe(script: str) -> list[str] | None:
        try:
            done = subprocess.run(
                [python, "-c", script, robot],
                env=environment,
                capture_output=True,
                text=True,
                timeout=timeout,
            )
        except subprocess.TimeoutExpired:
            return None
        return done.stdout.split() or [f"failed: {done.stderr[-200:]!r}"] * 2

    stopped = f"> {timeout:.0f} s wall (stopped)"
    ik = probe(IK_PROBE.format(tests=TESTS, q=Q))
    state = probe(STATE_PROBE.format(q=Q, calls=calls))
    first_ik = stopped if ik is None else f"{float(ik[0]):.2f} s CPU (success {ik[1]})"
    if state is None:
        return first_ik, stopped, stopped
    return first_ik, f"{float(state[0]):.3f} s CPU", f"{float(state[1]) * 1e6:.0f} us CPU"


def robot_path(name: str, folder: Path) -> str:
    """A catalogue name as it is, a benchmark arm written to a file in ``folder``."""
    if name not in BENCH_ARMS:
        return name
    path = folder / f"{name}.toml"
    path.write_text(BENCH_ARMS[name]())
    return str(path)


def run(command: list[str], environment: dict[str, str], timeout: float) -> str:
    """Wall and CPU time (user + system) of one command, as text; CPU time is the fairer
    figure on a shared machine (it hardly depends on the load)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    try:
        done = subprocess.run(command, env=environment, capture_output=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        # subprocess.run kills and reaps the child, so its CPU time is counted all the same.
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
        return f"> {timeout:.0f} s wall, > {cpu:.1f} s CPU (stopped)"
    elapsed = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    status = "" if done.returncode == 0 else f" (exit {done.returncode}: {done.stderr[-200:]!r})"
    return f"{elapsed:.2f} s wall, {cpu:.2f} s CPU{status}"


def cli_commands(robot: str, dof: int, target: str) -> dict[str, list[str]]:
    q = ",".join(str(v) for v in Q[:dof])
    goal = ",".join(f"{v + 0.2:.3g}" for v in Q[:dof])
    return {
        "eval": ["eval", robot, "--q", q],
        "ik": ["ik", robot, "--target", target, "--q0", q],
        "trajopt": [
            "trajopt",
            robot,
            "--from",
            q,
            "--to",
            goal,
            "--intervals",
            "10",
            "--time",
            "1",
        ],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("robots", nargs="*", default=["puma560", "panda", "jaco_like", "random6"])
    parser.add_argument("--src", default=str(Path(__file__).resolve().parents[1] / "src"))
    parser.add_argument("--timeout", type=float, default=600.0)
    parser.add_argument("--calls", type=int, default=1000)
    parser.add_argument("--skip-cli", action="store_true")
    parser.add_argument("--skip-api", action="store_true")
    args = parser.parse_args()
    environment = os.environ | {"PYTHONPATH": args.src}
    python = sys.executable
    print(f"src {args.src}; load average {os.getloadavg()[0]:.2f} (2 cores, shared)")
    with tempfile.TemporaryDirectory() as folder:
        for name in args.robots:
            robot = robot_path(name, Path(folder))
            dof = int(
                subprocess.run(
                    [python, "-c", f"import symkin; print(symkin.load_robot({robot!r}).dof)"],
                    env=environment,
                    capture_output=True,
                    text=True,
                    check=True,
                ).stdout
            )
            if not args.skip_api:
                first_ik, first, per_call = api_probes(
                    python, environment, robot, args.calls, args.timeout
                )
                print(
                    f"{name}: first solve_ik {first_ik}; kinematic_state first call {first}, "
                    f"then {per_call} per call (mean of {args.calls})",
                    flush=True,
                )
            if args.skip_cli:
                continue
            target = target_text(python, environment, robot, dof)
            for command, words in cli_commands(robot, dof, target).items():
                if command == "trajopt" and name == "jaco_like":
                    continue  # no inertial data in the file: trajopt has no dynamics to run on
                words += no_cache_flag(python, environment, command)
                elapsed = run([python, "-m", "symkin.cli", *words], environment, args.timeout)
                load = os.getloadavg()[0]
                print(f"{name}: symkin {command}: {elapsed} (load {load:.2f})", flush=True)


def no_cache_flag(python: str, environment: dict[str, str], command: str) -> list[str]:
    """``["--no-cache"]`` when this checkout's ``command`` has the option, else nothing."""
    done = subprocess.run(
        [python, "-m", "symkin.cli", command, "--help"],
        env=environment,
        capture_output=True,
        text=True,
    )
    return ["--no-cache"] if "--no-cache" in done.stdout else []


def target_text(python: str, environment: dict[str, str], robot: str, dof: int) -> str:
    """``x,y,z,rx,ry,rz`` of the tool at ``Q + 0.2`` by a numeric DH product (not timed)."""
    script = (
        "import sys, numpy as np, symkin\n"
        "from symkin.derive.numeric import numeric_function\n"
        "from symkin.spatial import euler_zyx_from_rotation\n"
        "m = symkin.derive(symkin.load_robot(sys.argv[1])).product_form\n"
        f"T = numeric_function(m, m.forward_kinematics)([v + 0.2 for v in {Q}][:{dof}])\n"
        "e = euler_zyx_from_rotation(T[:3, :3])\n"
        "print(','.join(f'{v:.12g}' for v in (*T[:3, 3], e.phi, e.theta, e.psi)))\n"
    )
    done = subprocess.run(
        [python, "-c", script, robot], env=environment, capture_output=True, text=True, check=True
    )
    return done.stdout.strip()


if __name__ == "__main__":
    main()
