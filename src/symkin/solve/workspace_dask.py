"""The workspace sampling of :mod:`symkin.solve.workspace` on Dask arrays, chunked, out of core.

The same chunks as the in-memory path (chunk ``c`` drawn from ``default_rng([seed, c + 1])``)
become a Dask array of configurations, ``(samples, n)`` in row chunks; the generated NumPy
kernel ``fk_jacobian`` runs on each block and reduces it to its summary row; the rows merge by
``max`` and ``+`` in Dask's reduction tree.  No block outlives its summary, so the number of
samples is limited by time, not by memory.  The result equals the in-memory one (maxima and
counts exactly; the manipulability sums up to rounding, as they are added in another order).

Workers get the kernel as its generated source text and import it once per process (through
:func:`symkin.runtime.modules.module_from_source`), not the SymPy model.  Needs the optional
extra ``symkin[dask]`` (``dask[distributed]``).
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

from symkin.derive import Model
from symkin.errors import SymkinError
from symkin.runtime.modules import generated_numpy_module, module_from_source
from symkin.solve.workspace import (
    DEFAULT_SAMPLES,
    MAX_LENGTH,
    ROW_LENGTH,
    SamplingPlan,
    Workspace,
    block_summary,
    evaluate_block,
    plan_sampling,
    preview_points,
    sample_block,
    workspace_from_summaries,
)

DEFAULT_WORKERS = 2

# Kernels imported in this (worker) process, by the hash of their source.
_KERNELS: dict[str, ModuleType] = {}


def _kernel(source: str) -> Any:
    digest = hashlib.sha256(source.encode()).hexdigest()
    if digest not in _KERNELS:
        _KERNELS[digest] = module_from_source(source, "workspace")
    return _KERNELS[digest].fk_jacobian


def _sample(index_block: np.ndarray, plan: SamplingPlan) -> np.ndarray:
    return sample_block(plan, int(index_block[0]))


def _summarise(q_block: np.ndarray, plan: SamplingPlan, source: str) -> np.ndarray:
    positions, manipulability = evaluate_block(_kernel(source), plan, q_block)
    return block_summary(positions, manipulability, plan)


def _dask() -> tuple[Any, Any]:
    try:
        import dask.array as da
        import distributed
    except ImportError as error:
        raise SymkinError(
            "--dask needs dask: pip install 'symkin[dask]' (or pip install 'dask[distributed]')"
        ) from error
    return da, distributed


@contextmanager
def dask_client(address: str | None = None, workers: int = DEFAULT_WORKERS) -> Iterator[Any]:
    """A client of the cluster at ``address``, or of a new local cluster of ``workers``
    single-threaded worker processes (closed on exit)."""
    _, distributed = _dask()
    if address:
        try:
            client = distributed.Client(address, timeout="20s")
        except OSError as error:
            raise SymkinError(f"cannot reach the Dask scheduler at {address}: {error}") from None
        with client:
            yield client
        return
    with (
        distributed.LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        yield client


def summary_arrays(plan: SamplingPlan, source: str) -> tuple[Any, Any]:
    """Lazy Dask arrays: the merged maxima and sums of every chunk of ``plan``."""
    da, _ = _dask()
    sizes = plan.chunk_sizes
    dof = len(plan.low)
    indices = da.arange(len(sizes), chunks=1)
    q = indices.map_blocks(_sample, plan, chunks=(sizes, (dof,)), new_axis=1, dtype=float)
    rows = q.map_blocks(
        _summarise, plan, source, chunks=((1,) * len(sizes), (ROW_LENGTH,)), dtype=float
    )
    return rows[:, :MAX_LENGTH].max(axis=0), rows[:, MAX_LENGTH:].sum(axis=0)


def sample_workspace_dask(
    model: Model, samples: int = DEFAULT_SAMPLES, client: Any = None, **options: Any
) -> Workspace:
    """:func:`symkin.solve.workspace.sample_workspace` on a Dask cluster.

    ``client``: a ``distributed.Client``; None starts a local cluster of two workers for this
    call (see :func:`dask_client`).  ``options`` as for
    :func:`~symkin.solve.workspace.plan_sampling`."""
    plan = plan_sampling(model, samples, **options)
    module = generated_numpy_module(model, "kinematics")
    source = Path(module.__file__).read_text(encoding="utf-8")
    maxima, sums = summary_arrays(plan, source)
    if client is None:
        with dask_client() as own:
            maxima, sums = own.compute([maxima, sums], sync=True)
    else:
        maxima, sums = client.compute([maxima, sums], sync=True)
    preview = preview_points(module.fk_jacobian, plan)
    return workspace_from_summaries(model, plan, np.asarray(maxima), np.asarray(sums), preview)
