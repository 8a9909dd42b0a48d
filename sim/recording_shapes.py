"""How a body's collision primitives are drawn in a Rerun recording (static children of the
body's entity, in the body frame): boxes, capsules, cylinders, spheres and ellipsoids, and a
plane as a thin box."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import rerun

    from motiontool.sim.trace import BodyShapes, Shape

__all__ = ["PLANE_HALF_SIZE_M", "PLANE_THICKNESS_M", "log_shapes"]

PLANE_HALF_SIZE_M = 2.0
"""Half the side of an infinite plane as drawn (a 4 m x 4 m floor), m."""

PLANE_THICKNESS_M = 1e-4
"""Half the thickness of a plane as drawn (a thin box just below its surface), m."""


def log_shapes(
    rec: rerun.RecordingStream, root: str, body: BodyShapes, color: tuple[int, int, int]
) -> None:
    """Log ``body``'s primitives under ``root``, in the body frame, one entity per kind."""
    by_kind: dict[str, list[Shape]] = {}
    for shape in body.shapes:
        by_kind.setdefault(shape.kind, []).append(shape)
    for kind, group in by_kind.items():
        drawn = _primitives(kind, group, color)
        if drawn is not None:
            rec.log(f"{root}/{drawn[0]}", drawn[1], static=True)


def _primitives(
    kind: str, group: Sequence[Shape], color: tuple[int, int, int]
) -> tuple[str, rerun.AsComponents] | None:
    """(entity name, archetype) of the primitives ``group`` of one ``kind``, or None for a kind
    that is not drawn."""
    import numpy as np
    import rerun as rr

    pos = np.array([s.pos for s in group], dtype=np.float64)
    quat = np.array([s.quat for s in group], dtype=np.float64)
    xyzw = quat[:, [1, 2, 3, 0]]
    size = np.array([s.size for s in group], dtype=np.float64)
    colors = [color] * len(group)
    if kind == "box":
        return "boxes", rr.Boxes3D(half_sizes=size, centers=pos, quaternions=xyzw, colors=colors)
    if kind == "capsule":  # Rerun's starts at its origin along +z; MuJoCo's is centred
        start = [_rotate(q, (0.0, 0.0, s[1])) for q, s in zip(quat, size, strict=True)]
        return "capsules", rr.Capsules3D(
            lengths=2 * size[:, 1],
            radii=size[:, 0],
            translations=pos - np.array(start),
            quaternions=xyzw,
            colors=colors,
        )
    if kind == "cylinder":
        return "cylinders", rr.Cylinders3D(
            lengths=2 * size[:, 1], radii=size[:, 0], centers=pos, quaternions=xyzw, colors=colors
        )
    if kind in ("sphere", "ellipsoid"):
        half = np.repeat(size[:, :1], 3, axis=1) if kind == "sphere" else size
        return f"{kind}s", rr.Ellipsoids3D(
            half_sizes=half, centers=pos, quaternions=xyzw, colors=colors, fill_mode="solid"
        )
    if kind == "plane":
        half = np.where(size[:, :2] > 0, size[:, :2], PLANE_HALF_SIZE_M)  # 0: infinite
        return "planes", rr.Boxes3D(
            half_sizes=np.column_stack([half, np.full(len(group), PLANE_THICKNESS_M)]),
            centers=pos - [0.0, 0.0, PLANE_THICKNESS_M],
            quaternions=xyzw,
            colors=colors,
            fill_mode="solid",
        )
    return None


def _rotate(quat: Iterable[float], v: tuple[float, float, float]) -> tuple[float, float, float]:
    """Rotate ``v`` by the unit quaternion ``quat`` (w, x, y, z)."""
    w, x, y, z = (float(c) for c in quat)
    vx, vy, vz = v
    # v + 2 w (q x v) + 2 q x (q x v)
    cx, cy, cz = y * vz - z * vy, z * vx - x * vz, x * vy - y * vx
    ddx, ddy, ddz = y * cz - z * cy, z * cx - x * cz, x * cy - y * cx
    return (vx + 2 * (w * cx + ddx), vy + 2 * (w * cy + ddy), vz + 2 * (w * cz + ddz))
