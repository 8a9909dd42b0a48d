"""What a robot can stand on in a Webots world (:class:`Support`): ``Floor`` (a plane), and
static solids (no ``physics``) whose ``boundingObject`` is a ``Box`` or a ``Plane`` (in a
``Pose``, ``Transform``, ``Shape`` or ``Group``): ``Solid`` nodes, and instances of local PROTOs
whose body is one (the wrestling ring). Part of reading a world (:mod:`motiontool.sim.world`);
every other node is noted with why it is not simulated."""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.sim.wbt import IsRef, Node, Value, describe

if TYPE_CHECKING:
    from motiontool.sim.world import _Reader

__all__ = ["FLOOR_DEFAULTS", "NOT_PHYSICAL", "Support", "read_supports"]

Vec3 = tuple[float, float, float]

FLOOR_DEFAULTS: dict[str, Value] = {
    "translation": (0.0, 0.0, 0.0),
    "rotation": (0.0, 0.0, 1.0, 0.0),
    "name": "floor",
    "size": (10.0, 10.0),
    "contactMaterial": "default",
}
"""Webots' ``Floor`` PROTO (R2023b): a plane of ``size`` (m) at ``translation``."""

NOT_PHYSICAL = frozenset(
    {
        "Viewpoint",
        "Background",
        "TexturedBackground",
        "TexturedBackgroundLight",
        "DirectionalLight",
        "PointLight",
        "SpotLight",
        "Fog",
    }
)
"""Node types that change nothing in the physics: read past without a note."""


@dataclass(frozen=True)
class Support:
    """Something the robot can stand on: a plane or a static box (world frame, z up, m).

    Attributes:
        node: the node's type (``Floor``, ``WrestlingRing``, ``Solid``).
        name: the node's ``name`` (``floor``, ``wrestling ring``), else its type.
        kind: ``plane`` or ``box``.
        center: the centre (a plane: a point of it), m.
        size: the box's edges, m (a plane: its two sides, 0 for unbounded, and 0).
        yaw_rad: its turn about the vertical, rad.
        material: its contact material.
        line: where its node is.
    """

    node: str
    name: str
    kind: str
    center: Vec3
    size: Vec3
    yaw_rad: float
    material: str
    line: int

    @property
    def top_z(self) -> float:
        """Height of its top face (a plane: its height), m."""
        return self.center[2] + (self.size[2] / 2 if self.kind == "box" else 0.0)

    def top_at(self, x: float, y: float) -> float | None:
        """Height of its top face above (x, y) m, or None if (x, y) is not over it."""
        c, s = math.cos(-self.yaw_rad), math.sin(-self.yaw_rad)
        dx, dy = x - self.center[0], y - self.center[1]
        lx, ly = c * dx - s * dy, s * dx + c * dy
        for local, edge in ((lx, self.size[0]), (ly, self.size[1])):
            if edge > 0 and abs(local) > edge / 2:
                return None
        return self.top_z


def read_supports(reader: _Reader, node: Node) -> list[Support]:
    """What ``node`` offers to stand on (none for most nodes; ``reader`` notes why)."""
    where = f"{node.type} line {node.line}"
    if node.type in NOT_PHYSICAL:
        return []
    if node.type == "Floor" and reader.proto(node) is None:
        values = {**FLOOR_DEFAULTS, **node.fields}
        size = values["size"]
        if not (isinstance(size, tuple) and len(size) == 2):
            raise reader.error(node, f"Floor.size must be 2 numbers, got {describe(size)}")
        return _supports_of(
            reader, node, values, [(Node("Plane", {"size": size}, 0, 0), (0.0,) * 3)]
        )
    if node.type == "Solid":
        solid = node
        values = dict(node.fields)
    else:
        made = reader.instance(node)
        if made is None:
            url = reader.urls.get(node.type, "")
            why = (
                "not read (EXTERNPROTO URLs are never fetched)"
                if "://" in url
                else "not read (no local PROTO file, or one with template code)"
            )
            reader.skip(why, where)
            return []
        solid, values = made
        if solid.type != "Solid":
            reader.skip(f"not read (a PROTO of a {solid.type}, not a Solid)", where)
            return []
    if solid.fields.get("physics") is not None:
        reader.skip("not simulated (solids with physics: they can move)", where)
        return []
    bounding = solid.fields.get("boundingObject")
    if bounding is None:
        return []
    shapes = list(_shapes(bounding, (0.0, 0.0, 0.0)))
    if not shapes or any(s is None for s, _at in shapes):
        reader.skip("not simulated (bounding objects other than Box and Plane)", where)
        return []
    merged = {**values, **solid.fields}
    return _supports_of(reader, node, merged, [(s, at) for s, at in shapes if s is not None])


