"""Static balance of a pose: the centre of mass over the support polygon of the feet."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, NamedTuple

from motiontool.errors import MotionToolError
from motiontool.kinematics._pinocchio.api import pin_module
from motiontool.kinematics._pinocchio.configuration import configuration
from motiontool.kinematics._pinocchio.hull import convex_hull, signed_distance
from motiontool.kinematics._pinocchio.model import built
from motiontool.kinematics.robots import RobotSpec
from motiontool.motionfmt.units import MM_PER_M

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["DEFAULT_CONTACT_TOLERANCE_M", "Balance", "com_and_support", "sole_heights"]

#: A foot whose lowest point is within this distance (m) of the floor supports the robot.
DEFAULT_CONTACT_TOLERANCE_M = 0.005


class Balance(NamedTuple):
    """Static balance of a pose.

    Attributes:
        com_xy: centre of mass projected on the floor, m, shape (2,) float64 (root frame).
        support_polygon: convex hull of the floor contact points of the supporting feet,
            counter-clockwise, m, shape (K, 2) float64 (K = 1 or 2 for a point or an edge).
        margin_mm: signed distance from ``com_xy`` to the polygon's boundary, mm: positive
            inside (statically stable), negative outside.
    """

    com_xy: npt.NDArray[np.float64]
    support_polygon: npt.NDArray[np.float64]
    margin_mm: float


_BOX_SIGNS = [[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]


def _foot_corners(
    spec: RobotSpec, q_by_joint: Mapping[str, float]
) -> tuple[npt.NDArray[np.float64], dict[str, npt.NDArray[np.float64]]]:
    """(com (3,), {foot geometry name: its 8 box corners, shape (8, 3)}) in metres."""
    import numpy as np

    pin = pin_module()
    if not spec.feet:
        raise MotionToolError(
            f"robot {spec.name} has no feet: the balance check needs a humanoid model with "
            "sole geometries (nao, nao-v5)"
        )
    loaded = built(spec)
    model, geoms = loaded.model, loaded.geoms
    data, geom_data = loaded.buffers()
    q = configuration(model, spec, q_by_joint)
    pin.forwardKinematics(model, data, q)
    pin.updateGeometryPlacements(model, data, geoms, geom_data)
    corners = {}
    for foot in spec.feet:
        gid = geoms.getGeometryId(foot)
        if gid >= len(geoms.geometryObjects):
            raise MotionToolError(f"robot {spec.name}: no collision geometry named '{foot}'")
        half = np.asarray(geoms.geometryObjects[gid].geometry.halfSide, dtype=np.float64)
        placement = geom_data.oMg[gid]
        corners[foot] = (
            np.asarray(_BOX_SIGNS, dtype=np.float64) * half
        ) @ placement.rotation.T + placement.translation
    com = pin.centerOfMass(model, data, q, False)
    return np.asarray(com, dtype=np.float64), corners


def sole_heights(spec: RobotSpec, q_by_joint: Mapping[str, float]) -> dict[str, float]:
    """Lowest point (m, world z, root at the origin) of each foot's sole geometry.

    For the Nao at the zero pose both are -0.3339: the torso origin is 0.3339 m above the floor.
    """
    _com, corners = _foot_corners(spec, q_by_joint)
    return {foot: float(points[:, 2].min()) for foot, points in corners.items()}


def com_and_support(
    spec: RobotSpec,
    q_by_joint: Mapping[str, float],
    *,
    contact_tolerance_m: float = DEFAULT_CONTACT_TOLERANCE_M,
) -> Balance:
    """Centre of mass, support polygon and stability margin of a pose (quasi-static).

    The floor is the lowest sole point at that pose. A foot whose lowest point is within
    ``contact_tolerance_m`` (m) of the floor supports the robot, through its sole corners that
    are within that distance too (a flat foot gives its 4 bottom corners, a tilted one an edge
    or a corner). The root stays upright at the origin (see the module docstring).

    Raises:
        MotionToolError: the robot has no feet (``spec.feet`` empty), or an unknown joint.
    """
    import numpy as np

    com, corners = _foot_corners(spec, q_by_joint)
    floor = min(float(points[:, 2].min()) for points in corners.values())
    contact: list[tuple[float, float]] = []
    for points in corners.values():
        if points[:, 2].min() <= floor + contact_tolerance_m:
            touching = points[points[:, 2] <= floor + contact_tolerance_m]
            contact.extend((float(x), float(y)) for x, y in touching[:, :2])
    hull = convex_hull(contact)
    com_xy = np.array(com[:2], dtype=np.float64)
    margin_m = signed_distance((float(com_xy[0]), float(com_xy[1])), hull)
    return Balance(com_xy, np.array(hull, dtype=np.float64).reshape(-1, 2), margin_m * MM_PER_M)
