"""The pair sweep (``kinematics/pair_sweep.py``) clears a pair of geometries for a run of
configurations only where it cannot penetrate as deep as the tolerance at any of them (the
overlap along every direction of the bound at the run's first configuration, measured at each
configuration), and the scan finds the same contacts with and without it."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from walks import random_walk

from motiontool.kinematics import _pinocchio, load_robot, pair_sweep
from motiontool.kinematics import collision as collision_module
from motiontool.kinematics.collision import geometry_poses, scan_self_collisions
from motiontool.kinematics.overlap_bound import _projected_overlap

pytestmark = pytest.mark.needs("kinematics")


def _overlap_along_first_directions(
    tables: _pinocchio.KinematicTables,
    rot: np.ndarray,
    centers: np.ndarray,
    rows: np.ndarray,
    pairs: np.ndarray,
) -> np.ndarray:
    """(C,) m: the smallest overlap of each candidate's two shapes at its own configuration
    along the 16 world directions that the bound takes at its run's first configuration."""
    a, b = tables.pair_first[pairs], tables.pair_second[pairs]
    f = rows // pair_sweep.PAIR_SWEEP * pair_sweep.PAIR_SWEEP
    ua, ub = np.swapaxes(rot[f, a], 1, 2), np.swapaxes(rot[f, b], 1, 2)
    x, y = ua[:, :, None, :], ub[:, None, :, :]
    cross = np.cross(x, y).reshape(-1, 9, 3)
    directions = [(centers[f, b] - centers[f, a])[:, None, :], ua, ub, cross]
    d = centers[rows, b] - centers[rows, a]
    return _projected_overlap(tables, a, b, rot[rows, a], rot[rows, b], d, directions)


@settings(max_examples=25, deadline=None)
@given(
    st.sampled_from(["nao", "ur5e"]),
    st.sampled_from([0.001, 0.01, 0.05, 0.3]),
    st.integers(2, 40),
    st.integers(0, 2**16),
    st.sampled_from([0.0, 0.015]),
)
def test_a_cleared_candidate_overlaps_less_than_the_tolerance_along_a_direction(
    robot: str, step: float, n: int, seed: int, tolerance: float
) -> None:
    """Every candidate the sweep drops has, at its own configuration, an overlap below the
    tolerance along one of the directions of its run's first configuration: the shapes
    penetrate less deep than that (the separating-axis argument of the module doc)."""
    spec = load_robot(robot)
    tables = _pinocchio.kinematic_tables(spec)
    q = random_walk(robot, n, step, seed)
    rot, centers = geometry_poses(tables, q)
    pairs_all = np.arange(tables.pair_first.shape[0])
    rows = np.repeat(np.arange(n), pairs_all.shape[0])
    pairs = np.tile(pairs_all, n)
    kept_rows, kept_pairs = pair_sweep.uncleared(tables, q, rot, centers, rows, pairs, tolerance)
    kept = set(zip(kept_rows.tolist(), kept_pairs.tolist(), strict=True))
    dropped = np.array([(r, p) not in kept for r, p in zip(rows, pairs, strict=True)])
    if step <= 0.01:
        assert dropped.mean() > 0.3  # a slow motion clears many
    overlap = _overlap_along_first_directions(tables, rot, centers, rows[dropped], pairs[dropped])
    assert (overlap < tolerance).all()


@pytest.mark.parametrize(("robot", "step"), [("nao", 0.01), ("nao", 0.08), ("ur5e", 0.1)])
@pytest.mark.parametrize("tolerance", [0.0, 0.015])
def test_the_scan_finds_the_same_contacts_without_the_pair_sweep(
    monkeypatch: pytest.MonkeyPatch, robot: str, step: float, tolerance: float
) -> None:
    spec = load_robot(robot)
    q = random_walk(robot, 3000, step, seed=11)
    dropped: list[int] = []
    sweep = collision_module.uncleared

    def counted(*args: object) -> object:
        got = sweep(*args)  # type: ignore[arg-type]
        dropped.append(args[4].shape[0] - got[0].shape[0])  # type: ignore[attr-defined]
        return got

    monkeypatch.setattr(collision_module, "uncleared", counted)
    swept = scan_self_collisions(spec, q, penetration_tolerance_m=tolerance)
    assert sum(dropped) > 0  # the sweep did clear candidates
    monkeypatch.setattr(pair_sweep, "PAIR_SWEEP", 1)  # no sweep
    assert scan_self_collisions(spec, q, penetration_tolerance_m=tolerance) == swept
    assert len(swept) > 20


def test_a_run_in_which_a_motor_turns_far_is_not_bounded() -> None:
    """Runs in which a motor turns more than ``_TURN_RAD`` from the run's first configuration
    are left to the usual path, whatever their pairs (a motion of random values)."""
    spec = load_robot("nao")
    tables = _pinocchio.kinematic_tables(spec)
    q = np.zeros((64, len(spec.joints)))
    q[:, 0] = np.arange(64) * 0.8  # HeadYaw: 2.4 rad within each run of 4
    q[32:, 0] = 0.0  # then still
    rot, centers = geometry_poses(tables, q)
    rows = np.repeat(np.arange(64), tables.pair_first.shape[0])
    pairs = np.tile(np.arange(tables.pair_first.shape[0]), 64)
    kept_rows, _ = pair_sweep.uncleared(tables, q, rot, centers, rows, pairs, 0.015)
    assert pair_sweep.PAIR_SWEEP == 4 and pair_sweep._TURN_RAD < 2.4
    assert (np.bincount(kept_rows, minlength=64)[:32] == tables.pair_first.shape[0]).all()
    assert kept_rows.shape[0] < rows.shape[0] / 2 + 32 * 8  # the still half is cleared


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_how_far_a_rotation_moves_a_point_is_read_from_the_trace(seed: int) -> None:
    """||R - R0||_2 = sqrt(3 - trace(R0^T R)) for rotations (2 sin of half their angle)."""
    rng = np.random.default_rng(seed)
    r0, r = (np.linalg.qr(rng.normal(size=(3, 3)))[0] for _ in range(2))
    r0 *= np.sign(np.linalg.det(r0))
    r *= np.sign(np.linalg.det(r))
    norm = np.linalg.norm(r - r0, ord=2)
    assert math.isclose(norm, math.sqrt(max(3.0 - float((r0 * r).sum()), 0.0)), abs_tol=1e-7)
