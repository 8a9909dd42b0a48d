"""Choregraphe's animations read as a motion: a joint's curve is its keys (time, angle) joined
as NAOqi's ``angleInterpolationBezier`` joins them (:mod:`.naoqi_curve`: a cubic Bézier curve
from key to key, the keys' handles its inner control points), what both a timeline
(:mod:`.choregraphe_xml`) and a Python export (:mod:`.choregraphe_py`) hold.

A key without handles (a timeline's key with no ``Tangent``, a ``bezier auto`` tangent, a
Python export's plain angle) gets the handles Choregraphe gives it automatically: a third of
the way to its neighbours in time, flat at a turning point and at the ends, else along the
line between its neighbours, shortened so the curve does not overshoot either of them
(:func:`auto_handles`). A ``linear`` handle lies on the straight line to its neighbour (the
segment is that line where both do); after a ``constant`` one the angle holds until the next
key.

The motion: each curve sampled at the control step from the earliest key of any joint (the
motion's 0 ms: before it, the robot reaches the first keys from its posture, which is not the
animation) to the last, a joint holding its first key until then and its last after; then its
keyframes reduced within the maximum error (:mod:`.sampled`). A NAO's ``LHand``/``RHand`` (0
closed to 1 open) become Webots' eight phalanges, and ``RHipYawPitch`` follows
``LHipYawPitch`` (one motor drives both on the real robot; Webots' model has two).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.motionfmt.convert.base import Imported, ImportOptions, Sampled
from motiontool.motionfmt.convert.held import MAX_EXPORT_STEPS
from motiontool.motionfmt.convert.joint_map import spread_hands
from motiontool.motionfmt.convert.naoqi_curve import BEZIER_HANDLE, Key, curve_at
from motiontool.motionfmt.convert.sampled import deviation_at, reduced
from motiontool.motionfmt.cscan import INT_MAX
from motiontool.motionfmt.units import MS_PER_S
from motiontool.motionfmt.writer import check_name

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["COUPLED", "Curve", "auto_handles", "curves_motion", "refuse_handles"]

COUPLED = (("LHipYawPitch", "RHipYawPitch"),)
"""(leader, follower): the NAO joints one motor drives, which Choregraphe names by the leader
and Webots' model has both of."""

_THIRD = 1.0 / 3.0


@dataclass(frozen=True)
class Curve:
    """One joint's keys, handles resolved.

    Attributes:
        name: the joint (Choregraphe's name).
        times_s: the keys' times, s, increasing.
        keys: angle (rad; a hand 0 to 1), then its two handles [type, dTime (s), dAngle].
        hold: per segment (key i to i + 1), whether the angle holds at key i's until key
            i + 1 (a ``constant`` tangent).
        line: where the file defines it (1-based).
    """

    name: str
    times_s: tuple[float, ...]
    keys: tuple[Key, ...]
    hold: tuple[bool, ...]
    line: int


def auto_handles(
    times_s: Sequence[float], angles: Sequence[float], i: int
) -> tuple[tuple[float, float], tuple[float, float]]:
    """Choregraphe's automatic handles of key ``i`` of the keys at ``times_s`` (s) with
    ``angles``: ((dTime, dAngle) before, (dTime, dAngle) after), s and rad (see the module)."""
    t, a = times_s[i], angles[i]
    t_left = times_s[i - 1] if i > 0 else t
    t_right = times_s[i + 1] if i + 1 < len(times_s) else t
    slope = 0.0
    if 0 < i < len(times_s) - 1:
        left, right = angles[i - 1], angles[i + 1]
        if min(left, right) < a < max(left, right):  # not a turning point
            slope = (right - left) / (t_right - t_left)
            rise = _THIRD * (t_right - t) * slope  # no overshoot of either neighbour
            if abs(rise) > abs(right - a):
                slope *= (right - a) / rise
            rise = _THIRD * (t - t_left) * slope
            if abs(rise) > abs(a - left):
                slope *= (a - left) / rise
    before = (-_THIRD * (t - t_left), -_THIRD * (t - t_left) * slope)
    after = (_THIRD * (t_right - t), _THIRD * (t_right - t) * slope)
    return before, after


