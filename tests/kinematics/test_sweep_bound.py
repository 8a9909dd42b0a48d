"""The collision scan's shortcuts: a block of consecutive configurations clears a pair of joints
only where no configuration of it brings them near (against forward kinematics at every one),
the scan finds the same contacts with and without it, the geometry pairs of a pair of bodies
are measured deepest bound first, and distinct configurations are found by their bytes."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from walks import random_walk

from motiontool.kinematics import _pinocchio, load_robot
from motiontool.kinematics import collision as collision_module
from motiontool.kinematics import distinct_rows as distinct_module
from motiontool.kinematics.collision import forward_kinematics, scan_self_collisions
from motiontool.kinematics.sweep_bound import SWEEP_BLOCK, cleared_groups

pytestmark = pytest.mark.needs("kinematics")


def _joint_gaps(tables: _pinocchio.KinematicTables, q: np.ndarray) -> np.ndarray:
    """(N, groups) m: distance of each group's two joint sphere centres at each configuration."""
    rot, pos = forward_kinematics(tables, q)
    centers = pos + np.einsum("njik,jk->nji", rot, tables.joint_center)
    ja, jb = tables.group_joints[:, 0], tables.group_joints[:, 1]
    return np.linalg.norm(centers[:, ja] - centers[:, jb], axis=2)


