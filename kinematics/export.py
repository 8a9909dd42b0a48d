"""A robot's model file, for MuJoCo / Pinocchio users: ``motiontool robots export``.

MJCF is the built-in robots' own format: ``nao`` and ``ur5e`` export their model file byte for
byte; ``nao-v5`` exports ``nao.xml`` with the real robot's limits written into it
(:mod:`motiontool.kinematics.mjcf_limits`, through an XML parser).

URDF is written from the Pinocchio model (:func:`urdf_bytes`), so it holds what Pinocchio read:
kinematic tree, joint limits, masses, centres of mass, inertias and collision primitives. URDF
has no capsule, so each capsule becomes its exact equivalent, a cylinder and two end spheres.
What URDF cannot hold is left out and said in the file's leading comment: the free-flying root
(load the file with a free-flyer root joint), the MuJoCo actuators, the Webots time step and the
names of the feet.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.kinematics.mjcf_limits import write_limits
from motiontool.kinematics.mjcf_limits import xml_number as _g
from motiontool.kinematics.robots import RobotSpec

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.kinematics._pinocchio.api import GeometryObject, Inertia

    Matrix = npt.NDArray[np.float64]

__all__ = ["URDF_KEPT", "NoMjcfError", "mjcf_bytes", "stored_urdf", "urdf_bytes", "urdf_cache_dir"]


def _quoteattr(value: str) -> str:
    """``value`` as a quoted XML attribute (:func:`xml.sax.saxutils.quoteattr`, imported here:
    it brings ``urllib``, 20 ms that ``validate``, which imports this module's errors, does not
    need)."""
    from xml.sax.saxutils import quoteattr as quote

    return quote(value)


class NoMjcfError(MotionToolError):
    """An MJCF file was asked of a robot that comes from a URDF file.

    Attributes:
        spec: the robot.
        how: how to export it instead, in the library's words (``as URDF (urdf_bytes)``); a
            front end words it its own way (the CLI: ``with --urdf``).
    """

    def __init__(self, spec: RobotSpec, how: str = "as URDF (urdf_bytes)") -> None:
        self.spec = spec
        super().__init__(
            f"robot {spec.name} comes from a URDF file ({spec.model_path}); export it {how}, "
            "or let MuJoCo convert it (mujoco.MjModel.from_xml_path, then "
            "mujoco.mj_saveLastXML)"
        )


def mjcf_bytes(spec: RobotSpec) -> bytes:
    """The MJCF file of ``spec``.

    Raises:
        NoMjcfError: ``spec`` comes from a URDF file.
    """
    if spec.model_format != "mjcf":
        raise NoMjcfError(spec)
    if spec.overrides_path is None:
        return spec.model_path.read_bytes()
    text = write_limits(spec.model_path, spec.joints)
    groups: dict[str, list[str]] = {}
    for leader, follower in spec.coupled_joints:
        groups.setdefault(leader, [leader]).append(follower)
    coupled = "; ".join(" = ".join(members) for members in groups.values())
    note = (  # no "--" inside an XML comment
        f"<!--\n  Robot {spec.name}: {spec.model_path.name} with the limits of "
        f"{spec.overrides_path.name} (the real robot's ranges and torques) written in.\n"
        "  Not expressible in MJCF, and checked by motiontool's validate with this robot "
        "instead: the HeadYaw-dependent HeadPitch range, and joints one motor drives: "
        f"{coupled}.\n-->\n"
    )
    head, _, rest = text.partition("\n")
    return (head + "\n" + note + rest).encode("utf-8")


def urdf_bytes(spec: RobotSpec) -> bytes:
    """A URDF file equivalent to ``spec``'s model as Pinocchio reads it (see the module doc).

    A robot that comes from a URDF file (without overrides) exports that file as it is.

    Raises:
        MotionToolError: the model has a joint URDF cannot express (neither a motor nor the
            free-flying root), or a body that does not sit at its joint's origin.
    """
    if spec.model_format == "urdf" and spec.overrides_path is None:
        return spec.model_path.read_bytes()
    return _Urdf(spec).text().encode("utf-8")


URDF_KEPT = 64
"""How many robots' URDF files :func:`stored_urdf` keeps (the least recently used go)."""


