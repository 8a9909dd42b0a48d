"""The real UR5e, where it differs from the Webots model: what a URScript program may ask of it.

The Webots ``UR5e`` PROTO lets the wrists turn at 6.28 rad/s (360 °/s); the real arm turns every
joint at 180 °/s at most. A program for the real arm is checked against these figures:

* :data:`MAX_VELOCITY_RAD_S`: 180 °/s (π rad/s) on every joint: UR's UR5e datasheet ("Joint
  ranges, speed: all joints 180 °/s") and UR's ROS 2 description,
  ``Universal_Robots_ROS2_Description/config/ur5e/joint_limits.yaml`` (``max_velocity:
  3.14159...`` on all six joints).
* :data:`MAX_ACCELERATION_RAD_S2`: 40 rad/s², the largest joint acceleration the controller
  takes for ``movej``'s ``a`` (UR's URScript manual gives ``a`` as "joint acceleration of
  leading axis"; SDU Robotics' ur_rtde, ``rtde_control_interface.h``, bounds it with
  ``UR_JOINT_ACCELERATION_MAX 40.0 // rad/s^2``). UR states that the arm has no joint
  acceleration limit of its own, only torque limits; UR's MoveIt configuration
  (``Universal_Robots_ROS2_Driver/ur_moveit_config/config/joint_limits.yaml``) plans with a
  conservative 5 rad/s². A path that needs more than 40 rad/s² is one the controller will not
  follow as sent.
* :data:`CONTROL_CYCLE_MS`: the e-Series controller runs at 500 Hz (UR's e-Series manuals):
  ``servoj``'s ``t`` shorter than 2 ms is no command the controller can keep.

Pure (numpy only): the stream comes in as a :class:`~motiontool.motionfmt.convert.base.RobotStream`.
"""

from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING

from motiontool.kinematics.checks._table import EPS
from motiontool.motionfmt.units import MS_PER_S

if TYPE_CHECKING:
    from collections.abc import Iterator

    from motiontool.kinematics.robot_spec import RobotSpec
    from motiontool.motionfmt.convert.base import RobotStream, StreamChunk

__all__ = [
    "CONTROL_CYCLE_MS",
    "MAX_ACCELERATION_RAD_S2",
    "MAX_VELOCITY_RAD_S",
    "movej_findings",
    "real_arm",
    "servoj_findings",
]

MAX_VELOCITY_RAD_S = math.pi
"""The real UR5e's joint speed limit, rad/s (180 °/s), on every joint."""
MAX_ACCELERATION_RAD_S2 = 40.0
"""The largest joint acceleration the UR controller takes, rad/s² (see the module)."""
CONTROL_CYCLE_MS = 2
"""The e-Series controller's cycle, ms (500 Hz)."""

REAL_ARMS = frozenset({"ur5e"})
"""The robots whose real limits are known here."""


def real_arm(spec: RobotSpec) -> RobotSpec:
    """``spec`` (the Webots ``ur5e``) with the real arm's speed limit on every joint, named
    ``'<name> (real arm)'``."""
    joints = tuple(dataclasses.replace(j, max_velocity=MAX_VELOCITY_RAD_S) for j in spec.joints)
    return dataclasses.replace(spec, name=f"{spec.name} (real arm)", joints=joints)


