"""Parabolic blends at the corners of Webots' straight lines: what lets a real arm, whose joint
acceleration is bounded, follow a piecewise-linear motion sent a control step at a time.

Webots' player interpolates straight lines between keyframes, so at a keyframe a joint's
velocity changes within one control step (a UR5e's shipped motions need 195 and 370 rad/s² in
one 8 ms step). The classic linear segments with parabolic blends round each corner: at a
keyframe where the velocity changes by ``dv_j`` (rad/s) per joint, every joint accelerates
uniformly for one blend time ``tb = max_j |dv_j| / a`` (s) centred on the keyframe, so that no
joint needs more than ``a`` and the joints stay in step (the path keeps its shape). Outside the
blends the lines are untouched, and every keyframe keeps its time: only the corners are cut,
and a joint passes its keyframe ``|dv_j| * tb / 8`` (rad) inside the corner.

Before the first pose and after the last the arm stands still (a URScript program moves to the
first pose and stops there; it stops at the end), so a motion that starts or ends moving has a
corner there too: its blend starts ``tb / 2`` before the first pose, while the arm stands at it,
and ends ``tb / 2`` after the last, where it comes to rest on the last pose.

Two blends may not overlap: ``tb_k / 2 + tb_k+1 / 2`` must fit in the segment between them
(:class:`CornersDoNotFit` where it does not).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.motionfmt.units import MS_PER_S

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.convert.base import StreamChunk

__all__ = ["FIT_SLACK_S", "Blends", "CornersDoNotFit", "blended_chunks", "plan_blends"]

FIT_SLACK_S = 1e-12
"""How far (s) two blends may overlap and still count as fitting: float rounding of ``tb``
only (two blends that touch exactly fit)."""


class CornersDoNotFit(MotionToolError):
    """The blends of two corners do not fit in the segment between them at the acceleration.

    Attributes:
        pose: the keyframe whose corner needs the longer blend of the two (0-based).
        other: the keyframe at the segment's other end.
        needed_rad_s2: the least acceleration at which both blends fit in the segment, rad/s².
        accel_rad_s2: the acceleration the blends were planned at, rad/s².
        worst_rad_s2: the least acceleration at which every blend of the motion fits, rad/s²
            (its most crowded segment's ``needed_rad_s2``).
        joint: the joint whose velocity changes most at ``pose``.
        segment_ms: the segment's duration, ms.
    """

    def __init__(
        self,
        pose: int,
        other: int,
        needed_rad_s2: float,
        accel_rad_s2: float,
        joint: str,
        segment_ms: int,
        worst_rad_s2: float,
    ) -> None:
        self.pose, self.other, self.joint = pose, other, joint
        self.worst_rad_s2 = worst_rad_s2
        self.needed_rad_s2, self.accel_rad_s2, self.segment_ms = (
            needed_rad_s2,
            accel_rad_s2,
            segment_ms,
        )
        super().__init__(f"pose {pose}: {self.reason()}")

    def speed(self) -> float:
        """A ``retime --speed`` factor (two significant digits, rounded down with 0.5 % to
        spare for whole-ms times) at which every blend fits: slowing a motion down by ``s``
        divides its velocity changes by ``s`` and multiplies its segments by ``s``, so the
        acceleration its blends need goes down by ``s²``."""
        x = math.sqrt(self.accel_rad_s2 / self.worst_rad_s2) * 0.995
        unit = 10.0 ** (math.floor(math.log10(x)) - 1)
        return math.floor(x / unit) * unit

    def reason(self) -> str:
        """What is wrong, without the place (the caller names the keyframe's line)."""
        return (
            f"its corner ({self.joint} most) needs {self.needed_rad_s2:.4g} rad/s² to be "
            f"rounded, with pose {self.other}'s, in the {self.segment_ms} ms between them, "
            f"beyond {self.accel_rad_s2:g} rad/s²"
        )


@dataclass(frozen=True)
class Blends:
    """The blends of a motion's corners.

    Attributes:
        joints: the N joints.
        times_ms: int64 (P,): each keyframe's time, ms.
        dv: float64 (P, N): each joint's change of velocity at each keyframe, rad/s (at the
            first, from rest; at the last, to rest).
        tb_s: float64 (P,): each keyframe's blend time, s (0: no corner).
        accel_rad_s2: the acceleration the blends are planned at, rad/s².
    """

    joints: tuple[str, ...]
    times_ms: npt.NDArray[np.int64]
    dv: npt.NDArray[np.float64]
    tb_s: npt.NDArray[np.float64]
    accel_rad_s2: float

    @property
    def corners(self) -> int:
        """How many keyframes are blended (a velocity change there)."""
        return int((self.tb_s > 0).sum())

    def deviation(self) -> npt.NDArray[np.float64]:
        """float64 (P, N): how far each joint passes each keyframe from it, rad: the largest
        distance between the blend and the two lines, ``|dv| * tb / 8``."""
        import numpy as np

        out: npt.NDArray[np.float64] = np.abs(self.dv) * self.tb_s[:, None] / 8.0
        return out

    def worst(self) -> tuple[float, int, int]:
        """(the largest deviation rad, its keyframe, its joint): the first in pose order."""
        import numpy as np

        d = self.deviation()
        if d.size == 0:
            return 0.0, 0, 0
        pose, joint = np.unravel_index(int(np.argmax(d)), d.shape)
        return float(d[pose, joint]), int(pose), int(joint)

    def span_ms(self) -> tuple[float, float]:
        """(ms, ms): when the first blend starts and the last one ends, ms: the first and the
        last pose's times where the motion starts and ends still."""
        start = float(self.times_ms[0]) - self.tb_s[0] / 2 * MS_PER_S
        end = float(self.times_ms[-1]) + self.tb_s[-1] / 2 * MS_PER_S
        return start, end

    def correction(self, elapsed_ms: npt.NDArray[np.int64]) -> npt.NDArray[np.float64]:
        """float64 (S, N): what to add to the lines at the times ``elapsed_ms`` (S,), ms, in
        increasing order, to follow the blends instead, rad; 0 outside them. Within the blend
        of a keyframe at ``T``, from ``T - tb/2``: ``dv * s² / (2 tb)`` with ``s`` the time
        since the blend started, less the line's own turn after ``T``, ``dv * (t - T)``."""
        import numpy as np

        out = np.zeros((elapsed_ms.shape[0], len(self.joints)))
        if elapsed_ms.shape[0] == 0:
            return out
        t = elapsed_ms.astype(np.float64) / MS_PER_S
        at = self.times_ms.astype(np.float64) / MS_PER_S
        half = self.tb_s / 2
        # The blends are in time order and never overlap: those that reach this chunk.
        first = int(np.searchsorted(at + half, t[0], side="left"))
        last = int(np.searchsorted(at - half, t[-1], side="right"))
        for k in range(first, last):
            tb = float(self.tb_s[k])
            if tb <= 0:
                continue
            lo = int(np.searchsorted(t, at[k] - tb / 2, side="right"))
            hi = int(np.searchsorted(t, at[k] + tb / 2, side="left"))
            s = t[lo:hi] - (at[k] - tb / 2)
            after = np.maximum(t[lo:hi] - at[k], 0.0)
            out[lo:hi] = self.dv[k] * (s * s / (2 * tb) - after)[:, None]
        return out


def plan_blends(
    joints: tuple[str, ...],
    times_ms: npt.NDArray[np.int64],
    targets: npt.NDArray[np.float64],
    sent: npt.NDArray[np.bool_],
    accel_rad_s2: float,
) -> Blends:
    """The blends of the corners of Webots' lines through ``targets`` at ``accel_rad_s2``.

    Args:
        joints: the N joints.
        times_ms: int64 (P,): the keyframes' times, ms, increasing.
        targets: float64 (P, N): what each joint holds at each keyframe, rad.
        sent: bool (P, N): whether the keyframe sends it; a segment whose two ends do not both
            send is held still (Webots sends nothing there), at 0 rad/s.
        accel_rad_s2: the acceleration every blend is planned at, rad/s² (> 0).

    Raises:
        CornersDoNotFit: two blends overlap (at the first segment where they do).
    """
    import numpy as np

    poses, n = targets.shape
    velocity = np.zeros((poses + 1, n))  # at rest before the first pose and after the last
    seconds = np.diff(times_ms).astype(np.float64) / MS_PER_S
    moving = sent[1:] & sent[:-1] & (seconds > 0)[:, None]
    with np.errstate(invalid="ignore", divide="ignore"):
        lines = np.diff(targets, axis=0) / seconds[:, None]
    velocity[1:-1] = np.where(moving, lines, 0.0)
    dv = np.diff(velocity, axis=0)
    tb = np.abs(dv).max(axis=1, initial=0.0) / accel_rad_s2
    blends = Blends(joints, times_ms, dv, tb, accel_rad_s2)
    over = (tb[:-1] + tb[1:]) / 2 > seconds + FIT_SLACK_S
    if over.any():
        k = int(np.argmax(over))
        pose, other = (k, k + 1) if tb[k] >= tb[k + 1] else (k + 1, k)
        with np.errstate(divide="ignore"):
            needed = (tb[:-1] + tb[1:]) * accel_rad_s2 / (2 * seconds)
        joint = joints[int(np.argmax(np.abs(dv[pose])))]
        segment = int(times_ms[k + 1] - times_ms[k])
        worst = float(needed.max())
        raise CornersDoNotFit(pose, other, float(needed[k]), accel_rad_s2, joint, segment, worst)
    return blends


def blended_chunks(
    chunks: Iterable[StreamChunk], blends: Blends, step_ms: int
) -> Iterator[tuple[npt.NDArray[np.int64], npt.NDArray[np.float64], npt.NDArray[np.float64]]]:
    """Webots' stream ``chunks`` (times ms, targets (S, N) rad) with its corners blended:
    (times ms (S,), Webots' targets (S, N), the blended targets (S, N)) a chunk at a time.
    Where the first or last blend reaches past the stream, steps of ``step_ms`` (ms) are
    added before or after it, the arm standing at the first or last target there."""
    import numpy as np

    start, end = blends.span_ms()
    last: tuple[int, npt.NDArray[np.float64]] | None = None
    for elapsed, base in chunks:
        if elapsed.shape[0] == 0:
            continue
        if last is None:  # the blend of a motion that starts moving: while the arm stands
            before = math.ceil((float(elapsed[0]) - start) / step_ms)
            if before > 0:
                at = elapsed[0] - step_ms * np.arange(before, 0, -1, dtype=np.int64)
                rest = np.repeat(base[:1], before, axis=0)
                yield at, rest, rest + blends.correction(at)
        yield elapsed, base, base + blends.correction(elapsed)
        last = (int(elapsed[-1]), base[-1])
    if last is None:
        return
    after = math.ceil((end - last[0]) / step_ms)
    if after > 0:  # the blend of a motion that ends moving: the arm comes to rest
        at = last[0] + step_ms * np.arange(1, after + 1, dtype=np.int64)
        rest = np.repeat(last[1][None, :], after, axis=0)
        yield at, rest, rest + blends.correction(at)
