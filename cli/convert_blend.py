"""``convert``'s URScript corners for a real arm: when the servoj stream's corners are blended
(:mod:`motiontool.motionfmt.convert.blend`), where blends cannot fit (one line at the keyframe,
exit 1), ``--max-error``'s bound on how far they pass from the keyframes, and the report's line
on them."""

from __future__ import annotations

from typing import TYPE_CHECKING

from motiontool.cli.convert_checks import cell_at
from motiontool.cli.text import num
from motiontool.errors import MotionToolError

if TYPE_CHECKING:
    from motiontool.motionfmt.convert.base import Imported
    from motiontool.motionfmt.convert.blend import Blends, CornersDoNotFit

__all__ = [
    "DEVIATION_SLACK_RAD",
    "beyond_blend_error",
    "blend_acceleration",
    "blend_lines",
    "pose_where",
    "refuse_blend_options",
    "unfit_corner",
]

DEVIATION_SLACK_RAD = 1e-9
"""Slack on ``--max-error`` against the blends' deviation, rad: float rounding only (as a
recording's bound allows)."""

_FIX = (
    "slow the motion down (motiontool retime --speed {speed:g} IN -o OUT fits every corner), "
    "give that segment more time, or send one movej per keyframe (--keyframes)"
)


def blend_acceleration(real: bool, no_blend: bool, keyframes: bool) -> float | None:
    """The joint acceleration the servoj stream's corners are blended at, rad/s²: the real
    arm's (:data:`~motiontool.kinematics.real_ur5e.MAX_ACCELERATION_RAD_S2`) where it is
    checked against the real arm (``real``); None where the corners go as they are
    (``--no-blend``, ``--keyframes``, or the Webots model, which has no acceleration limit)."""
    if not real or no_blend or keyframes:
        return None
    from motiontool.kinematics.real_ur5e import MAX_ACCELERATION_RAD_S2

    return MAX_ACCELERATION_RAD_S2


def refuse_blend_options(no_blend: bool, keyframes: bool, max_error: float | None) -> None:
    """``--no-blend`` and ``--max-error`` are about the servoj stream's corners: neither goes
    with ``--keyframes`` (movej, UR's own path between keyframes, no deviation claimed)."""
    for option, given in (("--no-blend", no_blend), ("--max-error", max_error is not None)):
        if given and keyframes:
            raise MotionToolError(
                f"{option} is about servoj's blended corners; --keyframes sends movej (UR's "
                "path between keyframes, no deviation claimed): give one or the other"
            )


def pose_where(imported: Imported, pose: int, joint: str | None = None) -> str:
    """Where a pose is in the input: ``path:line:col`` of its cell for ``joint`` (of its time
    where None), or ``path: pose N (T ms)`` where the format has no lines (``.npz``, a bag)."""
    motion = imported.motion
    j = motion.column(joint) if joint is not None and joint in motion.joints else None
    at = cell_at(imported, pose, j)
    if at is not None:
        return f"{imported.path}:{at[0]}:{at[1]}"
    return f"{imported.path}: pose {pose} ({int(motion.times_ms[pose])} ms)"


def _pose(imported: Imported, pose: int) -> str:
    motion = imported.motion
    return f"pose {pose} '{motion.pose_names[pose]}' ({int(motion.times_ms[pose])} ms)"


def unfit_corner(error: CornersDoNotFit, imported: Imported) -> str:
    """The one line that refuses a servoj stream whose corners' blends do not fit: at the
    keyframe's line, the acceleration its corner needs, and what to do."""
    fix = _FIX.format(speed=error.speed())
    return (
        f"{pose_where(imported, error.pose)}: not written: the corner at "
        f"{_pose(imported, error.pose)} needs {error.needed_rad_s2:.4g} rad/s² to be rounded "
        f"({error.joint} turns most; its blend and pose {error.other}'s share the "
        f"{error.segment_ms} ms between them), beyond the real arm's "
        f"{error.accel_rad_s2:g} rad/s²; {fix}"
    )


def _worst(blends: Blends, imported: Imported) -> tuple[float, str]:
    """The blends' largest deviation from the motion, rad, and where: joint, line, pose."""
    rad, pose, k = blends.worst()
    joint = blends.joints[k]
    return rad, f"{joint} at {pose_where(imported, pose, joint)}, {_pose(imported, pose)}"


def beyond_blend_error(blends: Blends | None, max_error: float | None, imported: Imported) -> str:
    """One line where the blended corners pass farther from a keyframe than ``max_error``
    (rad, ``--max-error``) allows; else ''."""
    if blends is None or max_error is None:
        return ""
    rad, where = _worst(blends, imported)
    if rad <= max_error + DEVIATION_SLACK_RAD:
        return ""
    return (
        f"not written: --max-error {num(max_error)} rad: the corners blended at "
        f"{blends.accel_rad_s2:g} rad/s² pass {num(rad)} rad from the motion ({where}); "
        "allow more, or slow the motion down at its corners (motiontool retime)"
    )


def blend_lines(blends: Blends | None, imported: Imported) -> list[str]:
    """The report's lines on the blended corners (none where there are none)."""
    if blends is None:
        return []
    if blends.corners == 0:
        return ["corners blended: none (the motion's velocity never changes)"]
    rad, where = _worst(blends, imported)
    return [
        f"corners blended at {blends.accel_rad_s2:g} rad/s² (the real arm's): "
        f"{blends.corners} keyframes, every one at its time",
        f"worst deviation from the motion: {num(rad)} rad ({where})",
    ]
