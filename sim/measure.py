"""Measuring a run: the trace of a simulation (:class:`motiontool.sim.trace.Trace`) made into the
numbers of its :class:`motiontool.sim.report.PlayReport`: the base (displacement, heading, tilt,
the fall and which way), the feet, each joint's tracking and time at its caps, and the contacts.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from motiontool.motionfmt.units import MM_PER_M
from motiontool.sim.report import (
    BaseStats,
    ContactSummary,
    FileRun,
    FootStats,
    JointStats,
    PlayReport,
)

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt import Motion
    from motiontool.sim._mujoco import Scene
    from motiontool.sim.play_options import PlayOptions
    from motiontool.sim.trace import ContactEvent, Trace

__all__ = [
    "LIMIT_TOLERANCE",
    "TORQUE_CAP_FRACTION",
    "SimulatedRun",
    "counted_contacts",
    "down_frames",
    "measure",
    "tilt_and_heading",
]

TORQUE_CAP_FRACTION = 0.999
"""A motor counts as torque-limited when its torque reaches this fraction of maxTorque."""

LIMIT_TOLERANCE = 0.01
"""How far past a motor limit (rad, or m) a position must be to count as beyond the limits."""


@dataclass(frozen=True)
class SimulatedRun:
    """A simulated run and how it was asked for: what the report and the recording are made of.

    Attributes:
        scene: the MuJoCo scene it ran in; trace: what happened; opts: how it was played.
        motions: the motions played, ``lengths`` their control steps, ``files`` their
            report entries; timestep_ms: the control step, ms.
    """

    scene: Scene
    trace: Trace
    opts: PlayOptions
    motions: list[Motion]
    lengths: list[int]
    timestep_ms: int
    files: list[FileRun]


def tilt_and_heading(quat: npt.NDArray[np.float64]) -> tuple[Any, Any]:
    """(tilt, heading) in degrees of (N, 4) quaternions (w, x, y, z)."""
    import numpy as np

    w, x, y, z = quat.T
    r22 = np.clip(1.0 - 2.0 * (x * x + y * y), -1.0, 1.0)
    r00 = 1.0 - 2.0 * (y * y + z * z)
    r10 = 2.0 * (x * y + w * z)
    return np.degrees(np.arccos(r22)), np.degrees(np.arctan2(r10, r00))


def down_frames(trace: Trace, opts: PlayOptions) -> npt.NDArray[np.bool_]:
    """(N,) bool: the frames where the robot is down, its root lower than ``fall_height_m`` or
    tilted more than ``fall_tilt_deg``."""
    tilt, _heading = tilt_and_heading(trace.base_quat)
    down: npt.NDArray[np.bool_] = (trace.base_pos[:, 2] < opts.fall_height_m) | (
        tilt > opts.fall_tilt_deg
    )
    return down


def _fall_direction_deg(quat: npt.NDArray[np.float64], heading_deg: float) -> float:
    """Which way a root with orientation ``quat`` (w, x, y, z) leans, in degrees from
    ``heading_deg`` (the heading it had while up), in (-180, 180]: 0 forward, 90 left, -90
    right, 180 back (the horizontal direction of its z axis)."""
    w, x, y, z = (float(v) for v in quat)
    lean = math.degrees(math.atan2(2.0 * (y * z - w * x), 2.0 * (x * z + w * y)))
    turned = (lean - heading_deg + 180.0) % 360.0 - 180.0
    return 180.0 if turned == -180.0 else turned


def _base(trace: Trace, opts: PlayOptions) -> BaseStats:
    import numpy as np

    tilt, heading = tilt_and_heading(trace.base_quat)
    down = down_frames(trace, opts)
    up = np.flatnonzero(~down)
    yaw: float | None = None
    if len(up):
        steps = np.diff(heading[up])
        yaw = float(np.sum((steps + 180.0) % 360.0 - 180.0))
    fell_at: float | None = None
    direction: float | None = None
    if len(up):
        after = np.flatnonzero(down[up[0] :])
        if len(after):
            k = up[0] + after[0]  # the first frame down; k - 1 was up
            fell_at = float(trace.time_s[k])
            direction = _fall_direction_deg(trace.base_quat[k], float(heading[k - 1]))
    d = trace.base_pos[-1] - trace.base_pos[0]
    return BaseStats(
        dx_m=float(d[0]),
        dy_m=float(d[1]),
        dz_m=float(d[2]),
        yaw_change_deg=yaw,
        max_tilt_deg=float(tilt.max()),
        final_tilt_deg=float(tilt[-1]),
        min_height_m=float(trace.base_pos[:, 2].min()),
        final_height_m=float(trace.base_pos[-1, 2]),
        started_down=bool(down[0]),
        fell=fell_at is not None,
        fell_at_s=fell_at,
        upright_at_end=not bool(down[-1]),
        fall_direction_deg=direction,
    )


def _feet(trace: Trace) -> list[FootStats]:
    import numpy as np

    out = []
    dt = trace.control_step_s
    for f, name in enumerate(trace.feet):
        xy = trace.foot_pos[:, f, :2]
        touching = trace.foot_contact[:, f]
        moves = np.linalg.norm(np.diff(xy, axis=0), axis=1)
        both = touching[1:] & touching[:-1]
        away = np.linalg.norm(xy - xy[0], axis=1)
        out.append(
            FootStats(
                name=name,
                contact_s=float(touching[1:].sum() * dt),
                slip_m=float(moves[both].sum()),
                max_displacement_m=float(away.max()),
                final_displacement_m=float(away[-1]),
            )
        )
    return out


def _joints(scene: Scene, trace: Trace) -> list[JointStats]:
    import numpy as np

    lim = scene.limits
    dt = trace.control_step_s
    clipped = np.clip(trace.targets, lim.lower, lim.upper)
    error = clipped - trace.position[1:]
    at_velocity_cap = np.abs(trace.velocity_cmd) >= lim.max_velocity
    at_torque_cap = np.abs(trace.torque) >= TORQUE_CAP_FRACTION * lim.max_torque
    outside_target = (trace.targets < lim.lower) | (trace.targets > lim.upper)
    pos = trace.position[1:]
    beyond = (pos < lim.lower - LIMIT_TOLERANCE) | (pos > lim.upper + LIMIT_TOLERANCE)
    ever: npt.NDArray[np.bool_] = np.asarray(trace.commanded.any(axis=0))
    first = np.where(ever, trace.commanded.argmax(axis=0), 0)
    out = []
    for j, name in enumerate(trace.joints):
        e = error[first[j] :, j]
        unit = scene.robot.joint(name).unit
        out.append(
            JointStats(
                name=name,
                limb=scene.joint_limbs[j],
                unit=unit,
                commanded=bool(ever[j]),
                rms_error=float(np.sqrt(np.mean(e * e))) if len(e) else 0.0,
                max_error=float(np.abs(e).max()) if len(e) else 0.0,
                velocity_cap_s=float(at_velocity_cap[:, j].sum() * dt),
                torque_cap_s=float(at_torque_cap[:, j].sum() * dt),
                target_clipped_s=float(outside_target[:, j].sum() * dt),
                beyond_limits_s=float(beyond[:, j].sum() * dt),
            )
        )
    return out


def counted_contacts(trace: Trace, kind: str, opts: PlayOptions) -> list[ContactEvent]:
    """The events of ``kind``; self-collisions: the probe's from the tolerance down, and every
    contact between robot bodies that the simulation itself collides."""
    if kind != "self":
        return [e for e in trace.events if e.kind == kind]
    floor = opts.collision_tolerance_mm / MM_PER_M
    return [
        e for e in trace.events if e.kind == "touch" or (e.kind == "self" and e.depth_m >= floor)
    ]


def _contact_summaries(trace: Trace, kind: str, opts: PlayOptions) -> list[ContactSummary]:
    """One summary per pair of bodies: first frame, frames seen (as a duration), deepest."""
    first: dict[tuple[str, str], int] = {}
    frames: dict[tuple[str, str], set[int]] = {}
    depth: dict[tuple[str, str], float] = {}
    for e in counted_contacts(trace, kind, opts):
        key = (e.body_a, e.body_b)
        first[key] = min(first.get(key, e.frame), e.frame)
        frames.setdefault(key, set()).add(e.frame)
        depth[key] = max(depth.get(key, 0.0), e.depth_m)
    return [
        ContactSummary(
            key[0],
            key[1],
            float(trace.time_s[first[key]]),
            len(frames[key]) * trace.control_step_s,
            depth[key],
        )
        for key in sorted(first, key=lambda k: (first[k], k))
    ]


def measure(
    run: SimulatedRun, options_doc: dict[str, Any], stamps: dict[str, Any], ignored: list[str]
) -> PlayReport:
    """The report of ``run``: its ``options`` and ``stamps`` as given, the joints, base, feet
    and contacts measured on the trace, the columns ``ignored`` (no motor of the robot), the
    simulator's warnings and error."""
    scene, trace, opts = run.scene, run.trace, run.opts
    return PlayReport(
        robot=scene.robot.name,
        files=run.files,
        options=options_doc,
        stamps=stamps,
        simulated_s=float(trace.time_s[-1]),
        control_steps=trace.steps_done,
        joints=_joints(scene, trace),
        base=_base(trace, opts) if scene.floating else None,
        feet=_feet(trace),
        self_collisions=_contact_summaries(trace, "self", opts),
        scene_contacts=_contact_summaries(trace, "scene", opts),
        ground_contacts=_contact_summaries(trace, "ground", opts),
        warnings=dict(trace.warnings),
        ignored_joints=ignored,
        error=trace.error,
    )
