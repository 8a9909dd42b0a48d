"""What motiontool knows about a robot without a physics library: its motors and their limits
(:class:`JointSpec`), the model they come from and its rules (:class:`RobotSpec`).

Where a spec comes from: :mod:`.builtin_robots` (the shipped models), :mod:`.erd` (URDF/MJCF
files and example-robot-data, through Pinocchio); :mod:`.robots` chooses one.
"""

from __future__ import annotations

import bisect
import difflib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal

from motiontool.errors import MotionToolError

__all__ = ["JointSpec", "RobotSpec", "fmt_name", "unknown_joint_message"]


@dataclass(frozen=True, slots=True)
class JointSpec:
    """One motor (actuated 1-DoF joint) and its limits.

    Attributes:
        name: the motor name, as a motion file's header names it.
        lower: lowest allowed position, rad (``unit == 'rad'``) or m (``unit == 'm'``);
            ``-inf`` when unbounded.
        upper: highest allowed position, same unit; ``+inf`` when unbounded.
        max_velocity: speed limit, rad/s or m/s; ``inf`` when the model gives none.
        max_torque: effort limit, N·m (hinge) or N (slide); ``inf`` when the model gives none.
        kind: ``'hinge'`` (revolute) or ``'slide'`` (prismatic).
        unit: ``'rad'`` for hinges, ``'m'`` for slides.
    """

    name: str
    lower: float
    upper: float
    max_velocity: float
    max_torque: float
    kind: Literal["hinge", "slide"] = "hinge"
    unit: Literal["rad", "m"] = "rad"


@dataclass(frozen=True)
class RobotSpec:
    """Everything motiontool knows about a robot, without loading a physics library.

    Attributes:
        name: ``nao``, ``nao-v5``, ``ur5e``, ``erd:<name>`` or the model file's stem.
        model_path: the MJCF (``.xml``) or URDF file describing the robot.
        model_hash: sha256 (hex) of the model file's bytes followed by the overrides file's bytes
            (``nao-v5``); stamps reports so a result names the exact model it used.
        joints: the motors, in model order.
        default_timestep_ms: control period of the robot's Webots world, ms (``nao`` 20,
            ``ur5e`` 8; 32, Webots' default, for other robots).
        model_format: ``'mjcf'`` or ``'urdf'``.
        floating_base: whether the model's root is free-flying (Nao, legged robots).
        overrides_path: the JSON file whose limits replace the model's (``nao-v5``), or None.
        head_pitch_envelope: rows (HeadYaw, HeadPitch min, HeadPitch max), rad, HeadYaw
            ascending: the HeadPitch range allowed at a given HeadYaw (``nao-v5``); empty if
            the robot has no such rule. See :meth:`head_pitch_limits`.
        coupled_joints: pairs (leader, follower) driven by one motor on the real robot, so that
            ``q[follower] == q[leader]`` must hold (``nao-v5``).
        feet: names of the collision geometries that touch the floor (the Nao's ``LFsr`` and
            ``RFsr`` boxes); empty for robots without feet.
    """

    name: str
    model_path: Path
    model_hash: str
    joints: tuple[JointSpec, ...]
    default_timestep_ms: int
    model_format: Literal["mjcf", "urdf"] = "mjcf"
    floating_base: bool = False
    overrides_path: Path | None = None
    head_pitch_envelope: tuple[tuple[float, float, float], ...] = ()
    coupled_joints: tuple[tuple[str, str], ...] = ()
    feet: tuple[str, ...] = ()
    _index: dict[str, int] = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        self._index.update((j.name, i) for i, j in enumerate(self.joints))

    @property
    def joint_names(self) -> tuple[str, ...]:
        """Motor names in model order."""
        return tuple(j.name for j in self.joints)

    def model_key(self, code_stamp: str) -> str:
        """What a result made from this robot's model is kept by on disk (sha256, hex): the
        model (its hash, overrides included), its motors, how it is built (format, free-flying
        root) and ``code_stamp``, the code that made the result."""
        import hashlib

        h = hashlib.sha256()
        for part in (
            self.model_hash,
            self.model_format,
            str(self.floating_base),
            "\0".join(self.joint_names),
            code_stamp,
        ):
            h.update(part.encode("utf-8", "surrogateescape") + b"\n")
        return h.hexdigest()

    def __contains__(self, name: object) -> bool:
        return name in self._index

    def joint(self, name: str) -> JointSpec:
        """The motor called ``name``; :class:`MotionToolError` naming the closest match if none."""
        try:
            return self.joints[self._index[name]]
        except KeyError:
            raise MotionToolError(unknown_joint_message(name, self)) from None

    def head_pitch_limits(self, head_yaw: float) -> tuple[float, float] | None:
        """Allowed (min, max) HeadPitch in rad at ``head_yaw`` rad, or None without an envelope.

        Linear interpolation between the envelope's rows; ``head_yaw`` outside the table is
        clamped to its first or last row.
        """
        rows = self.head_pitch_envelope
        if not rows:
            return None
        yaws = [r[0] for r in rows]
        if head_yaw <= yaws[0]:
            return rows[0][1], rows[0][2]
        if head_yaw >= yaws[-1]:
            return rows[-1][1], rows[-1][2]
        k = bisect.bisect_right(yaws, head_yaw)
        (y0, lo0, hi0), (y1, lo1, hi1) = rows[k - 1], rows[k]
        t = (head_yaw - y0) / (y1 - y0)
        return lo0 + t * (lo1 - lo0), hi0 + t * (hi1 - hi0)


def unknown_joint_message(name: str, spec: RobotSpec) -> str:
    """``unknown joint 'HeadYw' for robot nao; did you mean 'HeadYaw'?`` (one line)."""
    close = difflib.get_close_matches(name, spec.joint_names, n=1)
    hint = (
        f"did you mean '{close[0]}'?" if close else "choose one of " + ", ".join(spec.joint_names)
    )
    return f"unknown joint '{name}' for robot {spec.name}; {hint}"


def fmt_name(name: str) -> str:
    """A joint name for a message (undecodable bytes escaped)."""
    return name.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")
