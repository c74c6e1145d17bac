"""Reachable workspace and dexterity map by sampling the joint space.

Configurations are drawn uniformly within the joint limits (a joint without limits:
``(-pi, pi]`` if revolute, ``[-1, 1]`` m if prismatic, as for the IK restarts), in chunks:
chunk ``c`` of a run with seed ``s`` is drawn from ``numpy.random.default_rng([s, c])``, so the
samples do not depend on who computes the chunk (this process, or a Dask worker: see
:mod:`symkin.solve.workspace_dask`).  The generated NumPy kernel ``fk_jacobian`` evaluates each
chunk as one batch; nothing larger than a chunk is ever held.

Each chunk is reduced to fixed-size summaries that merge by ``max`` and ``+`` (so any number of
chunks, in any order, on any machine, gives the same result):

* the **2-D boundary** in a plane (``xy``, ``xz`` or ``yz``): the points are projected onto
  the plane (the workspace seen along the plane's normal) and, per polar-angle bin around the
  base origin, the largest and smallest radius reached: the outer and inner boundary curves
  (exact for star-shaped regions such as the annulus ``|L1 - L2| <= r <= L1 + L2`` of a planar
  2R; a region that is not star-shaped about the origin gets its star-shaped hull);
* the **3-D boundary**: per direction bin (azimuth x elevation around the base origin) the
  largest distance reached, the star-shaped outer surface of the point cloud;
* an **occupancy grid** over the plane (samples per cell) and the **dexterity map**: per cell the
  largest and the mean translational manipulability ``w = sqrt(det(Jv Jv^T))`` (Yoshikawa 1985;
  ``Jv`` the translational rows of the geometric Jacobian that are not identically zero, and
  ``sqrt(det(Jv^T Jv))`` when it has more rows than joints), so each point of the plane shows how
  well the arm can move there at best and on average.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from symkin.derive import Model
from symkin.derive.jacobians import rows_from_names
from symkin.errors import ParameterError, SymkinError
from symkin.runtime.modules import generated_numpy_module
from symkin.solve.ik.joints import PRISMATIC_RANGE, joint_bounds, parameter_vector
from symkin.solve.plotting import png_bytes

PLANES = {"xy": (0, 1, 2), "xz": (0, 2, 1), "yz": (1, 2, 0)}
DEFAULT_SAMPLES = 200_000
DEFAULT_CHUNK = 100_000
# One chunk is held in memory (q, the positions and the Jacobian rows: under 0.5 GB for seven
# joints at the cap); the chunks are a tuple here and a task each on Dask, so their number is
# capped too: at most MAX_CHUNK * MAX_CHUNKS = 10^11 samples, days of CPU time.
MAX_CHUNK = 1_000_000
MAX_CHUNKS = 100_000
ANGLE_BINS = 180
AZIMUTH_BINS, ELEVATION_BINS = 72, 35  # odd: a bin centred on the horizontal
GRID_CELLS = 80
PILOT_SAMPLES = 20_000  # sets the grid's extent; the pilot's chunk index is -1
PREVIEW_POINTS = 5_000  # kept for plots and CSV: the first points of chunk 0


@dataclass(frozen=True)
class SamplingPlan:
    """What every chunk needs, and nothing of the model: picklable for Dask workers.

    ``rows`` are the translational Jacobian rows of the manipulability; ``extent`` is the grid's
    ``(u_min, u_max, v_min, v_max)`` in the plane.
    """

    low: tuple[float, ...]
    high: tuple[float, ...]
    parameters: tuple[float, ...]
    rows: tuple[int, ...]
    plane: str
    extent: tuple[float, float, float, float]
    seed: int
    chunk: int
    samples: int

    @property
    def chunk_sizes(self) -> tuple[int, ...]:
        full, rest = divmod(self.samples, self.chunk)
        return (self.chunk,) * full + ((rest,) if rest else ())


@dataclass(frozen=True)
class Workspace:
    """The merged summaries of a sampling run (see the module docstring); lengths in metres.

    Empty bins and cells hold NaN.  ``outer_radius``/``inner_radius`` are indexed by the bin
    centres ``angles`` (rad, ``atan2(v, u)`` in the plane); ``surface_radius[a, e]`` by
    ``azimuths`` and ``elevations``; the grids ``[i, j]`` by cell ``u_edges[i]..u_edges[i+1]``,
    ``v_edges[j]..v_edges[j+1]``.  ``preview`` holds the first sampled points (x, y, z).
    """

    robot: str
    plane: str
    samples: int
    seed: int
    angles: np.ndarray
    outer_radius: np.ndarray
    inner_radius: np.ndarray
    azimuths: np.ndarray
    elevations: np.ndarray
    surface_radius: np.ndarray
    u_edges: np.ndarray
    v_edges: np.ndarray
    counts: np.ndarray
    manipulability_max: np.ndarray
    manipulability_mean: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    preview: np.ndarray = field(repr=False)

    def _repr_png_(self) -> bytes:
        """Jupyter: the three-panel figure of :mod:`symkin.solve.workspace_plot`."""
        # Imported here: the plot module imports this one.
        from symkin.solve.workspace_plot import workspace_figure

        return png_bytes(workspace_figure(self))


def translational_rows(model: Model) -> tuple[int, ...]:
    """Indices of the x, y, z rows of the geometric Jacobian that are not identically zero."""
    jacobian = model.product_form.geometric_jacobian
    names = [n for k, n in enumerate("xyz") if any(e != 0 for e in jacobian.row(k))]
    return rows_from_names(names)


def sample_block(plan: SamplingPlan, index: int) -> np.ndarray:
    """The configurations of chunk ``index`` (``-1``: the pilot), shape (size, n)."""
    size = PILOT_SAMPLES if index < 0 else plan.chunk_sizes[index]
    rng = np.random.default_rng([plan.seed, index + 1])  # entropy must be non-negative
    return rng.uniform(plan.low, plan.high, size=(size, len(plan.low)))


def _check_sizes(samples: int, chunk: int) -> None:
    """At most :data:`MAX_CHUNK` configurations a chunk and :data:`MAX_CHUNKS` chunks."""
    if chunk > MAX_CHUNK:
        raise ParameterError(f"{{chunk}} {chunk:.3g} is over the cap of {MAX_CHUNK:,} (memory)")
    chunks = -(-samples // chunk)
    if chunks > MAX_CHUNKS:
        raise ParameterError(
            f"{{samples}} {samples:.3g} in chunks of {chunk:,} makes {chunks:.3g} chunks; at "
            f"most {MAX_CHUNKS:,} chunks of at most {MAX_CHUNK:,} ({{chunk}}), so {{samples}} "
            f"at most {MAX_CHUNK * MAX_CHUNKS:.0e}"
        )


def plan_sampling(
    model: Model,
    samples: int = DEFAULT_SAMPLES,
    plane: str = "xy",
    seed: int = 0,
    chunk: int = DEFAULT_CHUNK,
    overrides: Mapping[str, float] | None = None,
) -> SamplingPlan:
    """The plan of a run; the grid extent comes from a pilot chunk, 5 % margin each side."""
    if plane not in PLANES:
        raise SymkinError(f"plane must be one of {', '.join(PLANES)}, got {plane!r}")
    if samples < 1 or chunk < 1:
        raise SymkinError(f"samples and chunk size must be positive, got {samples} and {chunk}")
    _check_sizes(samples, chunk)
    lower, upper = joint_bounds(model)
    revolute = np.array([j.type == "revolute" for j in model.robot.joints])
    default = np.where(revolute, np.pi, PRISMATIC_RANGE)
    low = np.where(np.isfinite(lower), lower, -default)
    high = np.where(np.isfinite(upper), upper, default)
    plan = SamplingPlan(
        low=tuple(map(float, low)),
        high=tuple(map(float, high)),
        parameters=tuple(map(float, parameter_vector(model, overrides))),
        rows=translational_rows(model),
        plane=plane,
        extent=(-1.0, 1.0, -1.0, 1.0),
        seed=int(seed),
        chunk=int(chunk),
        samples=int(samples),
    )
    kernel = generated_numpy_module(model, "kinematics").fk_jacobian
    positions, _ = evaluate_block(kernel, plan, sample_block(plan, -1))
    u, v, _ = plane_coordinates(positions, plane)
    margin = 0.05 * max(float(np.ptp(u)), float(np.ptp(v)), 1e-6)
    extent = (u.min() - margin, u.max() + margin, v.min() - margin, v.max() + margin)
    return replace(plan, extent=tuple(map(float, extent)))


def plane_coordinates(
    positions: np.ndarray, plane: str
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(u, v, w)``: the two in-plane coordinates and the one along the plane's normal."""
    i, j, k = PLANES[plane]
    return positions[:, i], positions[:, j], positions[:, k]