def urdf_cache_dir() -> Path:
    """Where :func:`stored_urdf` keeps them: ``$XDG_CACHE_HOME/motiontool/urdf``."""
    from motiontool.disk_cache import cache_root

    return cache_root() / "urdf"


def stored_urdf(spec: RobotSpec) -> bytes:
    """:func:`urdf_bytes` of ``spec``, kept on disk (``$XDG_CACHE_HOME/motiontool/urdf``):
    writing it builds the Pinocchio model (Pinocchio's import alone is about 100 MB), which
    ``play --bag`` then needs only the first time for a robot. The key is the model (its
    sha256, overrides included), its motors, how it is built, the code of
    ``motiontool.kinematics`` and the installed Pinocchio; a cache that cannot be read or
    written is no error, the file is written again.

    Raises:
        MotionToolError: as :func:`urdf_bytes`.
    """
    from motiontool.disk_cache import ResultCache, code_stamp

    if spec.model_format == "urdf" and spec.overrides_path is None:
        return spec.model_path.read_bytes()
    key = spec.model_key(code_stamp(["kinematics"], ["pinocchio"]))
    cache = ResultCache(urdf_cache_dir(), max_results=URDF_KEPT)
    stored = cache.load(key)
    if stored is not None and isinstance(stored.get("urdf"), str):
        return str(stored["urdf"]).encode("utf-8")
    data = urdf_bytes(spec)
    if cache.store(key, {"urdf": data.decode("utf-8")}):
        cache.prune()
    return data