@settings(max_examples=30, deadline=None)
@given(
    st.sampled_from(["nao", "ur5e"]),
    st.sampled_from([0.0005, 0.005, 0.05, 0.5]),
    st.integers(1, 100),
    st.integers(0, 2**16),
    st.sampled_from([0.0, 0.015]),
)
def test_a_cleared_pair_is_apart_at_every_configuration_of_its_block(
    robot: str, step: float, n: int, seed: int, tolerance: float
) -> None:
    spec = load_robot(robot)
    tables = _pinocchio.kinematic_tables(spec)
    q = random_walk(robot, n, step, seed)
    groups = np.arange(tables.group_joints.shape[0])
    cleared = cleared_groups(tables, q, groups, tolerance)
    assert cleared is not None and cleared.shape == (-(-n // SWEEP_BLOCK), groups.shape[0])
    reach = tables.joint_radius[tables.group_joints].sum(axis=1) - tolerance
    near = _joint_gaps(tables, q) <= reach  # what the joint broad phase lets through
    assert not (near & cleared[np.arange(n) // SWEEP_BLOCK]).any()


def test_small_moves_clear_most_pairs_and_large_ones_few() -> None:
    # The bound is of use: a slow motion clears most (block, pair)s, a wild one hardly any.
    tables = _pinocchio.kinematic_tables(load_robot("nao"))
    groups = np.arange(tables.group_joints.shape[0])
    slow = cleared_groups(tables, random_walk("nao", 320, 0.002, 1), groups, 0.015)
    wild = cleared_groups(tables, random_walk("nao", 320, 1.0, 1), groups, 0.015)
    assert slow is not None and wild is not None
    assert slow.mean() > 0.9 and wild.mean() < slow.mean() - 0.1


def test_a_model_with_a_prismatic_joint_is_not_swept() -> None:
    tables = _pinocchio.kinematic_tables(load_robot("erd:panda"))  # its fingers slide
    assert cleared_groups(tables, np.zeros((4, len(load_robot("erd:panda").joints))),
                          np.arange(tables.group_joints.shape[0]), 0.0) is None  # fmt: skip


@pytest.mark.parametrize(("robot", "step"), [("nao", 0.01), ("nao", 0.08), ("ur5e", 0.1)])
@pytest.mark.parametrize("tolerance", [0.0, 0.015])
def test_the_scan_finds_the_same_contacts_without_the_sweep(
    monkeypatch: pytest.MonkeyPatch, robot: str, step: float, tolerance: float
) -> None:
    spec = load_robot(robot)
    q = random_walk(robot, 3000, step, seed=9)
    swept = scan_self_collisions(spec, q, penetration_tolerance_m=tolerance)
    skipped: list[int] = []
    sweep = collision_module.cleared_groups

    def counted(*args: object) -> object:
        got = sweep(*args)  # type: ignore[arg-type]
        skipped.append(0 if got is None else int(got.sum()))
        return got

    monkeypatch.setattr(collision_module, "cleared_groups", counted)
    assert scan_self_collisions(spec, q, penetration_tolerance_m=tolerance) == swept
    assert sum(skipped) > 0  # the sweep did clear pairs
    monkeypatch.setattr(collision_module, "cleared_groups", lambda *args: None)
    assert scan_self_collisions(spec, q, penetration_tolerance_m=tolerance) == swept
    assert len(swept) > 20


def test_the_deepest_pair_of_geometries_is_found_without_measuring_them_all(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # A forearm folded across the belly and wild poses: each pair of bodies' depth is the
    # deepest of its geometry pairs, as measuring every one of them gives, with fewer measures.
    spec = load_robot("nao")
    q = random_walk("nao", 400, 0.6, seed=2)
    measured: list[int] = []
    distances = _pinocchio.pair_signed_distances

    def every(spec_: object, unique: np.ndarray, rows: np.ndarray, pairs: np.ndarray) -> object:
        measured.append(rows.shape[0])
        return distances(spec_, unique, rows, pairs)  # type: ignore[arg-type]

    def all_at_once(*args: object) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        _spec, _tables, _ids, unique, rows, pairs, bound = args
        found = _pinocchio.pair_signed_distances(_spec, unique, rows, pairs)  # type: ignore[arg-type]
        depth = np.minimum(-found, bound)
        return rows, pairs, depth  # type: ignore[return-value]

    monkeypatch.setattr(_pinocchio, "pair_signed_distances", every)
    first = scan_self_collisions(spec, q, fingers_in_hand=True)
    fewer = sum(measured)
    monkeypatch.setattr(collision_module, "deepest_first", all_at_once)
    measured.clear()
    assert scan_self_collisions(spec, q, fingers_in_hand=True) == first
    assert len(first) > 50 and fewer < sum(measured)


def test_distinct_configurations_by_their_bytes_whatever_their_hash(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    q = np.array([[0.5, 1.0], [0.0, 2.0], [0.5, 1.0], [-0.0, 2.0], [0.0, 2.0], [3.0, 3.0]])
    unique, inverse, hashed = distinct_module.distinct_rows(q)
    # -0.0 and 0.0 have different bytes: two configurations, each checked (the same answer).
    assert unique.tolist() == [[0.5, 1.0], [0.0, 2.0], [-0.0, 2.0], [3.0, 3.0]]
    assert np.signbit(unique[2, 0]) and inverse.tolist() == [0, 1, 0, 2, 1, 3]
    assert len(set(hashed.tolist())) == 4
    every, order, _ = distinct_module.distinct_rows(unique)  # all distinct: as they are
    assert every.tolist() == unique.tolist() and order.tolist() == [0, 1, 2, 3]
    monkeypatch.setattr(distinct_module, "_hash_weights", lambda n: np.zeros(n, np.uint64))
    same, again, _ = distinct_module.distinct_rows(q)  # every row hashed alike: bytes decide
    assert same.tolist() == unique.tolist() and again.tolist() == inverse.tolist()


def test_a_configuration_met_before_is_known_by_its_bytes_not_its_hash(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # Every configuration given one hash: the memo of the first call (a hand in the hip) must
    # not answer for another configuration of the second call (the arm down, no contact).
    spec = load_robot("nao")
    into_hip = np.zeros((1, len(spec.joints)))
    for name, value in {"RShoulderPitch": 1.7, "RShoulderRoll": 0.3, "RElbowYaw": -1.8}.items():
        into_hip[0, spec.joint_names.index(name)] = value
    distinct_rows = collision_module.distinct_rows

    def one_hash(q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        unique, inverse, hashed = distinct_rows(q)
        return unique, inverse, np.zeros_like(hashed)

    monkeypatch.setattr(collision_module, "distinct_rows", one_hash)
    known = collision_module.Known()
    assert scan_self_collisions(spec, into_hip, known=known, fingers_in_hand=True)
    assert len(known) == 1
    assert scan_self_collisions(spec, 0 * into_hip, known=known, fingers_in_hand=True) == []
    again = scan_self_collisions(spec, into_hip, known=known, fingers_in_hand=True)
    assert again == scan_self_collisions(spec, into_hip, fingers_in_hand=True)


def test_a_configuration_has_one_hash_whatever_block_it_is_in() -> None:
    # The memo finds a configuration of an earlier block by its hash: the same whichever of
    # its columns change in the block around it.
    x, y = np.array([0.5, -1.0, 0.0, 2.0]), np.array([0.5, 1.0, 0.0, -2.0])
    alone = distinct_module.distinct_rows(x[None])[2]
    among = distinct_module.distinct_rows(np.stack([y, x, y]))[2]
    assert alone.tolist() == [among[1]] and among[0] != among[1]
