"""The collision shapes of coal geometries, as :class:`~.tables.KinematicTables` holds them."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from motiontool.kinematics._pinocchio.api import CollisionGeometry

__all__ = ["BOX", "CAPSULE", "CYLINDER", "OTHER", "SPHERE", "bounding_sphere", "shape"]

#: Geometry shapes in :class:`~.tables.KinematicTables`.
OTHER, SPHERE, BOX, CAPSULE, CYLINDER = 0, 1, 2, 3, 4


def shape(geometry: CollisionGeometry) -> tuple[int, tuple[float, float, float]]:
    """(shape code, sizes in m) of a coal geometry, as :class:`KinematicTables` holds them."""
    kind = type(geometry).__name__
    if kind == "Sphere":
        return SPHERE, (float(geometry.radius), 0.0, 0.0)
    if kind == "Box":
        h = geometry.halfSide
        return BOX, (float(h[0]), float(h[1]), float(h[2]))
    if kind in ("Capsule", "Cylinder"):
        code = CAPSULE if kind == "Capsule" else CYLINDER
        return code, (float(geometry.radius), float(geometry.halfLength), 0.0)
    return OTHER, (0.0, 0.0, 0.0)


def bounding_sphere(geometry: CollisionGeometry) -> tuple[tuple[float, float, float], float]:
    """(centre in the geometry frame, radius), m, of a sphere enclosing a coal geometry."""
    kind = type(geometry).__name__
    origin = (0.0, 0.0, 0.0)
    if kind == "Sphere":
        return origin, float(geometry.radius)
    if kind == "Capsule":
        return origin, float(geometry.radius) + float(geometry.halfLength)
    if kind == "Cylinder":
        return origin, math.hypot(float(geometry.radius), float(geometry.halfLength))
    if kind == "Box":
        return origin, math.sqrt(sum(float(h) ** 2 for h in geometry.halfSide))
    geometry.computeLocalAABB()
    c = geometry.aabb_center
    return (float(c[0]), float(c[1]), float(c[2])), float(geometry.aabb_radius)
