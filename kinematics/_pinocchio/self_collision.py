"""Self-collision at a pose: the pairs of bodies in contact and how deep, and the exact signed
distances of chosen pairs at many poses (the narrow phase of
:func:`motiontool.kinematics.collision.scan_self_collisions`)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

from motiontool.kinematics._pinocchio.api import pin_module
from motiontool.kinematics._pinocchio.configuration import configuration, configurations
from motiontool.kinematics._pinocchio.model import built
from motiontool.kinematics._pinocchio.tables import kinematic_tables
from motiontool.kinematics.robots import RobotSpec

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = [
    "geometry_centers",
    "pair_signed_distances",
    "self_collision_depths",
    "self_collisions",
]


def self_collision_depths(
    spec: RobotSpec, q_by_joint: Mapping[str, float]
) -> dict[tuple[str, str], float]:
    """Penetration depth (m, >= 0) of every pair of bodies in collision at the given pose.

    Keys are (body_a, body_b) with body_a < body_b, named after the bodies (MJCF) or links
    (URDF) holding the geometries; the depth is the deepest over their geometry pairs.
    Adjacent bodies and geometry pairs already touching at the zero pose are never reported
    (see :func:`build_model`).
    """
    pin = pin_module()
    loaded = built(spec)
    model, geoms = loaded.model, loaded.geoms
    data, geom_data = loaded.buffers()
    q = configuration(model, spec, q_by_joint)
    if not pin.computeCollisions(model, data, geoms, geom_data, q, False):
        return {}
    objects = geoms.geometryObjects
    depths: dict[tuple[str, str], float] = {}
    for index, result in enumerate(geom_data.collisionResults):
        if not result.isCollision():
            continue
        pair = geoms.collisionPairs[index]
        a = model.frames[objects[pair.first].parentFrame].name
        b = model.frames[objects[pair.second].parentFrame].name
        key = (min(a, b), max(a, b))
        distance = pin.computeDistance(geoms, geom_data, index).min_distance
        depths[key] = max(depths.get(key, 0.0), max(0.0, -float(distance)))
    return dict(sorted(depths.items()))


def self_collisions(
    spec: RobotSpec,
    q_by_joint: Mapping[str, float],
    *,
    penetration_tolerance_m: float = 0.0,
) -> list[tuple[str, str]]:
    """Pairs of bodies whose collision geometries intersect at the given pose.

    Args:
        spec: the robot.
        q_by_joint: motor positions, rad or m (motors left out stay at 0).
        penetration_tolerance_m: report only pairs that penetrate at least this deep (m); 0
            reports every intersection. The Webots bounding primitives are coarse (an arm
            raised beside the head already overlaps it by a few mm), so a lint may want some.

    Returns sorted (body_a, body_b) pairs with body_a < body_b. Adjacent bodies and geometry
    pairs already touching at the zero pose are never reported (see :func:`build_model`).
    """
    return [
        pair
        for pair, depth in self_collision_depths(spec, q_by_joint).items()
        if depth >= penetration_tolerance_m
    ]


def geometry_centers(spec: RobotSpec, q_motors: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """World centres (N, G, 3) float64, m, of the geometries' bounding spheres, computed by
    Pinocchio one configuration at a time (for models :class:`KinematicTables` cannot move)."""
    import numpy as np

    pin = pin_module()
    loaded = built(spec)
    model, geoms = loaded.model, loaded.geoms
    data, geom_data = loaded.buffers()
    tables = kinematic_tables(spec)
    out = np.empty((q_motors.shape[0], len(geoms.geometryObjects), 3))
    for n, q in enumerate(configurations(spec, q_motors)):
        pin.updateGeometryPlacements(model, data, geoms, geom_data, q)
        for g, placement in enumerate(geom_data.oMg):
            out[n, g] = placement.act(tables.geom_center[g])
    return out


def pair_signed_distances(
    spec: RobotSpec,
    q_motors: npt.NDArray[np.float64],
    rows: npt.NDArray[np.int64],
    pairs: npt.NDArray[np.int64],
) -> npt.NDArray[np.float64]:
    """Signed distance (m; negative = penetration depth) of collision pair ``pairs[c]`` at
    configuration ``q_motors[rows[c]]``, shape (C,) float64.

    ``q_motors`` is (N, M) float64 in ``spec.joints`` order; ``rows`` and ``pairs`` are (C,)
    int arrays, ``pairs`` indexing :attr:`KinematicTables.pair_first`. Primitive pairs get
    the exact signed distance (GJK/EPA). Where coal gives no signed distance (intersecting
    meshes read as 0), the depth of the contact its collision test reports is used.
    """
    import numpy as np

    pin = pin_module()
    loaded = built(spec)
    model, geoms = loaded.model, loaded.geoms
    data, geom_data = loaded.buffers()
    out = np.empty(rows.shape[0], dtype=np.float64)
    if rows.shape[0] == 0:
        return out
    order = np.argsort(rows, kind="stable")
    q_all = configurations(spec, q_motors[np.unique(rows)])
    row_pos = {int(r): i for i, r in enumerate(np.unique(rows))}
    current = -1
    for c in order:
        row = int(rows[c])
        if row != current:
            pin.updateGeometryPlacements(model, data, geoms, geom_data, q_all[row_pos[row]])
            current = row
        k = int(pairs[c])
        distance = float(pin.computeDistance(geoms, geom_data, k).min_distance)
        if distance == 0.0 and pin.computeCollision(geoms, geom_data, k):  # meshes
            result = geom_data.collisionResults[k]
            depths = [
                float(result.getContact(i).penetration_depth) for i in range(result.numContacts())
            ]
            distance = min(distance, *(-abs(d) for d in depths)) if depths else distance
        out[c] = distance
    return out
