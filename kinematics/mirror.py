"""Left/right mirror maps of a robot, derived from its model's joint axes.

Mirroring a motion reflects the robot through its sagittal plane, the x-z plane of the root
body's frame (x forward, z up): the reflection is ``M = diag(1, -1, 1)``. A rotation by ``q``
about a unit axis ``a`` becomes, reflected, ``M R(a, q) M = R(M a, -q)`` (an axis is a
pseudovector: ``M (u x v) = -(M u x M v)`` because ``det M = -1``). If the partner joint's
axis ``b`` is ``M a`` up to sign, ``b = c M a`` with ``c = (M a) . b = +-1``, the reflected
rotation is ``R(b, -c q)``: the partner's angle is ``s q`` with::

    s = -(M a) . b

Both axes are taken in the root frame at the zero pose. For a Nao, pitch joints (axis y) keep
their sign (``s = +1``), roll and yaw joints (axis x or z) flip it (``s = -1``); the hip
yaw-pitch joints, whose axes are ``(0, 0.707, -0.707)`` (left) and ``(0, 0.707, 0.707)``
(right), keep it, as the real robot's single motor for both requires. A joint with no partner
(HeadYaw, HeadPitch) is its own partner, with the same rule. A prismatic joint moves along its
axis, a vector (not a pseudovector): its sign is ``+(M a) . b``.

Partners are paired by name: ``L``/``R`` prefixes before a capital (``LShoulderPitch``),
``l_``/``r_``, ``left``/``right`` and ``Left``/``Right`` as words (``leg_left_1_joint``).
Joints whose axes are not mirror images (``|(M a) . b| < 1 -`` :data:`AXIS_TOLERANCE`) cannot be
mirrored joint by joint and raise :class:`MotionToolError`.

Axes and anchors are read from the model with :mod:`xml.etree` and numpy (MJCF ``quat`` or
URDF ``origin rpy``), no physics library.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.kinematics.robots import RobotSpec

if TYPE_CHECKING:
    import xml.etree.ElementTree as ET

    import numpy as np
    import numpy.typing as npt

__all__ = [
    "AXIS_TOLERANCE",
    "JointFrame",
    "MirrorMap",
    "MirrorPair",
    "joint_frames",
    "mirror_map",
    "partner_name",
]

AXIS_TOLERANCE = 1e-6
"""How far (dimensionless, on a dot product of unit vectors) two joint axes may be from exact
mirror images, ``|(M a) . b| >= 1 - AXIS_TOLERANCE``: the shipped models' axes are written with
6 to 9 significant digits (``0.707107``), so their dot products miss 1 by about 1e-7."""

_SIDE_PATTERNS = (
    # (regex matching one side, replacement function): tried in order.
    re.compile(r"^(?P<s>[LR])(?=[A-Z0-9_])"),
    re.compile(r"(?:^|(?<=_))(?P<s>[lr])(?=_)"),
    re.compile(r"(?:^|(?<=_))(?P<s>left|right)(?=_|$)"),
    re.compile(r"(?:^|(?<=_))(?P<s>[lr])$"),
    re.compile(r"(?P<s>Left|Right)"),
)
_SWAP = {
    "L": "R",
    "R": "L",
    "l": "r",
    "r": "l",
    "left": "right",
    "right": "left",
    "Left": "Right",
    "Right": "Left",
}


def partner_name(name: str) -> str | None:
    """The name of ``name``'s mirror partner by the naming conventions (``LShoulderRoll`` ->
    ``RShoulderRoll``, ``leg_left_1_joint`` -> ``leg_right_1_joint``), or None without a side."""
    for pattern in _SIDE_PATTERNS:
        m = pattern.search(name)
        if m:
            a, b = m.span("s")
            return name[:a] + _SWAP[m.group("s")] + name[b:]
    return None


@dataclass(frozen=True)
class JointFrame:
    """A motor's axis and anchor at the zero pose, in the root body's frame.

    Attributes:
        name: the motor.
        axis: unit axis, shape (3,) float64 (dimensionless).
        anchor: the joint's position, m, shape (3,) float64.
        kind: ``'hinge'`` or ``'slide'``.
    """

    name: str
    axis: npt.NDArray[np.float64]
    anchor: npt.NDArray[np.float64]
    kind: str


@dataclass(frozen=True)
class MirrorPair:
    """How one joint's target maps under the left/right mirror.

    Attributes:
        joint: the motor.
        partner: the motor that plays its mirror image (``joint`` itself for a centre joint).
        sign: ``+1`` or ``-1``: ``q[partner]' = sign * q[joint]``.
        dot: ``(M a) . b`` of the two axes (dimensionless, +-1 within :data:`AXIS_TOLERANCE`).
        offset_m: distance between the partner's anchor and the reflected anchor of ``joint``,
            m: 0 for a geometrically symmetric model.
    """

    joint: str
    partner: str
    sign: int
    dot: float
    offset_m: float


@dataclass(frozen=True)
class MirrorMap:
    """A robot's left/right mirror: every motor's partner and sign.

    Attributes:
        robot: the robot's name.
        model_hash: sha256 of the model the map was derived from.
        pairs: one :class:`MirrorPair` per motor, in model order.
    """

    robot: str
    model_hash: str
    pairs: tuple[MirrorPair, ...]

    def as_dict(self) -> dict[str, tuple[str, int]]:
        """``{joint: (partner, sign)}`` for :func:`motiontool.motionfmt.ops.mirror.mirror`."""
        return {p.joint: (p.partner, p.sign) for p in self.pairs}

    @property
    def largest_offset_m(self) -> float:
        """The largest anchor asymmetry of the model, m (see :attr:`MirrorPair.offset_m`)."""
        return max((p.offset_m for p in self.pairs), default=0.0)


def _quat_matrix(w: float, x: float, y: float, z: float) -> npt.NDArray[np.float64]:
    import numpy as np

    n = math.sqrt(w * w + x * x + y * y + z * z)
    if n == 0.0:
        raise MotionToolError("a body quaternion of the model is zero")
    w, x, y, z = w / n, x / n, y / n, z / n
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def _rpy_matrix(r: float, p: float, y: float) -> npt.NDArray[np.float64]:
    import numpy as np

    cr, sr, cp, sp, cy, sy = (
        math.cos(r),
        math.sin(r),
        math.cos(p),
        math.sin(p),
        math.cos(y),
        math.sin(y),
    )
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    out: npt.NDArray[np.float64] = rz @ ry @ rx  # URDF: fixed-axis roll, then pitch, then yaw
    return out


def _vec(text: str | None, default: tuple[float, float, float]) -> npt.NDArray[np.float64]:
    import numpy as np

    if text is None:
        return np.array(default, dtype=np.float64)
    parts = text.split()
    if len(parts) != 3:
        raise MotionToolError(f"expected 3 numbers in the model, got '{text}'")
    return np.array([float(v) for v in parts], dtype=np.float64)


def _unit(v: npt.NDArray[np.float64], what: str) -> npt.NDArray[np.float64]:
    import numpy as np

    n = float(np.linalg.norm(v))
    if n == 0.0:
        raise MotionToolError(f"joint {what} has a zero axis in the model")
    return v / n


def _mjcf_frames(path: Path) -> Iterator[JointFrame]:
    """Joint frames of an MJCF file: body ``pos``/``quat`` composed from the root body down."""
    import xml.etree.ElementTree as ET

    import numpy as np

    root = ET.fromstring(path.read_bytes())
    world = root.find("worldbody")
    base = None if world is None else world.find("body")
    if base is None:
        raise MotionToolError(f"{path}: no body under <worldbody>")

    def walk(
        body: ET.Element, rot: npt.NDArray[np.float64], pos: npt.NDArray[np.float64]
    ) -> Iterator[JointFrame]:
        for attr in ("euler", "axisangle", "xyaxes", "zaxis"):
            if body.get(attr) is not None:
                raise MotionToolError(
                    f"{path}: body '{body.get('name')}' gives its orientation as '{attr}'; the "
                    "mirror map reads 'quat' only"
                )
        for joint in body.iterfind("joint"):
            kind = joint.get("type", "hinge")
            if kind not in ("hinge", "slide"):
                continue
            name = joint.get("name", "")
            axis = rot @ _unit(_vec(joint.get("axis"), (0.0, 0.0, 1.0)), name)
            anchor = pos + rot @ _vec(joint.get("pos"), (0.0, 0.0, 0.0))
            yield JointFrame(name, axis, anchor, kind)
        for child in body.iterfind("body"):
            q = _vec_quat(child.get("quat"))
            yield from walk(
                child,
                rot @ _quat_matrix(*q),
                pos + rot @ _vec(child.get("pos"), (0.0, 0.0, 0.0)),
            )

    yield from walk(base, np.eye(3), np.zeros(3))


def _vec_quat(text: str | None) -> tuple[float, float, float, float]:
    if text is None:
        return (1.0, 0.0, 0.0, 0.0)
    parts = [float(v) for v in text.split()]
    if len(parts) != 4:
        raise MotionToolError(f"expected a quaternion of 4 numbers in the model, got '{text}'")
    return parts[0], parts[1], parts[2], parts[3]


def _urdf_frames(path: Path) -> Iterator[JointFrame]:
    """Joint frames of a URDF file: joint ``origin`` (xyz, rpy) composed from the root link."""
    import xml.etree.ElementTree as ET

    import numpy as np

    root = ET.fromstring(path.read_bytes())
    children: dict[str, list[ET.Element]] = {}
    child_links = set()
    for joint in root.iterfind("joint"):
        parent = joint.find("parent")
        child = joint.find("child")
        if parent is None or child is None:
            continue
        children.setdefault(parent.get("link", ""), []).append(joint)
        child_links.add(child.get("link", ""))
    roots = [link.get("name", "") for link in root.iterfind("link")]
    roots = [n for n in roots if n not in child_links]
    if not roots:
        raise MotionToolError(f"{path}: no root link")

    def walk(
        link: str, rot: npt.NDArray[np.float64], pos: npt.NDArray[np.float64]
    ) -> Iterator[JointFrame]:
        for joint in children.get(link, []):
            origin = joint.find("origin")
            xyz = _vec(None if origin is None else origin.get("xyz"), (0.0, 0.0, 0.0))
            rpy = _vec(None if origin is None else origin.get("rpy"), (0.0, 0.0, 0.0))
            jrot = rot @ _rpy_matrix(*(float(v) for v in rpy))
            jpos = pos + rot @ xyz
            kind = joint.get("type", "fixed")
            if kind in ("revolute", "continuous", "prismatic"):
                axis_el = joint.find("axis")
                name = joint.get("name", "")
                axis = _unit(
                    _vec(None if axis_el is None else axis_el.get("xyz"), (1.0, 0.0, 0.0)), name
                )
                yield JointFrame(
                    name, jrot @ axis, jpos, "slide" if kind == "prismatic" else "hinge"
                )
            child = joint.find("child")
            if child is not None:
                yield from walk(child.get("link", ""), jrot, jpos)

    yield from walk(roots[0], np.eye(3), np.zeros(3))


def joint_frames(spec: RobotSpec) -> dict[str, JointFrame]:
    """Every motor's axis and anchor at the zero pose, in the root frame, by name."""
    reader = _urdf_frames if spec.model_format == "urdf" else _mjcf_frames
    frames = {f.name: f for f in reader(spec.model_path)}
    return {name: frames[name] for name in spec.joint_names if name in frames}