def evaluate_block(kernel, plan: SamplingPlan, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Tool positions (size, 3) and translational manipulability (size,) of a batch ``q``."""
    with np.errstate(all="ignore"):
        transform, jacobian = kernel(q, np.asarray(plan.parameters))
    Jv = jacobian[:, list(plan.rows), :]
    k, n = Jv.shape[1:]
    gram = Jv @ np.swapaxes(Jv, 1, 2) if k <= n else np.swapaxes(Jv, 1, 2) @ Jv
    manipulability = np.sqrt(np.maximum(np.linalg.det(gram), 0.0))
    return transform[:, :3, 3], manipulability


# The summaries of one chunk, flattened into one row: first the parts merged by max (minima
# are stored negated), then the parts merged by sum.
def _sizes() -> dict[str, int]:
    return {
        "outer": ANGLE_BINS,
        "neg_inner": ANGLE_BINS,
        "surface": AZIMUTH_BINS * ELEVATION_BINS,
        "manip_max": GRID_CELLS * GRID_CELLS,
        "upper": 3,
        "neg_lower": 3,
        "counts": GRID_CELLS * GRID_CELLS,
        "manip_sum": GRID_CELLS * GRID_CELLS,
    }


SUM_PARTS = ("counts", "manip_sum")
ROW_LENGTH = sum(_sizes().values())
MAX_LENGTH = ROW_LENGTH - sum(_sizes()[p] for p in SUM_PARTS)


def _binned_max(index: np.ndarray, values: np.ndarray, bins: int) -> np.ndarray:
    out = np.full(bins, -np.inf)
    np.maximum.at(out, index, values)
    return out


def block_summary(positions: np.ndarray, manipulability: np.ndarray, plan: SamplingPlan):
    """The chunk's summary row, shape (1, ROW_LENGTH) (see :data:`SUM_PARTS`)."""
    u, v, _ = plane_coordinates(positions, plan.plane)
    radius = np.hypot(u, v)
    angle_bin = _bin(np.arctan2(v, u), -np.pi, np.pi, ANGLE_BINS)
    distance = np.linalg.norm(positions, axis=1)
    azimuth = _bin(np.arctan2(positions[:, 1], positions[:, 0]), -np.pi, np.pi, AZIMUTH_BINS)
    elevation_angle = np.arcsin(np.clip(positions[:, 2] / np.maximum(distance, 1e-300), -1, 1))
    elevation = _bin(elevation_angle, -np.pi / 2, np.pi / 2, ELEVATION_BINS)
    u_min, u_max, v_min, v_max = plan.extent
    cell_u, cell_v = _bin(u, u_min, u_max, GRID_CELLS), _bin(v, v_min, v_max, GRID_CELLS)
    inside = (u >= u_min) & (u <= u_max) & (v >= v_min) & (v <= v_max)
    cell = (cell_u * GRID_CELLS + cell_v)[inside]
    cells = GRID_CELLS * GRID_CELLS
    parts = [
        _binned_max(angle_bin, radius, ANGLE_BINS),
        _binned_max(angle_bin, -radius, ANGLE_BINS),
        _binned_max(azimuth * ELEVATION_BINS + elevation, distance, AZIMUTH_BINS * ELEVATION_BINS),
        _binned_max(cell, manipulability[inside], cells),
        positions.max(axis=0, initial=-np.inf),
        (-positions).max(axis=0, initial=-np.inf),
        np.bincount(cell, minlength=cells).astype(float),
        np.bincount(cell, weights=manipulability[inside], minlength=cells),
    ]
    return np.concatenate(parts)[None, :]


def _bin(values: np.ndarray, low: float, high: float, bins: int) -> np.ndarray:
    """Bin index of each value in ``bins`` equal bins over ``[low, high]`` (ends included)."""
    index = np.floor((values - low) / (high - low) * bins).astype(np.int64)
    return np.clip(index, 0, bins - 1)


def chunk_summary(kernel, plan: SamplingPlan, index: int) -> np.ndarray:
    """Sample chunk ``index``, evaluate it and reduce it to its summary row."""
    positions, manipulability = evaluate_block(kernel, plan, sample_block(plan, index))
    return block_summary(positions, manipulability, plan)


def merge_summaries(maxima: np.ndarray, sums: np.ndarray) -> dict[str, np.ndarray]:
    """The named parts of merged summaries (max parts, sum parts), empty bins NaN."""
    flat = np.concatenate([maxima, sums])
    parts, start = {}, 0
    for name, size in _sizes().items():
        part = flat[start : start + size]
        parts[name] = np.where(np.isfinite(part), part, np.nan)
        start += size
    return parts


def workspace_from_summaries(
    model: Model, plan: SamplingPlan, maxima: np.ndarray, sums: np.ndarray, preview: np.ndarray
) -> Workspace:
    """Assemble a :class:`Workspace` from merged summary parts."""
    p = merge_summaries(maxima, sums)
    grid = (GRID_CELLS, GRID_CELLS)
    counts = p["counts"].reshape(grid)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(counts > 0, p["manip_sum"].reshape(grid) / counts, np.nan)
    u_min, u_max, v_min, v_max = plan.extent
    return Workspace(
        robot=model.robot.name,
        plane=plan.plane,
        samples=plan.samples,
        seed=plan.seed,
        angles=_centres(-np.pi, np.pi, ANGLE_BINS),
        outer_radius=p["outer"],
        inner_radius=-p["neg_inner"],
        azimuths=_centres(-np.pi, np.pi, AZIMUTH_BINS),
        elevations=_centres(-np.pi / 2, np.pi / 2, ELEVATION_BINS),
        surface_radius=p["surface"].reshape(AZIMUTH_BINS, ELEVATION_BINS),
        u_edges=np.linspace(u_min, u_max, GRID_CELLS + 1),
        v_edges=np.linspace(v_min, v_max, GRID_CELLS + 1),
        counts=counts,
        manipulability_max=p["manip_max"].reshape(grid),
        manipulability_mean=mean,
        lower=-p["neg_lower"],
        upper=p["upper"],
        preview=preview,
    )


def _centres(low: float, high: float, bins: int) -> np.ndarray:
    edges = np.linspace(low, high, bins + 1)
    return (edges[:-1] + edges[1:]) / 2


def preview_points(kernel, plan: SamplingPlan) -> np.ndarray:
    """The first :data:`PREVIEW_POINTS` tool positions of chunk 0 (for plots and CSV)."""
    q = sample_block(plan, 0)[:PREVIEW_POINTS]
    return evaluate_block(kernel, plan, q)[0]


def sample_workspace(model: Model, samples: int = DEFAULT_SAMPLES, **options: Any) -> Workspace:
    """The workspace of ``samples`` configurations, computed here chunk by chunk.

    ``options``: ``plane``, ``seed``, ``chunk`` and ``overrides`` as for
    :func:`plan_sampling`.  Memory is that of one chunk, whatever ``samples`` is; the same run
    on Dask (:func:`symkin.solve.workspace_dask.sample_workspace_dask`) gives the same result."""
    plan = plan_sampling(model, samples, **options)
    kernel = generated_numpy_module(model, "kinematics").fk_jacobian
    maxima = np.full(MAX_LENGTH, -np.inf)
    sums = np.zeros(ROW_LENGTH - MAX_LENGTH)
    for index in range(len(plan.chunk_sizes)):
        row = chunk_summary(kernel, plan, index)[0]
        maxima = np.maximum(maxima, row[:MAX_LENGTH])
        sums += row[MAX_LENGTH:]
    return workspace_from_summaries(model, plan, maxima, sums, preview_points(kernel, plan))


def boundary_polygon(workspace: Workspace, which: str = "outer") -> np.ndarray:
    """The ``outer`` or ``inner`` boundary as plane points (u, v), one per non-empty bin."""
    radius = workspace.outer_radius if which == "outer" else workspace.inner_radius
    keep = np.isfinite(radius)
    angles = workspace.angles[keep]
    return np.column_stack([radius[keep] * np.cos(angles), radius[keep] * np.sin(angles)])