def _supports_of(
    reader: _Reader, node: Node, values: dict[str, Value], shapes: list[tuple[Node, Vec3]]
) -> list[Support]:
    """The supports of a solid (``values``: its fields) made of ``shapes`` (offsets in its
    frame, before the coordinate system is turned)."""
    t = values.get("translation", (0.0, 0.0, 0.0))
    r = values.get("rotation", (0.0, 0.0, 1.0, 0.0))
    if isinstance(t, IsRef) or isinstance(r, IsRef):
        return []
    if not (isinstance(t, tuple) and len(t) == 3 and isinstance(r, tuple) and len(r) == 4):
        raise reader.error(node, f"{node.type}: translation and rotation must be numbers")
    axis = reader.enu(r[:3])
    yaw = 0.0
    if r[3] != 0.0:
        if not math.isclose(abs(axis[2]), math.hypot(*axis), rel_tol=1e-6):
            reader.skip("not simulated (tilted solids)", f"{node.type} line {node.line}")
            return []
        yaw = r[3] if axis[2] > 0 else -r[3]
    name = values.get("name")
    label = name if isinstance(name, str) else node.type
    material = values.get("contactMaterial", "default")
    out = []
    for shape, at in shapes:
        size = shape.fields.get("size", (1.0, 1.0, 1.0) if shape.type == "Box" else (1.0, 1.0))
        if not isinstance(size, tuple) or len(size) != (3 if shape.type == "Box" else 2):
            raise reader.error(shape, f"{shape.type}.size: got {describe(size)}")
        c, s = math.cos(yaw), math.sin(yaw)
        off = reader.enu(at)
        centre = reader.enu(t)
        centre = (
            centre[0] + c * off[0] - s * off[1],
            centre[1] + s * off[0] + c * off[1],
            centre[2] + off[2],
        )
        if shape.type == "Box":
            edges = reader.enu(size)
            dims = (abs(edges[0]), abs(edges[1]), abs(edges[2]))
        else:  # a Plane lies in the file's ground plane: its size is (x, the other axis)
            dims = (size[0], size[1], 0.0)
        out.append(
            Support(
                node=node.type,
                name=label,
                kind="box" if shape.type == "Box" else "plane",
                center=centre,
                size=dims,
                yaw_rad=yaw,
                material=material if isinstance(material, str) else "default",
                line=node.line,
            )
        )
    return out


def _shapes(node: Value, at: Vec3) -> Iterator[tuple[Node | None, Vec3]]:
    """The Box and Plane nodes of a bounding object with their offsets (None: another shape)."""
    if isinstance(node, list):
        for item in node:
            yield from _shapes(item, at)
        return
    if not isinstance(node, Node):
        return
    if node.type in ("Box", "Plane"):
        yield node, at
    elif node.type == "Shape":
        yield from _shapes(node.fields.get("geometry"), at)
    elif node.type == "Group":
        yield from _shapes(node.fields.get("children", []), at)
    elif node.type in ("Pose", "Transform"):
        t = node.fields.get("translation", (0.0, 0.0, 0.0))
        r = node.fields.get("rotation", (0.0, 0.0, 1.0, 0.0))
        if not (isinstance(t, tuple) and len(t) == 3) or (isinstance(r, tuple) and r[3:] != (0.0,)):
            yield None, at
            return
        yield from _shapes(
            node.fields.get("children", []), (at[0] + t[0], at[1] + t[1], at[2] + t[2])
        )
    else:
        yield None, at
