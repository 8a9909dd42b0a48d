"""What a Webots world (``.wbt``) says about a run: :func:`read_world` reads the physics
settings, the robot that plays the motion and what it stands on. Pure Python (the syntax is
:mod:`motiontool.sim.wbt`); applying it to a MuJoCo run is :mod:`motiontool.sim.world_run`.

Read:

- ``WorldInfo``: ``basicTimeStep`` (ms), ``gravity`` (m/s², a number since R2021a; an older
  world's vector), ``ERP``, ``CFM``, ``coordinateSystem`` (``ENU``, or ``NUE`` as in R2021
  worlds: y up) and ``contactProperties`` (``ContactProperties { material1 material2
  coulombFriction bounce bounceVelocity softCFM softERP }``); a field not written has Webots'
  default.
- The robots: ``Robot`` nodes and instances of a PROTO whose body is a ``Robot`` (a local PROTO
  file), or of the Webots robot PROTOs motiontool knows (:data:`ROBOT_PROTOS`): their ``name``,
  ``DEF``, ``translation``, ``rotation``, ``selfCollision`` and the feet's contact material.
- What a robot can stand on (:mod:`motiontool.sim.world_ground`): ``Floor``, static boxes and
  planes, solids of local PROTOs (the wrestling ring). A PROTO is local when an
  ``EXTERNPROTO`` names it by a relative path, or it is in a ``protos/`` folder beside the world
  or beside the world's folder, as Webots finds it.

Never fetched: ``EXTERNPROTO`` URLs. Every node that is not read is in :attr:`World.skipped`,
one line per reason, so the report can say what the run did not simulate.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

from motiontool.errors import MotionSyntaxError
from motiontool.motionfmt.fileio import read_file
from motiontool.sim.wbt import IsRef, Node, Proto, Value, WbtFile, describe, parse_wbt
from motiontool.sim.world_ground import Support, read_supports

__all__ = [
    "ROBOT_PROTOS",
    "ContactProps",
    "RobotNode",
    "Support",
    "World",
    "read_world",
]

Vec3 = tuple[float, float, float]


@dataclass(frozen=True)
class ContactProps:
    """A ``ContactProperties`` node (Webots' defaults where a field is not written).

    Attributes:
        material1, material2: the two contact materials it applies to (either order).
        coulomb_friction: Coulomb friction coefficient (the first of ``coulombFriction``).
        bounce: coefficient of restitution, 0..1.
        bounce_velocity: slowest impact that bounces, m/s.
        soft_cfm, soft_erp: ODE's contact softness.
        line: where it is written (0: Webots' default, not written).
    """

    material1: str = "default"
    material2: str = "default"
    coulomb_friction: float = 1.0
    bounce: float = 0.5
    bounce_velocity: float = 0.01
    soft_cfm: float = 0.001
    soft_erp: float = 0.2
    line: int = 0

    def matches(self, a: str, b: str) -> bool:
        """Whether it applies to a contact between materials ``a`` and ``b``."""
        return {self.material1, self.material2} == {a, b}


@dataclass(frozen=True)
class RobotProto:
    """What motiontool knows of a Webots robot PROTO whose file is not at hand."""

    robots: tuple[str, ...]  # the motiontool robots it is
    defaults: dict[str, Value]


ROBOT_PROTOS: dict[str, RobotProto] = {
    "Nao": RobotProto(
        ("nao", "nao-v5"),
        {
            "name": "NAO",
            "selfCollision": False,
            "footContactMaterial": "NAO foot material",
        },
    ),
}
"""Webots robot PROTOs by node type (their fields that matter here, R2023b's defaults); a local
PROTO file of the same name wins."""

UP_AXIS = {"ENU": 2, "NUE": 1}
"""The up axis of each coordinate system read (``EUN`` is not)."""


@dataclass(frozen=True)
class RobotNode:
    """The robot node that plays the motion.

    Attributes:
        type: its node type (``Nao``; ``Robot``).
        name: its ``name`` field.
        def_name: its ``DEF`` name, or None.
        translation: where the world puts it, m (z up), or None: the PROTO's default.
        rotation: its rotation (axis x, y, z, angle rad; z up), or None: the default.
        self_collision: ``selfCollision``.
        foot_material: the contact material of its feet (``footContactMaterial``; a plain
            ``Robot``: its ``contactMaterial``).
        robots: the motiontool robots it is (empty: unknown).
        line: where the node is.
    """

    type: str
    name: str
    def_name: str | None
    translation: Vec3 | None
    rotation: tuple[float, float, float, float] | None
    self_collision: bool
    foot_material: str
    robots: tuple[str, ...]
    line: int

    @property
    def label(self) -> str:
        """``'participant' (DEF WRESTLER_RED, Nao)``."""
        parts = ([f"DEF {self.def_name}"] if self.def_name else []) + [self.type]
        return f"'{self.name}' ({', '.join(parts)})"


@dataclass(frozen=True)
class World:
    """What a world file says about a run (see the module docstring).

    Attributes:
        path: the world file, as named.
        version: its header's version (``R2023b``).
        coordinate_system: ``ENU`` or ``NUE`` (positions here are turned to z up).
        basic_time_step_ms: ``basicTimeStep``, ms.
        gravity: gravity, m/s² (z up).
        erp, cfm: ODE's global ``ERP`` and ``CFM``.
        written: the ``WorldInfo`` fields the file writes (the others are Webots' defaults).
        contact_properties: ``contactProperties``, in file order.
        robot: the robot that plays the motion.
        supports: what it can stand on.
        skipped: one line per kind of node not read, naming the nodes.
        files: the files read: the world, then each local PROTO file.
    """

    path: str
    version: str
    coordinate_system: str
    basic_time_step_ms: float
    gravity: Vec3
    erp: float
    cfm: float
    written: frozenset[str]
    contact_properties: tuple[ContactProps, ...]
    robot: RobotNode
    supports: tuple[Support, ...]
    skipped: tuple[str, ...] = ()
    files: tuple[Path, ...] = ()

    def contact(self, material: str) -> ContactProps:
        """The contact properties between the robot's feet and ``material``: the first
        ``ContactProperties`` whose two materials are those two, else Webots' defaults."""
        foot = self.robot.foot_material
        for props in self.contact_properties:
            if props.matches(foot, material):
                return props
        return ContactProps()


def read_world(path: str | Path, robot_node: str | None = None, robot: str = "") -> World:
    """Read the world file ``path`` for a run of robot ``robot`` (a motiontool robot name).

    Args:
        robot_node: the ``name`` or ``DEF`` of the robot node that plays the motion; None: the
            world's one robot of kind ``robot``.
        robot: the motiontool robot that plays (``nao``): the robot node must be one.

    Raises:
        MotionSyntaxError: the file is not a world, a syntax error, a value of the wrong kind,
            no robot node, none named ``robot_node``, several and none chosen, or one that is
            not ``robot`` (``path:line:col: message``). MotionToolError: it cannot be read.
    """
    name = str(path)
    text = _text(path)
    wbt = parse_wbt(text, name)
    reader = _Reader(Path(path), wbt)
    return reader.world(robot_node, robot)


def _text(path: str | Path) -> str:
    data = read_file(path)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise MotionSyntaxError("not UTF-8 text", str(path), line, 1) from None


class _Reader:
    """The meaning of one parsed world file."""

    def __init__(self, path: Path, wbt: WbtFile) -> None:
        self.path, self.wbt = path, wbt
        self.name = wbt.path
        self.protos: dict[str, Proto | None] = {}
        self.urls: dict[str, str] = {}
        for url, _line, _col in wbt.externprotos:
            stem = url.rsplit("/", 1)[-1].removesuffix(".proto")
            self.urls[stem] = url
        self.up = 2
        self.skipped: dict[str, list[str]] = {}
        self.read: list[Path] = []  # the local PROTO files read

    def error(self, node: Node | None, message: str) -> MotionSyntaxError:
        line, col = (node.line, node.column) if node is not None else (1, 1)
        return MotionSyntaxError(message, self.name, line, col)

    def world(self, robot_node: str | None, robot: str) -> World:
        info = next((n for n in self.wbt.nodes if n.type == "WorldInfo"), None)
        fields = info.fields if info is not None else {}
        system = self.string(info, fields, "coordinateSystem", "ENU" if self.modern() else "NUE")
        if system not in UP_AXIS:
            raise self.error(
                info, f"coordinateSystem {system!r} is not read: only ENU (z up) and NUE (y up)"
            )
        self.up = UP_AXIS[system]
        step = self.number(info, fields, "basicTimeStep", 32.0)
        if not step > 0:
            raise self.error(info, f"basicTimeStep must be > 0 ms, got {step:g}")
        robots, supports = [], []
        for node in self.wbt.nodes:
            if node.type == "WorldInfo":
                continue
            found = self.robot(node)
            if found is not None:
                robots.append(found)
                continue
            supports.extend(read_supports(self, node))
        chosen = self.choose(robots, robot_node, robot)
        for other in robots:
            if other is not chosen:
                self.skip(
                    "other robots (only the robot that plays the motion is simulated)",
                    f"{other.label} line {other.line}",
                )
        return World(
            path=self.name,
            version=self.wbt.version,
            coordinate_system=system,
            basic_time_step_ms=step,
            gravity=self.gravity(info, fields),
            erp=self.number(info, fields, "ERP", 0.2),
            cfm=self.number(info, fields, "CFM", 1e-5),
            written=frozenset(fields),
            contact_properties=tuple(self.contacts(info, fields)),
            robot=chosen,
            supports=tuple(supports),
            skipped=tuple(f"{why}: {', '.join(names)}" for why, names in self.skipped.items()),
            files=(self.path, *self.read),
        )

    def modern(self) -> bool:
        """Whether the file is R2022a or later (ENU by default)."""
        version = self.wbt.version
        return not (version[:1] == "R" and version[1:5].isdigit() and int(version[1:5]) < 2022)

    # -- fields

    def number(
        self, node: Node | None, fields: dict[str, Value], key: str, default: float
    ) -> float:
        value = fields.get(key)
        if value is None:
            return default
        if not (isinstance(value, tuple) and len(value) == 1):
            raise self.error(node, f"{_type(node)}.{key} must be one number, got {describe(value)}")
        return value[0]

    def string(self, node: Node | None, fields: dict[str, Value], key: str, default: str) -> str:
        value = fields.get(key, default)
        if not isinstance(value, str):
            raise self.error(node, f"{_type(node)}.{key} must be a string, got {describe(value)}")
        return value

    def vector(
        self, node: Node, fields: dict[str, Value], key: str, size: int
    ) -> tuple[float, ...]:
        value = fields[key]
        if not (isinstance(value, tuple) and len(value) == size):
            raise self.error(
                node, f"{node.type}.{key} must be {size} numbers, got {describe(value)}"
            )
        return value

    def enu(self, v: Sequence[float]) -> Vec3:
        """A vector of the file's coordinate system with z up."""
        if self.up == 1:  # NUE: x north, y up, z east
            return (v[2], v[0], v[1])
        return (v[0], v[1], v[2])

    def gravity(self, node: Node | None, fields: dict[str, Value]) -> Vec3:
        value = fields.get("gravity")
        if value is None:
            return (0.0, 0.0, -9.81)
        if isinstance(value, tuple) and len(value) == 1:
            return (0.0, 0.0, -value[0])
        if isinstance(value, tuple) and len(value) == 3:
            return self.enu(value)
        raise self.error(node, f"WorldInfo.gravity must be a number, got {describe(value)}")

    def contacts(self, info: Node | None, fields: dict[str, Value]) -> Iterator[ContactProps]:
        listed = fields.get("contactProperties", [])
        for item in listed if isinstance(listed, list) else [listed]:
            if not isinstance(item, Node) or item.type != "ContactProperties":
                raise self.error(
                    info,
                    f"WorldInfo.contactProperties holds {describe(item)}, not ContactProperties",
                )
            f = item.fields
            friction = f.get("coulombFriction", [(1.0,)])
            first = friction[0] if isinstance(friction, list) and friction else friction
            if not (isinstance(first, tuple) and len(first) == 1):
                raise self.error(item, f"coulombFriction must be numbers, got {describe(friction)}")
            yield ContactProps(
                material1=self.string(item, f, "material1", "default"),
                material2=self.string(item, f, "material2", "default"),
                coulomb_friction=first[0],
                bounce=self.number(item, f, "bounce", 0.5),
                bounce_velocity=self.number(item, f, "bounceVelocity", 0.01),
                soft_cfm=self.number(item, f, "softCFM", 0.001),
                soft_erp=self.number(item, f, "softERP", 0.2),
                line=item.line,
            )

    # -- PROTOs

    def proto(self, node: Node) -> Proto | None:
        """The local PROTO of ``node``'s type, or None (a URL, a built-in, not found)."""
        kind = node.type
        if kind in self.protos:
            return self.protos[kind]
        found = None
        for candidate in self.proto_files(kind):
            if candidate.is_file():
                self.read.append(candidate)
                text = _text(candidate)
                parsed = parse_wbt(text, str(candidate))
                found = next((p for p in parsed.protos if p.name == kind), None)
                if found is None:
                    raise self.error(node, f"{candidate} does not define PROTO {kind}")
                break
        self.protos[kind] = found
        return found

    def proto_files(self, kind: str) -> Iterator[Path]:
        url = self.urls.get(kind)
        if url is not None:
            if "://" in url:
                return  # never fetched
            yield (self.path.parent / url).resolve()
            return
        folder = self.path.parent
        yield folder / "protos" / f"{kind}.proto"
        yield folder.parent / "protos" / f"{kind}.proto"

    def instance(self, node: Node) -> tuple[Node, dict[str, Value]] | None:
        """``node`` as the node its PROTO makes (IS fields replaced), and the PROTO's fields
        with the instance's values; None when the PROTO's body is not read."""
        proto = self.proto(node)
        if proto is None or proto.body is None:
            return None
        values = {**proto.defaults, **node.fields}
        return _substitute(proto.body, values), values

    def skip(self, why: str, what: str) -> None:
        self.skipped.setdefault(why, []).append(what)

    # -- robots

    def robot(self, node: Node) -> RobotNode | None:
        """``node`` as a robot node, or None if it is not one."""
        proto = self.proto(node) if node.type != "Robot" else None
        known = ROBOT_PROTOS.get(node.type)
        if node.type == "Robot":
            values = dict(node.fields)
        elif proto is not None and proto.base_type == "Robot":
            values = {**proto.defaults, **node.fields}
        elif known is not None:
            values = {**known.defaults, **node.fields}
        else:
            return None
        foot_key = "footContactMaterial" if "footContactMaterial" in values else "contactMaterial"
        translation = rotation = None
        if "translation" in node.fields:
            translation = self.enu(self.vector(node, node.fields, "translation", 3))
        if "rotation" in node.fields:
            r = self.vector(node, node.fields, "rotation", 4)
            rotation = (*self.enu(r[:3]), r[3])
        collide = values.get("selfCollision", False)
        if not isinstance(collide, bool):
            raise self.error(node, f"{node.type}.selfCollision must be TRUE or FALSE")
        return RobotNode(
            type=node.type,
            name=self.string(node, values, "name", node.type),
            def_name=node.def_name,
            translation=translation,
            rotation=rotation,
            self_collision=collide,
            foot_material=self.string(node, values, foot_key, "default"),
            robots=known.robots if known is not None else (),
            line=node.line,
        )

    def choose(self, robots: list[RobotNode], wanted: str | None, robot: str) -> RobotNode:
        names = ", ".join(r.label for r in robots)
        if wanted is not None:
            chosen = [r for r in robots if wanted in (r.name, r.def_name)]
            if not chosen:
                raise self.error(
                    None,
                    f"no robot node named {wanted!r} (name or DEF) in this world; its robots: "
                    + (names or "none"),
                )
            node = chosen[0]
            if robot and robot not in node.robots:
                what = f"a {node.type}" if node.robots else f"a {node.type}, not a known robot"
                raise MotionSyntaxError(
                    f"robot node {node.label} is {what}: it cannot play a motion for {robot}",
                    self.name,
                    node.line,
                    1,
                )
            return node
        fits = [r for r in robots if not robot or robot in r.robots]
        if not fits:
            raise self.error(
                None,
                f"no robot node for {robot or 'the motion'} in this world"
                + (f" (its robots: {names})" if robots else " (no Robot node, no robot PROTO)"),
            )
        if len(fits) > 1:
            raise self.error(
                None,
                f"{len(fits)} robot nodes could play it: "
                + ", ".join(r.label for r in fits)
                + "; name the one that plays (its name or DEF)",
            )
        return fits[0]


def _substitute(node: Node, values: dict[str, Value]) -> Node:
    """A copy of a PROTO body's ``node`` with every ``IS field`` replaced by ``values``."""

    def sub(value: Value) -> Value:
        if isinstance(value, IsRef):
            return values.get(value.name)
        if isinstance(value, Node):
            return _substitute(value, values)
        if isinstance(value, list):
            return [sub(v) for v in value]
        return value

    return Node(
        node.type,
        {k: sub(v) for k, v in node.fields.items()},
        node.line,
        node.column,
        node.def_name,
    )


def _type(node: Node | None) -> str:
    return node.type if node is not None else "WorldInfo"
