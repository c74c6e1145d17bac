"""Time each phase of ``symkin derive`` on one robot (issue 15 profiling).

Usage: ``python bench/profile_phases.py ROBOT|random:N:SEED:TWISTS:LENGTHS|jaco [--budget S]``.
Each phase runs once, in order, in this process (later phases reuse the cached results of
earlier ones, as ``symkin derive`` does); a phase past ``--budget`` seconds of CPU time is cut
off by SIGVTALRM and reported as ``CUT OFF``.  Prints one line per phase: name, wall and
CPU seconds (CPU is the figure to trust on a shared machine), and the operation count of the
kernels a phase builds.
"""

from __future__ import annotations

import argparse
import signal
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).parent))

import random_arms
import symkin
from symkin.derive import Model
from symkin.derive.base_parameters import base_parameters
from symkin.emit.c import emit_c
from symkin.emit.casadi import emit_casadi
from symkin.emit.numpy import emit_numpy
from symkin.kernels import dynamics_kernels, kinematics_kernels, point_kernels
from symkin.kernels.statics import statics_kernels


class _OverrunError(Exception):
    pass


def _alarm(signum: int, frame: Any) -> None:
    raise _OverrunError


def robot_from_spec(spec: str) -> symkin.Robot:
    """A catalogue name, ``jaco``, or ``random:N:SEED:TWISTS:LENGTHS`` (with dynamics)."""
    text = random_arms.toml_from_spec(spec)
    if text is None:
        return symkin.load_robot(spec)
    path = Path("/tmp") / f"profile_{abs(hash(spec))}.toml"
    path.write_text(text)
    return symkin.load_robot(str(path))


def phases(model: Model, n: int) -> list[tuple[str, Callable[[], Any]]]:
    point = [(n, (0.1, -0.05, 0.2))]
    box: dict[str, Any] = {}

    def kernels(key: str, make: Callable[[], Any]) -> Callable[[], Any]:
        def run() -> Any:
            box[key] = make()
            return sum(k.operation_counts["total"] for k in box[key])

        return run

    def all_kernels() -> tuple:
        return tuple(k for key in ("kin", "dyn", "sta", "pts") for k in box.get(key, ()))

    return [
        ("fk (readable)", lambda: model.forward_kinematics),
        ("fk (product)", lambda: model.product_form.forward_kinematics),
        ("jacobian (readable)", lambda: model.geometric_jacobian),
        ("jacobian (product)", lambda: model.product_form.geometric_jacobian),
        ("determinant", lambda: model.determinant()),
        ("kinematics kernels (CSE)", kernels("kin", lambda: kinematics_kernels(model))),
        # The recursion the CLI's point kernel uses (PointMotion.assignments), not the
        # expanded closed form ``.acceleration``, which ran for minutes on a generic arm.
        ("point recursion", lambda: len(model.point_motion(*point[0]).assignments)),
        ("point kernel (CSE)", kernels("pts", lambda: point_kernels(model, point))),
        ("base parameters", lambda: base_parameters(model.robot, model.kinematics)),
        ("newton-euler M,c,G,C", lambda: model.newton_euler),
        ("tau recursion", lambda: model.inverse_dynamics_recursion),
        ("dynamics kernels (passes)", kernels("dyn", lambda: dynamics_kernels(model))),
        ("statics kernels (passes)", kernels("sta", lambda: statics_kernels(model))),
        ("emit c", lambda: emit_c(model.robot, all_kernels(), "double", ())),
        ("emit numpy", lambda: emit_numpy(model.robot, all_kernels(), ())),
        ("emit casadi", lambda: emit_casadi(model.robot, all_kernels(), ())),
        ("lagrange", lambda: model.lagrange),
    ]


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("robot")
    parser.add_argument("--budget", type=float, default=120.0)
    parser.add_argument("--skip", default="", help="comma-separated phase-name prefixes")
    args = parser.parse_args()
    robot = robot_from_spec(args.robot)
    model = Model(robot)
    skip = [s for s in args.skip.split(",") if s]
    if "determinant" in skip:
        # The kinematics kernels ask for det too: without it they measure the rest alone.
        Model.determinant = lambda self, rows=None: None  # type: ignore[method-assign]
    signal.signal(signal.SIGVTALRM, _alarm)
    total = total_cpu = 0.0
    for name, run in phases(model, robot.dof):
        if any(name.startswith(s) for s in skip):
            print(f"{name:28s}  skipped", flush=True)
            continue
        start, cpu = time.perf_counter(), time.process_time()
        signal.setitimer(signal.ITIMER_VIRTUAL, args.budget)
        try:
            result = run()
            shown = result if isinstance(result, int) else ""
        except _OverrunError:
            shown = "CUT OFF"
        finally:
            signal.setitimer(signal.ITIMER_VIRTUAL, 0)
        elapsed, cpu = time.perf_counter() - start, time.process_time() - cpu
        total += elapsed
        total_cpu += cpu
        print(f"{name:28s} {elapsed:8.2f} s  cpu {cpu:8.2f} s  {shown}", flush=True)
    print(f"{'total':28s} {total:8.2f} s  cpu {total_cpu:8.2f} s", flush=True)


if __name__ == "__main__":
    main()
