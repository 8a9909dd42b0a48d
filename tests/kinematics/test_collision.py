"""Batched self-collision: numpy kinematics against Pinocchio, the pruning bounds against coal
and exact geometry, and the whole scan against the one-configuration-at-a-time oracle."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import import_extra
from hypothesis import given, settings
from hypothesis import strategies as st

from motiontool.errors import MotionToolError
from motiontool.kinematics import RobotSpec, _pinocchio, load_robot, self_collision_depths
from motiontool.kinematics._pinocchio import BOX, SPHERE
from motiontool.kinematics.collision import geometry_poses, scan_self_collisions
from motiontool.kinematics.overlap_bound import overlap_bound

pin = import_extra("pinocchio", "kinematics")


def _random(spec_name: str, n: int, seed: int = 0) -> tuple[RobotSpec, np.ndarray]:
    spec = load_robot(spec_name)
    lo = np.array([max(j.lower, -math.pi) for j in spec.joints])
    hi = np.array([min(j.upper, math.pi) for j in spec.joints])
    return spec, lo + (hi - lo) * np.random.default_rng(seed).random((n, len(lo)))


@pytest.mark.parametrize("robot", ["nao", "ur5e", "erd:panda"])
def test_numpy_kinematics_match_pinocchio(robot: str) -> None:
    spec, q = _random(robot, 8)
    tables = _pinocchio.kinematic_tables(spec)
    assert tables.exact
    rot, centers = geometry_poses(tables, q)
    model, geoms = _pinocchio.build_model(spec)
    data, geom_data = model.createData(), pin.GeometryData(geoms)
    for n, config in enumerate(_pinocchio.configurations(spec, q)):
        pin.updateGeometryPlacements(model, data, geoms, geom_data, config)
        for g, placement in enumerate(geom_data.oMg):
            np.testing.assert_allclose(rot[n, g], placement.rotation, atol=1e-12)
            np.testing.assert_allclose(
                centers[n, g], placement.act(tables.geom_center[g]), atol=1e-12
            )


@pytest.mark.parametrize("robot", ["nao", "ur5e", "erd:ur5"])
def test_scan_finds_the_pairs_of_the_one_at_a_time_oracle(robot: str) -> None:
    spec, q = _random(robot, 60, seed=1)
    q = np.concatenate([q, q[:5]])  # repeated configurations are checked once, reported each
    contacts = scan_self_collisions(spec, q)
    oracle = {
        (i, a, b): depth
        for i, row in enumerate(q)
        for (a, b), depth in self_collision_depths(
            spec,
            dict(zip(spec.joint_names, row.tolist(), strict=True)),
        ).items()
    }
    assert {(c.config, c.body_a, c.body_b) for c in contacts} == set(oracle)
    if robot == "erd:ur5":
        return  # meshes: the oracle has no depth (0), the scan takes coal's contact depth
    for c in contacts:
        # Never deeper than coal says: the scan only corrects coal's overshoots downwards.
        assert c.depth_m <= oracle[(c.config, c.body_a, c.body_b)]


def test_a_depth_does_not_depend_on_what_was_checked_before() -> None:
    # coal's GJK started from the last answer made depths vary by up to 1 µm with the order
    # of the configurations, and so which of two near-equal overlaps a finding names.
    spec, q = _random("nao", 300, seed=3)
    forward = scan_self_collisions(spec, q)
    backward = scan_self_collisions(spec, q[::-1].copy())
    last = q.shape[0] - 1
    assert len(forward) > 20
    assert sorted(forward) == sorted(c._replace(config=last - c.config) for c in backward)


def test_tolerance_keeps_exactly_the_deep_contacts() -> None:
    spec, q = _random("nao", 80, seed=2)
    every = scan_self_collisions(spec, q)
    for tolerance in (0.002, 0.015, 0.03):
        deep = scan_self_collisions(spec, q, penetration_tolerance_m=tolerance)
        expected = [c for c in every if c.depth_m >= tolerance]
        assert [c[:3] for c in deep] == [c[:3] for c in expected]
        np.testing.assert_allclose([c.depth_m for c in deep], [c.depth_m for c in expected],
                                   atol=1e-6)  # fmt: skip


def test_overlap_bound_is_exact_for_boxes_and_spheres_and_never_below_the_depth() -> None:
    spec, q = _random("nao", 150, seed=3)
    tables = _pinocchio.kinematic_tables(spec)
    rot, centers = geometry_poses(tables, q)
    rows = np.repeat(np.arange(q.shape[0]), tables.pair_first.shape[0])
    pairs = np.tile(np.arange(tables.pair_first.shape[0]), q.shape[0])
    bound = overlap_bound(tables, rot, centers, rows, pairs)
    hit = bound > 0
    depth = -_pinocchio.pair_signed_distances(spec, q, rows[hit], pairs[hit])
    shapes = {SPHERE, BOX}
    same = np.array(
        [
            tables.geom_shape[tables.pair_first[k]] in shapes
            and tables.geom_shape[tables.pair_second[k]] in shapes
            for k in pairs[hit]
        ]
    )
    inside = depth > 1e-6
    # Boxes and spheres among themselves: separating axes give the exact depth (coal's EPA
    # agrees to its tolerance) wherever they penetrate.
    box_box = same & inside & np.array(
        [tables.geom_shape[tables.pair_first[k]] == BOX == tables.geom_shape[tables.pair_second[k]]
         for k in pairs[hit]]
    )  # fmt: skip
    assert box_box.sum() > 10
    np.testing.assert_allclose(bound[hit][box_box], depth[box_box], atol=1e-6)
    # Every penetration coal finds deeper than the bound involves a cylinder (coal's EPA
    # overshoots on flat caps; see the exact case below).
    over = depth > bound[hit] + 1e-6
    assert not (over & same).any()


def test_cylinder_in_sphere_depth_is_exact_where_coal_overshoots() -> None:
    # A random pose of test_scan (row 43 of seed 0) put the 1 cm sphere of l_pelvis inside the
    # 3 cm cylinder of l_hand, 7.6 mm from its cap: exact depth 12.44 mm, coal's EPA 29.0 mm.
    spec, q = _random("nao", 150, seed=0)
    tables = _pinocchio.kinematic_tables(spec)
    model, geoms = _pinocchio.build_model(spec)
    data, geom_data = model.createData(), pin.GeometryData(geoms)
    config = _pinocchio.configurations(spec, q[43:44])[0]
    pin.updateGeometryPlacements(model, data, geoms, geom_data, config)
    hand, pelvis = geoms.getGeometryId("l_hand_0"), geoms.getGeometryId("l_pelvis_0")
    center = geom_data.oMg[hand].actInv(geom_data.oMg[pelvis].translation)
    cylinder = geoms.geometryObjects[hand].geometry
    radial = math.hypot(center[0], center[1])
    inside = min(cylinder.radius - radial, cylinder.halfLength - abs(center[2]))
    exact = geoms.geometryObjects[pelvis].geometry.radius + inside
    (contact,) = [
        c
        for c in scan_self_collisions(spec, q[43:44])
        if (c.body_a, c.body_b) == ("l_hand", "l_pelvis")
    ]
    assert contact.depth_m == pytest.approx(exact, abs=1e-9)
    assert exact == pytest.approx(0.01244, abs=1e-5)
    k = next(i for i, p in enumerate(geoms.collisionPairs) if {p.first, p.second} == {hand, pelvis})
    assert -pin.computeDistance(geoms, geom_data, k).min_distance > exact + 0.01
    del tables


def test_fingers_count_as_their_hand_when_asked() -> None:
    spec = load_robot("nao")
    q = np.zeros((1, len(spec.joints)))
    for name, value in {"RShoulderPitch": 1.4, "RShoulderRoll": 0.3, "RElbowRoll": 1.5}.items():
        q[0, spec.joint_names.index(name)] = value
    bodies = {(c.body_a, c.body_b) for c in scan_self_collisions(spec, q)}
    assert ("r_phalanx7", "torso") in bodies
    grouped = scan_self_collisions(spec, q, fingers_in_hand=True)
    assert {(c.body_a, c.body_b) for c in grouped} == {("r_forearm", "torso"), ("r_hand", "torso")}
    hand = next(c for c in grouped if c.body_a == "r_hand")
    assert hand.depth_m == max(c.depth_m for c in scan_self_collisions(spec, q)
                               if c.body_b == "torso" and c.body_a.startswith(("r_hand", "r_phalanx")))  # fmt: skip


def test_scan_rejects_bad_shapes_and_values() -> None:
    spec = load_robot("ur5e")
    with pytest.raises(MotionToolError, match=r"shape \(N, 6\)"):
        scan_self_collisions(spec, np.zeros((2, 5)))
    with pytest.raises(MotionToolError, match="non-finite"):
        scan_self_collisions(spec, np.full((1, 6), np.nan))
    assert scan_self_collisions(spec, np.zeros((0, 6))) == []
    assert scan_self_collisions(spec, np.zeros((3, 6))) == []


def test_configurations_are_scanned_in_blocks(monkeypatch: pytest.MonkeyPatch) -> None:
    from motiontool.kinematics import collision

    spec, q = _random("nao", 50, seed=4)
    whole = scan_self_collisions(spec, q, penetration_tolerance_m=0.005)
    monkeypatch.setattr(collision, "_BLOCK", 7)
    blocks = scan_self_collisions(spec, q, penetration_tolerance_m=0.005)
    assert [c[:3] for c in blocks] == [c[:3] for c in whole] and whole
    np.testing.assert_allclose([c.depth_m for c in blocks], [c.depth_m for c in whole], atol=1e-6)


@settings(max_examples=100, deadline=None)
@given(st.lists(st.integers(-5, 50), max_size=40))
def test_distinct_values_are_np_uniques(values: list[int]) -> None:
    from motiontool.motionfmt.arrays import sorted_distinct

    a = np.array(values, dtype=np.int64)
    got = sorted_distinct(a)
    assert got.dtype == a.dtype and got.tolist() == np.unique(a).tolist()