class _Urdf:
    """Writes a Pinocchio model (and its collision geometry) as URDF."""

    def __init__(self, spec: RobotSpec) -> None:
        import numpy as np

        from motiontool.kinematics._pinocchio import FIXED, PRISMATIC, build_model

        self.spec = spec
        self.model, self.geoms = build_model(spec)
        self.fixed, self.prismatic = FIXED, PRISMATIC
        model = self.model
        self.frames = list(model.frames)
        self.floating = model.njoints > 1 and model.joints[1].shortname() == "JointModelFreeFlyer"
        # The body that moves with each joint: the BODY frame right after its JOINT frame.
        self.main: dict[int, int] = {}
        for fid, frame in enumerate(self.frames):
            if str(frame.type) != "BODY":
                continue
            parent = self.frames[frame.parentFrame]
            if str(parent.type) == "JOINT" and frame.parentJoint not in self.main:
                if not np.allclose(frame.placement.homogeneous, np.eye(4), atol=1e-12):
                    raise MotionToolError(
                        f"cannot write robot {spec.name} as URDF: body '{frame.name}' is not "
                        "at its joint's origin"
                    )
                self.main[frame.parentJoint] = fid
        root_joint = 1 if self.floating else 0
        universe_bodies = [
            fid
            for fid, f in enumerate(self.frames)
            if str(f.type) == "BODY"
            and f.parentJoint == root_joint
            and fid not in self.main.values()
        ]
        if root_joint not in self.main:
            self.main[root_joint] = universe_bodies.pop(0) if universe_bodies else -1
        self.root_joint = root_joint

    def link_of_joint(self, jid: int) -> str:
        fid = self.main[jid]
        return "world" if fid < 0 else self.frames[fid].name

    def placement(self, fid: int) -> Matrix:
        """Placement (4x4) of frame ``fid`` in its joint's frame (identity for 'world')."""
        import numpy as np

        return np.eye(4) if fid < 0 else np.asarray(self.frames[fid].placement.homogeneous)

    def text(self) -> str:
        links: dict[str, list[str]] = {}  # link name -> its XML lines, in order of appearance
        joints_xml = self._moving_links(links) + self._fixed_links(links)
        self._collision_links(links)
        out = self._header()
        for name, body in links.items():
            if body:
                out.append(f"  <link name={_quoteattr(name)}>")
                out.extend("    " + line for line in body)
                out.append("  </link>")
            else:
                out.append(f"  <link name={_quoteattr(name)}/>")
        out.extend(joints_xml)
        out.append("</robot>")
        return "\n".join(out) + "\n"

    def _header(self) -> list[str]:
        spec = self.spec
        out = [
            '<?xml version="1.0" encoding="utf-8"?>',
            "<!--",
            f"  Robot {spec.name}, written by motiontool from {spec.model_path.name}",
            f"  (sha256 {spec.model_hash}) as Pinocchio reads it.",
        ]
        if self.floating:
            out.append(
                f"  The root link '{self.link_of_joint(1)}' is free-flying: load this file with a "
                "free-flyer root joint (pinocchio.JointModelFreeFlyer())."
            )
        return [
            *out,
            "  URDF has no capsule: each capsule is written as its exact equivalent, a cylinder",
            "  and two end spheres. Not written (no URDF equivalent): MuJoCo actuators and",
            "  options, sites, the Webots time step and the names of the feet.",
            "-->",
            f"<robot name={_quoteattr(spec.name)}>",
        ]

    def _moving_links(self, links: dict[str, list[str]]) -> list[str]:
        """The link of each model joint (with its inertial) into ``links``; the joints' XML."""
        joints_xml = []
        for jid in sorted(self.main):
            body = links.setdefault(self.link_of_joint(jid), [])
            inertia = self.model.inertias[jid]
            if jid >= self.root_joint and float(inertia.mass) > 0.0 and self.main[jid] >= 0:
                body.append(self._inertial(inertia))
            if jid > self.root_joint:
                joints_xml.append(self._joint(jid))
        return joints_xml

    def _fixed_links(self, links: dict[str, list[str]]) -> list[str]:
        """Fixed bodies (e.g. the Nao's foot force-sensor boxes) into ``links``; the XML of
        their fixed joints."""
        import numpy as np

        joints_xml = []
        mains = set(self.main.values())
        for fid, frame in enumerate(self.frames):
            if str(frame.type) != "BODY" or fid in mains:
                continue
            parent_fid = self._parent_body(fid)
            links.setdefault(frame.name, [])
            rel = np.linalg.inv(self.placement(parent_fid)) @ self.placement(fid)
            joint_name = self.frames[frame.parentFrame].name
            joints_xml.append(
                f'  <joint name={_quoteattr(joint_name)} type="fixed">'
                f"<parent link={_quoteattr(self._body_name(parent_fid))}/>"
                f"<child link={_quoteattr(frame.name)}/>{origin(rel[:3, :3], rel[:3, 3])}</joint>"
            )
        return joints_xml

    def _collision_links(self, links: dict[str, list[str]]) -> None:
        """Each collision geometry into the link of the body that holds it."""
        import numpy as np

        for obj in self.geoms.geometryObjects:
            body_fid = obj.parentFrame
            name = self.frames[body_fid].name if body_fid > 0 else self.link_of_joint(0)
            parent = np.linalg.inv(self.placement(body_fid if body_fid > 0 else -1))
            rel = np.asarray(parent @ obj.placement.homogeneous, dtype=np.float64)
            links.setdefault(name, []).extend(self._collisions(obj, rel))

    def _parent_body(self, fid: int) -> int:
        """The BODY frame a fixed body hangs from (-1: the world)."""
        frame_id = int(self.frames[fid].parentFrame)
        while frame_id > 0 and str(self.frames[frame_id].type) != "BODY":
            frame_id = int(self.frames[frame_id].parentFrame)
        if frame_id > 0:
            return frame_id
        return self.main.get(int(self.frames[fid].parentJoint), -1)

    def _body_name(self, fid: int) -> str:
        return "world" if fid < 0 else self.frames[fid].name

    def _inertial(self, inertia: Inertia) -> str:
        import numpy as np

        i = inertia.inertia
        com = inertia.lever
        return (
            f'<inertial>{origin(np.eye(3), com)}<mass value="{_g(inertia.mass)}"/>'
            f'<inertia ixx="{_g(i[0, 0])}" ixy="{_g(i[0, 1])}" ixz="{_g(i[0, 2])}" '
            f'iyy="{_g(i[1, 1])}" iyz="{_g(i[1, 2])}" izz="{_g(i[2, 2])}"/></inertial>'
        )

    def _joint(self, jid: int) -> str:
        from motiontool.kinematics._pinocchio import joint_motion

        model = self.model
        name = model.names[jid]
        joint = model.joints[jid]
        kind, axis = joint_motion(joint, joint.shortname())
        if kind == self.fixed or name not in self.spec:
            raise MotionToolError(
                f"cannot write robot {self.spec.name} as URDF: joint '{name}' "
                f"({joint.shortname()}) has no URDF equivalent"
            )
        limits = self.spec.joint(name)
        placement = model.jointPlacements[jid]
        bounded = math.isfinite(limits.lower) and math.isfinite(limits.upper)
        if kind == self.prismatic:
            urdf_type = "prismatic"
        else:
            urdf_type = "revolute" if bounded and joint.nq == 1 else "continuous"
        attrs = []
        if urdf_type != "continuous":
            attrs.append(f'lower="{_g(limits.lower)}" upper="{_g(limits.upper)}"')
        attrs.append(
            f'effort="{_g(limits.max_torque if math.isfinite(limits.max_torque) else 0)}" '
            f'velocity="{_g(limits.max_velocity if math.isfinite(limits.max_velocity) else 0)}"'
        )
        parent = self.link_of_joint(int(model.parents[jid]))
        return (
            f'  <joint name={_quoteattr(name)} type="{urdf_type}">'
            f"<parent link={_quoteattr(parent)}/>"
            f"<child link={_quoteattr(self.link_of_joint(jid))}/>"
            f"{origin(placement.rotation, placement.translation)}"
            f'<axis xyz="{" ".join(_g(a) for a in axis)}"/><limit {" ".join(attrs)}/></joint>'
        )

    def _collisions(self, obj: GeometryObject, rel: Matrix) -> list[str]:
        import numpy as np

        geometry = obj.geometry
        kind = type(geometry).__name__
        shapes: list[tuple[Matrix, str]] = []
        if kind == "Sphere":
            shapes.append((rel, f'<sphere radius="{_g(geometry.radius)}"/>'))
        elif kind == "Box":
            size = " ".join(_g(2.0 * h) for h in geometry.halfSide)
            shapes.append((rel, f'<box size="{size}"/>'))
        elif kind in ("Cylinder", "Capsule"):
            r, half = float(geometry.radius), float(geometry.halfLength)
            shapes.append((rel, f'<cylinder radius="{_g(r)}" length="{_g(2.0 * half)}"/>'))
            if kind == "Capsule":
                for sign in (-1.0, 1.0):
                    end = np.eye(4)
                    end[2, 3] = sign * half
                    shapes.append((rel @ end, f'<sphere radius="{_g(r)}"/>'))
        elif kind in ("BVHModelOBBRSS", "BVHModelOBB", "Convex") and obj.meshPath:
            scale = " ".join(_g(s) for s in obj.meshScale)
            shapes.append(
                (rel, f'<mesh filename={_quoteattr(str(obj.meshPath))} scale="{scale}"/>')
            )
        else:
            raise MotionToolError(
                f"cannot write robot {self.spec.name} as URDF: geometry '{obj.name}' is a "
                f"{kind}, which URDF cannot hold"
            )
        return [
            f"<collision>{origin(m[:3, :3], m[:3, 3])}<geometry>{shape}</geometry></collision>"
            for m, shape in shapes
        ]


def _rpy(rotation: Matrix) -> tuple[float, float, float]:
    """URDF roll, pitch, yaw (rad) of a rotation matrix (R = Rz(yaw) Ry(pitch) Rx(roll))."""
    r = [[float(rotation[i][j]) for j in range(3)] for i in range(3)]
    pitch = math.asin(max(-1.0, min(1.0, -r[2][0])))
    if abs(r[2][0]) < 1.0 - 1e-12:
        roll = math.atan2(r[2][1], r[2][2])
        yaw = math.atan2(r[1][0], r[0][0])
    else:  # gimbal lock: yaw absorbs roll
        roll = 0.0
        yaw = math.atan2(-r[0][1], r[1][1])
    return roll, pitch, yaw


def origin(rotation: Matrix, translation: Matrix) -> str:
    """A URDF ``<origin>`` element for a placement (rotation matrix, translation in m)."""
    xyz = " ".join(_g(float(v)) for v in translation)
    rpy = " ".join(_g(v) for v in _rpy(rotation))
    return f"<origin xyz={_quoteattr(xyz)} rpy={_quoteattr(rpy)}/>"
