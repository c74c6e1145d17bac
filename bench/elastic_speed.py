"""Elastic-joint inverse dynamics against the rigid inverse dynamics of the same robot: the
generated kernels' operation counts (the figures in the generated files' headers) and CPU
nanoseconds per call in a C loop (``bench/elastic_speed_loop.c``, ``gcc -O2``), for the
worked example ``examples/elastic_2r.toml`` and ``tests/data/puma560_elastic.toml`` (the
catalogue PUMA 560 with every joint elastic).  Also the CPU seconds of building the dynamics
kernels with and without the elastic ones.

Prints a Markdown table with the machine and the load average and writes it into
``docs/benchmarks.md`` between ``<!-- elastic:begin -->`` and ``<!-- elastic:end -->``; no
test passes or fails on it.  Usage::

    .venv/bin/python bench/elastic_speed.py
    .venv/bin/python bench/elastic_speed.py --quick --no-write   # 2 repeats, print only
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from codegen_speed import write_docs
from derivation_time import measured_line, version

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs" / "benchmarks.md"
MARKERS = ("<!-- elastic:begin -->", "<!-- elastic:end -->")
ROBOTS = (ROOT / "examples" / "elastic_2r.toml", ROOT / "tests" / "data" / "puma560_elastic.toml")
HARNESS = Path(__file__).resolve().parent / "elastic_speed_loop.c"


def measure(path: Path, calls: int = 200_000, repeats: int = 5) -> dict[str, float]:
    from symkin import load_robot
    from symkin.derive import derive
    from symkin.generate import files_for_robot
    from symkin.kernels import dynamics_kernels
    from symkin.output_folder import write_folder

    robot = load_robot(path)
    start = time.process_time()
    kernels = {k.name: k for k in dynamics_kernels(derive(robot))}
    seconds = time.process_time() - start
    with tempfile.TemporaryDirectory() as folder:
        directory = Path(folder)
        write_folder(directory, files_for_robot(robot, ("c",)))
        c = directory / "c"
        executable = c / "loop"
        values = list(robot.parameter_values().values())
        defines = [f"-DROBOT={robot.name}", f'-DHEADER="{robot.name}.h"', f"-DDOF={robot.dof}"]
        defines.append(f"-DN_P={len(values)}")
        subprocess.run(
            ["gcc", "-O2", "-std=c99", *defines, "-I", str(c), str(HARNESS),
             str(c / f"{robot.name}.c"), "-lm", "-o", str(executable)],
            check=True,
        )  # fmt: skip
        run = [str(executable), str(calls), str(repeats), *map(repr, values)]
        out = subprocess.run(run, capture_output=True, text=True, check=True).stdout
    times: dict[str, list[float]] = {"rigid_ns": [], "elastic_ns": []}
    for line in out.splitlines():
        key, value = line.split()
        if key in times:
            times[key].append(float(value))
    return {
        "rigid_ops": kernels["inverse_dynamics"].operation_counts["total"],
        "elastic_ops": kernels["elastic_inverse_dynamics"].operation_counts["total"],
        "rigid_ns": statistics.median(times["rigid_ns"]),
        "elastic_ns": statistics.median(times["elastic_ns"]),
        "kernel_seconds": seconds,
    }


def compiler() -> str:
    done = subprocess.run(["gcc", "--version"], capture_output=True, text=True, check=False)
    return (done.stdout.splitlines() or ["gcc"])[0]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="2 repeats instead of 5")
    parser.add_argument("--docs", type=Path, default=DOCS)
    parser.add_argument("--no-write", action="store_true", help="print only")
    args = parser.parse_args(argv)
    repeats = 2 if args.quick else 5
    load_start = os.getloadavg()[0]
    rows = [
        "| robot | tau ops | elastic ops | ratio | tau ns/call | elastic ns/call | ratio "
        "| dynamics kernels built [s CPU] |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for path in ROBOTS:
        r = measure(path, repeats=repeats)
        rows.append(
            f"| `{path.relative_to(ROOT)}` | {r['rigid_ops']} | {r['elastic_ops']} | "
            f"{r['elastic_ops'] / r['rigid_ops']:.2f} | {r['rigid_ns']:.0f} | "
            f"{r['elastic_ns']:.0f} | {r['elastic_ns'] / r['rigid_ns']:.2f} "
            f"| {r['kernel_seconds']:.2f} |"
        )
    header = measured_line(
        f"{compiler()} with `-O2`; symkin {version('symkin')}, SymPy {version('sympy')}. C loop: "
        f"median of {repeats} repeats of 200,000 calls over 16,384 states, thread CPU time.",
        (load_start, os.getloadavg()[0]),
        "elastic_speed.py",
    )
    table = header + "\n\n" + "\n".join(rows)
    print(table)
    if not args.no_write:
        write_docs(table, args.docs, MARKERS, "Elastic joints")
        print(f"wrote {args.docs}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
