"""The Panda's symbolic manipulability under the default budget (issue 15: it used to run for
more than 25 minutes; the target is an answer or the fallback message within 60 s).

Usage: ``python bench/panda_manipulability.py [--budget S] [--rounds N]``.  Each round runs
``Model(panda, budget=S).manipulability_form()`` in a fresh process (so nothing is cached),
and reports the CPU time of that process and of the budget's forked child (``getrusage``
of self and children), the wall time, the load average and the outcome: the closed form's
operation count, or the one-line warning of the fallback.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time
import warnings

from symkin.derive.budget import DEFAULT_BUDGET_SECONDS


def measure(budget: float) -> dict[str, object]:
    """One measurement in this process (``--child``)."""
    import symkin
    from symkin.derive import Model
    from symkin.kernels import count_operations

    robot = symkin.load_robot("panda")
    start = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        form = Model(robot, budget=budget).manipulability_form()
    wall = time.perf_counter() - start
    cpu = sum(
        usage.ru_utime + usage.ru_stime
        for usage in (
            resource.getrusage(resource.RUSAGE_SELF),
            resource.getrusage(resource.RUSAGE_CHILDREN),
        )
    )
    return {
        "status": form.status,
        "operations": count_operations([form.value])["total"] if form.found else None,
        "messages": [str(w.message) for w in caught],
        "wall": wall,
        "cpu_process": cpu,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--budget", type=float, default=DEFAULT_BUDGET_SECONDS)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(measure(args.budget)))
        return
    for k in range(args.rounds):
        command = [sys.executable, __file__, "--child", "--budget", str(args.budget)]
        output = subprocess.run(command, capture_output=True, text=True, check=True).stdout
        result = json.loads(output)
        load = os.getloadavg()[0]
        print(
            f"round {k + 1}: {result['status']}, wall {result['wall']:.1f} s, CPU (process "
            f"incl. imports and the budget's child) {result['cpu_process']:.1f} s, "
            f"load {load:.1f}; operations {result['operations']}; {result['messages']}",
            flush=True,
        )


if __name__ == "__main__":
    main()
