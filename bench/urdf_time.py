"""URDF robots: the Panda read and its readable FK + J derived, and a full ``symkin derive`` of
the UR5 (issue 16's targets: under 2 s and under 10 s).

Each measurement is a fresh process (``python -c`` for the Panda, the ``symkin`` command for the
UR5 with ``--no-cache``), timed by ``os.wait4``: wall time, and CPU time (user + system,
including the C compiler ``derive`` waits for).  On a shared machine the CPU time is the figure
to compare; the wall time is given with the load average.  The URDFs are those shipped in the
``example-robot-data`` package.  Writes its table into ``docs/benchmarks.md`` between
``<!-- urdf:begin -->`` and ``<!-- urdf:end -->``.  No test passes or fails on it.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from importlib.metadata import distribution
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from codegen_speed import write_docs

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs" / "benchmarks.md"
MARKERS = ("<!-- urdf:begin -->", "<!-- urdf:end -->")
ROBOTS = "cmeel.prefix/share/example-robot-data/robots"

PANDA = """
import time, warnings
warnings.simplefilter("ignore")
import symkin
start = time.perf_counter()
model = symkin.derive(symkin.load_robot({path!r}, tip="panda_hand_tcp"))
model.forward_kinematics, model.geometric_jacobian
print(f"{{time.perf_counter() - start:.3f}}")
"""


def timed(command: list[str], cwd: str) -> tuple[float, float, str]:
    """``(wall, cpu, stdout)`` of one child process."""
    start = time.perf_counter()
    child = subprocess.Popen(command, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
    out = child.stdout.read().decode() if child.stdout else ""
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.perf_counter() - start
    if status != 0:
        raise SystemExit(f"failed: {' '.join(command)}")
    return wall, usage.ru_utime + usage.ru_stime, out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--docs", type=Path, default=DOCS)
    args = parser.parse_args()
    robots = Path(str(distribution("example-robot-data").locate_file(ROBOTS)))
    panda = robots / "panda_description/urdf/panda.urdf"
    ur5 = robots / "ur_description/urdf/ur5_robot.urdf"
    symkin = str(Path(sys.executable).parent / "symkin")
    with tempfile.TemporaryDirectory() as work:
        code = PANDA.format(path=str(panda))
        panda_wall, panda_cpu, inner = timed([sys.executable, "-c", code], work)
        ur5_command = [symkin, "derive", str(ur5), "--tip", "tool0", "--out", "ur5", "--no-cache"]
        ur5_wall, ur5_cpu, _ = timed(ur5_command, work)
    load = os.getloadavg()[0]
    table = "\n".join(
        [
            f"Measured by `bench/urdf_time.py` on {os.cpu_count()} cores, load average "
            f"{load:.1f} at the end (the machine was shared; compare CPU times).",
            "",
            "| what | target | CPU time | wall time |",
            "|------|--------|----------|-----------|",
            f"| Panda URDF: load + readable FK + J (process, with imports) | 2 s | "
            f"{panda_cpu:.2f} s | {panda_wall:.2f} s (load + FK + J alone: {float(inner):.2f} s) |",
            f"| UR5 URDF: `symkin derive --tip tool0 --no-cache` (all backends, C compiled) | "
            f"10 s | {ur5_cpu:.2f} s | {ur5_wall:.2f} s |",
        ]
    )
    write_docs(table, args.docs, MARKERS, "URDF robots")
    print(table)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
