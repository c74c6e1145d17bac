"""Workspace sampling throughput: the in-memory path against Dask (local cluster of 2 workers).

Both paths run the same chunks (``symkin.solve.workspace``): the in-memory path loops over
them in this process (it must chunk too: 10^8 PUMA configurations with their Jacobians would
be ~36 GB at once), the Dask path maps them over a Dask array on a local cluster of
single-threaded worker processes.  For each: wall time, samples per second, and CPU time
(this process; for Dask the workers' CPU, read on each worker before and after).  The two
results are compared (maxima and counts must be identical).  On a shared machine the wall time
waits for a core; the CPU time is what the sampling costs.

    python bench/workspace_dask.py                                # PUMA 560, 10^8 samples
    python bench/workspace_dask.py --samples 1e6 --robot planar_2r
"""

from __future__ import annotations

import argparse
import json
import os
import time

import numpy as np

import symkin
from symkin.solve.workspace import sample_workspace
from symkin.solve.workspace_dask import dask_client, sample_workspace_dask

SAME = ("outer_radius", "inner_radius", "surface_radius", "counts", "manipulability_max")


def _worker_cpu() -> float:
    return time.process_time()


def in_memory(model, options: dict) -> tuple[object, dict]:
    wall, cpu = time.perf_counter(), time.process_time()
    result = sample_workspace(model, **options)
    return result, {
        "wall_s": time.perf_counter() - wall,
        "cpu_s": time.process_time() - cpu,
    }


def on_dask(model, options: dict, workers: int) -> tuple[object, dict]:
    start = time.perf_counter()
    with dask_client(workers=workers) as client:
        ready = time.perf_counter()
        before = client.run(_worker_cpu)
        cpu = time.process_time()
        result = sample_workspace_dask(model, client=client, **options)
        wall = time.perf_counter() - ready
        after = client.run(_worker_cpu)
    worker_cpu = sum(after[w] - before[w] for w in after)
    return result, {
        "cluster_start_s": ready - start,
        "wall_s": wall,
        "cpu_s": worker_cpu + time.process_time() - cpu,
        "workers": workers,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--robot", default="puma560")
    parser.add_argument("--samples", type=float, default=1e8)
    parser.add_argument("--chunk", type=int, default=250_000)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    model = symkin.derive(symkin.load_robot(args.robot), closed_forms=False)
    options = {"samples": int(args.samples), "chunk": args.chunk, "plane": "xz"}
    sample_workspace(model, 1000)  # build and import the kernels first
    here, memory = in_memory(model, options)
    there, dask = on_dask(model, options, args.workers)
    equal = all(np.array_equal(getattr(here, k), getattr(there, k), equal_nan=True) for k in SAME)
    for timing in (memory, dask):
        timing["samples_per_s"] = options["samples"] / timing["wall_s"]
    report = {
        "robot": args.robot,
        "samples": options["samples"],
        "chunk": args.chunk,
        "load_average": os.getloadavg(),
        "cpus": os.cpu_count(),
        "in_memory": memory,
        "dask": dask,
        "identical": equal,
    }
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