def refuse_handles(curve: Curve, where: str) -> None:
    """A handle whose time leaves its segment makes no curve of time (NAOqi's model needs the
    time along each segment to increase): refused, naming the key."""
    t = curve.times_s
    for i in range(len(t) - 1):
        span = t[i + 1] - t[i]
        after, before = curve.keys[i][2][1], curve.keys[i + 1][1][1]
        if not (0.0 <= after <= span and -span <= before <= 0.0):
            raise MotionToolError(
                f"{where}: {curve.name}: the handles between its keys at {t[i]:g} s and "
                f"{t[i + 1]:g} s reach outside that segment (dTime {after:g} s after the first, "
                f"{before:g} s before the second); they must stay within its {span:g} s"
            )


def _sampled(curve: Curve, t_s: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """The curve at the times ``t_s`` (s), float64: its first key's angle before it."""
    import numpy as np

    q = curve_at(list(curve.times_s), list(curve.keys), t_s)
    q[t_s < curve.times_s[0]] = curve.keys[0][0]
    for i, hold in enumerate(curve.hold):
        if hold:
            inside = (t_s >= curve.times_s[i]) & (t_s < curve.times_s[i + 1])
            q[inside] = curve.keys[i][0]
    return np.asarray(q, dtype=np.float64)


def _grid(start_s: float, end_s: float, step_ms: int, path: str) -> npt.NDArray[np.float64]:
    """Every control step from 0 ms to the last key (ms from the earliest key), and the last
    key's whole ms where it falls between steps."""
    import numpy as np

    end_ms = round((end_s - start_s) * MS_PER_S)
    if end_ms > INT_MAX:
        raise MotionToolError(f"'{path}': {end_ms} ms long, beyond {INT_MAX} ms")
    if end_ms // step_ms + 2 > MAX_EXPORT_STEPS:
        raise MotionToolError(
            f"'{path}': {end_ms} ms long: {end_ms // step_ms + 1:,} control steps of {step_ms} "
            f"ms, more than the {MAX_EXPORT_STEPS:,} an import samples"
        )
    grid = np.arange(0, end_ms + 1, step_ms, dtype=np.int64)
    if grid[-1] != end_ms:
        grid = np.append(grid, end_ms)
    return grid.astype(np.float64)


def curves_motion(
    curves: Sequence[Curve], path: str, options: ImportOptions, what: str, notes: Sequence[str]
) -> Imported:
    """The motion the curves make (see the module), with what they held and its deviation."""
    import numpy as np

    if not curves:
        raise MotionToolError(f"'{path}': no joint curve to read ({what})")
    n_keys, n_curves = sum(len(c.times_s) for c in curves), len(curves)
    curves = [*curves]
    names = [c.name for c in curves]
    for leader, follower in COUPLED:
        if leader in names and follower not in names:
            names.append(follower)
            curves.append(curves[names.index(leader)])
    for name in names:
        check_name(name, "joint")
    start = min(c.times_s[0] for c in curves)
    end = max(c.times_s[-1] for c in curves)
    t_ms = _grid(start, end, options.timestep_ms, path)
    t_s = start + t_ms / MS_PER_S
    q = np.column_stack([_sampled(c, t_s) for c in curves])
    joints, columns = spread_hands(names)
    q = q[:, columns]
    motion, _ = reduced(joints, t_ms, q, options.max_error_rad, path)
    compared = (
        f"{q.size} targets: every joint at every {options.timestep_ms} ms control step "
        "(and the last key) of its curve"
    )
    worst = deviation_at(motion, t_ms, q, compared)
    sampled = Sampled(
        what,
        n_keys,
        n_curves,
        start,
        options.timestep_ms,
        t_ms.shape[0],
        options.max_error_rad,
        worst,
        tuple(notes),
    )
    return Imported(motion, path, sampled=sampled)


def bezier_handle(dt: float, da: float) -> tuple[int, float, float]:
    """A handle as NAOqi takes it: [type, dTime (s), dAngle (rad)]."""
    return (BEZIER_HANDLE, dt, da)
