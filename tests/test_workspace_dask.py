"""The Dask path of the workspace sampling equals the in-memory path (local cluster, 2 workers)."""

from __future__ import annotations

import numpy as np
import pytest

from symkin.derive import derive
from symkin.io import load_robot
from symkin.solve.workspace import sample_workspace
from symkin.solve.workspace_dask import dask_client, sample_workspace_dask

EXACT = (
    "outer_radius",
    "inner_radius",
    "surface_radius",
    "counts",
    "manipulability_max",
    "lower",
    "upper",
    "preview",
    "u_edges",
    "v_edges",
)


@pytest.mark.slow
def test_dask_equals_in_memory_on_two_local_workers() -> None:
    options = {"samples": 90_001, "plane": "xz", "seed": 5, "chunk": 20_000}  # a short last chunk
    model = derive(load_robot("puma560"), closed_forms=False)
    here = sample_workspace(model, **options)
    with dask_client(workers=2) as client:
        assert len(client.scheduler_info()["workers"]) == 2
        there = sample_workspace_dask(model, client=client, **options)
    for name in EXACT:  # maxima and counts do not depend on the order of merging
        np.testing.assert_array_equal(getattr(there, name), getattr(here, name), err_msg=name)
    # Sums of manipulability are added in another order: equal up to rounding.
    np.testing.assert_allclose(there.manipulability_mean, here.manipulability_mean, rtol=1e-12)
    assert here.counts.sum() == 90_001
