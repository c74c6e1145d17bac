"""Workspace sampling, dexterity map and manipulability ellipsoids (symkin.solve).

Independent references: the planar 2R's annulus ``|L1 - L2| <= r <= L1 + L2`` and its
manipulability ``L1 L2 |sin q2|`` (hand derivation); NumPy's SVD of a Jacobian obtained by
differentiating a naive numeric DH product (tests/numeric_dh.py, not our kernels).
"""

from __future__ import annotations

import csv
import io
import json

import numpy as np
import pytest

from numeric_dh import NumericRobot
from symkin.cli import main
from symkin.derive import derive
from symkin.errors import SymkinError
from symkin.io import load_robot
from symkin.solve.ellipsoid import ellipsoids_at
from symkin.solve.workspace import plan_sampling, sample_block, sample_workspace

L1, L2 = 1.0, 0.6


@pytest.fixture(scope="module")
def two_r():
    model = derive(load_robot("planar_2r"), closed_forms=False)
    return model, sample_workspace(model, 60_000, chunk=15_000, overrides={"L2": L2})


def test_planar_2r_boundary_is_the_annulus(two_r) -> None:
    _, workspace = two_r
    outer, inner = workspace.outer_radius, workspace.inner_radius
    assert np.all(np.isfinite(outer)) and np.all(np.isfinite(inner))  # every angle reached
    # Never outside the annulus (up to rounding) and close to its radii in every bin.
    assert outer.max() <= L1 + L2 + 1e-12
    assert outer.min() > L1 + L2 - 2e-3
    assert inner.min() >= abs(L1 - L2) - 1e-12
    assert inner.max() < abs(L1 - L2) + 5e-3
    assert workspace.counts.sum() == 60_000
    np.testing.assert_allclose(workspace.upper[:2], [L1 + L2] * 2, atol=2e-3)
    assert workspace.lower[2] == workspace.upper[2] == 0.0


def test_planar_2r_dexterity_map_by_hand(two_r) -> None:
    # w = L1 L2 |sin q2| and r^2 = L1^2 + L2^2 + 2 L1 L2 cos q2: at radius r the manipulability
    # is fixed, w(r) = L1 L2 sqrt(1 - c^2) with c = (r^2 - L1^2 - L2^2) / (2 L1 L2).
    _, workspace = two_r
    u = (workspace.u_edges[:-1] + workspace.u_edges[1:]) / 2
    v = (workspace.v_edges[:-1] + workspace.v_edges[1:]) / 2
    uu, vv = np.meshgrid(u, v, indexing="ij")
    half_cell = np.hypot(np.diff(workspace.u_edges)[0], np.diff(workspace.v_edges)[0]) / 2

    def w(r):
        c = np.clip((r**2 - L1**2 - L2**2) / (2 * L1 * L2), -1, 1)
        return L1 * L2 * np.sqrt(1 - c**2)

    r = np.hypot(uu, vv)
    radii = np.linspace(r - half_cell, r + half_cell, 9)
    bound = w(radii).max(axis=0)  # the largest w anywhere in the cell: at a sampled radius,
    peak = np.hypot(L1, L2)  # or at the peak w = L1 L2 (cos q2 = 0) when the cell holds it
    bound = np.where(np.abs(r - peak) <= half_cell, L1 * L2, bound)
    seen = np.isfinite(workspace.manipulability_max)
    assert np.all(workspace.manipulability_max[seen] <= bound[seen] + 1e-9)
    assert np.nanmax(workspace.manipulability_max) == pytest.approx(L1 * L2, abs=1e-3)
    assert np.all(workspace.manipulability_mean[seen] <= workspace.manipulability_max[seen] + 1e-12)


def test_samples_respect_the_limits_and_the_seed() -> None:
    model = derive(load_robot("puma560"), closed_forms=False)
    plan = plan_sampling(model, 1000, chunk=400, seed=3)
    q = sample_block(plan, 2)
    assert q.shape == (200, 6)
    assert np.all(q >= plan.low) and np.all(q <= plan.high)
    np.testing.assert_array_equal(q, sample_block(plan, 2))  # a chunk is its seed's alone
    assert not np.array_equal(q[:10], sample_block(plan, 1)[:10])