def mirror_map(spec: RobotSpec) -> MirrorMap:
    """The left/right mirror of ``spec``'s motors (see the module docstring).

    Raises:
        MotionToolError: a motor whose partner's axis (its own, for a centre joint) is not the
            mirror image of its axis, naming the joints and the dot product found.
    """
    import numpy as np

    frames = joint_frames(spec)
    reflect = np.array([1.0, -1.0, 1.0])
    pairs = []
    bad = []
    for name, frame in frames.items():
        partner = partner_name(name)
        if partner is None or partner not in frames:
            partner = name
        other = frames[partner]
        dot = float((reflect * frame.axis) @ other.axis)
        if abs(abs(dot) - 1.0) > AXIS_TOLERANCE:
            bad.append(f"{name} -> {partner} ((M a).b = {dot:.6g})")
            continue
        sign = 1 if dot > 0 else -1
        if frame.kind == "hinge":
            sign = -sign
        offset = float(np.linalg.norm(reflect * frame.anchor - other.anchor))
        pairs.append(MirrorPair(name, partner, sign, dot, offset))
    if bad:
        raise MotionToolError(
            f"robot {spec.name} cannot be mirrored joint by joint: the axes of "
            + ", ".join(bad)
            + " are not mirror images through its x-z plane"
        )
    return MirrorMap(spec.name, spec.model_hash, tuple(pairs))