def servoj_findings(stream: RobotStream, timestep_ms: int, what: str) -> list[str]:
    """What a ``servoj`` stream sent every ``timestep_ms`` (ms) asks beyond the real arm: a
    ``t`` under the controller's cycle, and per joint the largest acceleration between three
    consecutive targets (rad/s², its first time, ms) above :data:`MAX_ACCELERATION_RAD_S2`.
    The arm stands at the first target before the stream (a movej took it there) and at the
    last one after it (stopj): the step from rest into the stream and back to rest count.
    One line each. The stream is read a chunk at a time."""
    import numpy as np

    out = []
    if timestep_ms < CONTROL_CYCLE_MS:
        out.append(
            f"{what}: servoj t = {timestep_ms} ms is shorter than the controller's "
            f"{CONTROL_CYCLE_MS} ms cycle"
        )
    worst: dict[int, tuple[float, int]] = {}
    tail_t = np.zeros(0, dtype=np.float64)
    tail_q = np.zeros((0, len(stream.joints)))
    for times_ms, targets in _at_rest_around(stream, timestep_ms):
        t = np.concatenate((tail_t, times_ms.astype(np.float64) / MS_PER_S))
        q = np.concatenate((tail_q, targets))
        tail_t, tail_q = t[-2:], q[-2:]
        if t.shape[0] < 3:
            continue
        v = np.diff(q, axis=0) / np.diff(t)[:, None]
        with np.errstate(invalid="ignore"):
            a = np.abs(np.diff(v, axis=0)) / ((t[2:] - t[:-2]) / 2)[:, None]
        a = np.where(np.isnan(a), 0.0, a)
        for k in range(a.shape[1]):
            i = int(np.argmax(a[:, k]))
            if a[i, k] > worst.get(k, (0.0, 0))[0]:
                worst[k] = (float(a[i, k]), round(float(t[i + 1]) * MS_PER_S))
    for k, (acc, at) in sorted(worst.items()):
        if acc > MAX_ACCELERATION_RAD_S2 * (1 + EPS):
            out.append(
                f"{what}: {stream.joints[k]} needs {acc:.6g} rad/s² at {at} ms, beyond the "
                f"real arm's {MAX_ACCELERATION_RAD_S2:g} rad/s²"
            )
    return out


def _at_rest_around(stream: RobotStream, timestep_ms: int) -> Iterator[StreamChunk]:
    """``stream``'s chunks with its first target once more a step before it and its last
    once more a step after it: the arm at rest on either side."""

    last: StreamChunk | None = None
    for times_ms, targets in stream.chunks():
        if times_ms.shape[0] == 0:
            continue
        if last is None:
            yield times_ms[:1] - timestep_ms, targets[:1]
        yield times_ms, targets
        last = times_ms[-1:], targets[-1:]
    if last is not None:
        yield last[0] + timestep_ms, last[1]


def _trapezoid(distance: float, seconds: float) -> tuple[float, float]:
    """The gentlest rest-to-rest trapezoid that covers ``distance`` (rad) in ``seconds`` (s)
    without passing :data:`MAX_VELOCITY_RAD_S`: (its peak velocity rad/s, its acceleration
    rad/s²); the acceleration is inf where even constant speed needs more than the limit."""
    if distance == 0:
        return 0.0, 0.0
    if 2 * distance / seconds <= MAX_VELOCITY_RAD_S:  # a triangle: the least acceleration
        return 2 * distance / seconds, 4 * distance / seconds**2
    cruise = seconds - distance / MAX_VELOCITY_RAD_S
    if cruise <= 0:
        return distance / seconds, math.inf
    return MAX_VELOCITY_RAD_S, MAX_VELOCITY_RAD_S / cruise


def movej_findings(stream: RobotStream, what: str) -> list[str]:
    """What ``movej`` with ``t`` = each segment and ``r = 0`` asks of the real arm: the
    controller runs a trapezoid from rest to rest in ``t``; per joint, the segment whose
    gentlest trapezoid needs the most acceleration, where it passes the real arm's speed or
    acceleration limit. One line per joint at fault."""
    import numpy as np

    t = stream.times_ms
    q = stream.targets
    out = []
    for k, name in enumerate(stream.joints):
        worst: tuple[float, float, int] | None = None  # (accel, peak, segment)
        for i in range(1, t.shape[0]):
            seconds = float(t[i] - t[i - 1]) / MS_PER_S
            peak, acc = _trapezoid(abs(float(q[i, k] - q[i - 1, k])), seconds)
            if np.isnan(peak) or (worst is not None and acc <= worst[0]):
                continue
            if acc > MAX_ACCELERATION_RAD_S2 * (1 + EPS) or peak > MAX_VELOCITY_RAD_S * (1 + EPS):
                worst = (acc, peak, i)
        if worst is None:
            continue
        acc, peak, i = worst
        distance = abs(float(q[i, k] - q[i - 1, k]))
        needs = (
            f"{peak:.6g} rad/s even at constant speed"
            if math.isinf(acc)
            else f"a peak of {peak:.6g} rad/s and {acc:.6g} rad/s²"
        )
        out.append(
            f"{what}: {name} moves {distance:.6g} rad in movej from {int(t[i - 1])} ms to "
            f"{int(t[i])} ms (rest to rest): its trapezoid needs {needs}, beyond the real "
            f"arm's {MAX_VELOCITY_RAD_S:.6g} rad/s and {MAX_ACCELERATION_RAD_S2:g} rad/s²"
        )
    return out