@pytest.mark.parametrize("name", ["puma560", "stanford", "scara"])
def test_ellipsoid_axes_are_numpy_svd_of_a_dh_product_jacobian(name: str) -> None:
    robot = load_robot(name)
    model = derive(robot, closed_forms=False)
    reference = NumericRobot.from_robot(robot)
    rng = np.random.default_rng(7)
    for _ in range(3):
        q = rng.uniform(-1.5, 1.5, robot.dof)
        J = reference.jacobian(q, method="complex")
        rows = [k for k in range(3) if np.abs(J[k]).max() > 1e-12]
        U, s, _ = np.linalg.svd(J[rows])
        ellipsoids = ellipsoids_at(model, q)
        np.testing.assert_allclose(ellipsoids.velocity_radii, s, rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(ellipsoids.force_radii, 1 / s, rtol=1e-9)
        # Directions agree up to sign (distinct singular values at random q).
        np.testing.assert_allclose(np.abs(ellipsoids.axes.T @ U), np.eye(len(rows)), atol=1e-7)
        np.testing.assert_allclose(ellipsoids.position, reference.fk(q)[:3, 3], atol=1e-12)


def test_ellipsoid_at_a_singular_configuration() -> None:
    model = derive(load_robot("planar_2r"), closed_forms=False)
    ellipsoids = ellipsoids_at(model, [0.4, 0.0])  # stretched out: q2 = 0
    assert ellipsoids.rows == ("x", "y")
    assert ellipsoids.velocity_radii[-1] == pytest.approx(0.0, abs=1e-12)
    assert ellipsoids.force_radii[-1] == np.inf
    assert ellipsoids.manipulability == pytest.approx(0.0, abs=1e-12)
    # The stuck direction is radial: along the stretched arm.
    np.testing.assert_allclose(
        np.abs(ellipsoids.axes[:, -1]), np.abs([np.cos(0.4), np.sin(0.4)]), atol=1e-9
    )


def test_bad_plane_is_an_error() -> None:
    model = derive(load_robot("planar_2r"), closed_forms=False)
    with pytest.raises(SymkinError, match="xy"):
        sample_workspace(model, 10, plane="xw")


def run(capsys, *argv: str) -> tuple[int, str, str]:
    capsys.readouterr()
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def test_cli_workspace_json_and_csv(capsys, tmp_path) -> None:
    table = tmp_path / "boundary.csv"
    argv = ("workspace", "planar_2r", "--samples", "20000", "--set", "L2=0.6", "--json")
    status, out, err = run(capsys, *argv, "--csv", str(table))
    assert status == 0, err
    data = json.loads(out)
    assert data["samples"] == 20000 and data["plane"] == "xy"
    assert max(data["boundary"]["outer_radius"]) == pytest.approx(1.6, abs=5e-3)
    rows = list(csv.DictReader(io.StringIO(table.read_text())))
    assert len(rows) == 180
    assert float(rows[0]["outer_radius"]) == pytest.approx(1.6, abs=1e-2)


def test_cli_ellipsoid_json_and_errors(capsys) -> None:
    status, out, _ = run(capsys, "ellipsoid", "planar_2r", "--q", "0.3,90deg", "--json")
    assert status == 0
    data = json.loads(out)
    # At q2 = 90 deg (L1 = L2 = 1): J J^T has eigenvalues (3 +- sqrt 5) / 2.
    expected = np.sqrt([(3 + np.sqrt(5)) / 2, (3 - np.sqrt(5)) / 2])
    np.testing.assert_allclose(data["velocity_semi_axes"], expected)
    status, _, err = run(capsys, "ellipsoid", "planar_2r")
    assert status == 2 and "--q" in err
    status, _, err = run(capsys, "ellipsoid", "planar_2r", "--pose", "home")
    assert status == 2 and "no pose 'home'" in err
    with pytest.raises(SystemExit) as exit_status:  # argparse's own usage error
        run(capsys, "workspace", "planar_2r", "--samples", "0")
    assert exit_status.value.code == 2
