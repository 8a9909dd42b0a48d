"""Semantic comparison of two motions: what a robot is commanded, not how the file is spelt.

Two motions are compared through the targets a Webots controller sends while playing them
(:func:`motiontool.motionfmt.player.commands_at`, bit-identical to Webots' player), on one common
grid of playback times ``0, T, 2T, ...`` up to the first multiple of ``T`` at or after the longer
motion's end. Joints are matched by name:

* Of two columns with one name, the later one's command wins at a step where it sends one; where
  it sends none (``*``) the earlier column's command, if any, reaches the motor.
* Where a joint gets no command at a step (a segment touching ``*``), the motor keeps its
  previous target: the comparison uses that *held target*, the last value commanded at an
  earlier step of the grid. Before a motion first commands a joint, it holds no target (the
  motor sits wherever it was); a step where only one side holds a target is a *presence*
  difference, counted separately from the value differences.
* After a motion ends, its motors hold their last targets: a shorter motion is compared, up to
  the longer one's end, with the targets it leaves behind.

Both rules are :func:`motiontool.motionfmt.player.hold_targets`, the forward-fill that the
simulator and the robot checks use too.

So a file that only re-spells numbers, re-spaces keyframes along the same lines, or re-orders its
columns is the *same* motion; added or removed joints and a changed duration are differences.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from motiontool.motionfmt.compare_steps import Played, compared_steps, every_step, played_steps
from motiontool.motionfmt.motion import Motion
from motiontool.motionfmt.player import Held, Holder, commands_at, require_held

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt


__all__ = [
    "DEFAULT_TOLERANCE_RAD",
    "EVERY_STEP_LIMIT",
    "JointDiff",
    "MotionDiff",
    "Played",
    "compare_motions",
    "held_pair",
    "held_targets",
    "joint_names",
]

DEFAULT_TOLERANCE_RAD = 1e-4
"""Largest |Δq| (rad, m for linear joints) for which two commanded targets count as the same.

1e-4 rad is 0.006°, below the resolution of the Nao's joint encoders (12 bit over 2π, 1.5e-3 rad)
and well above the rounding of a value written with 6 decimals (5e-7)."""

EVERY_STEP_LIMIT = 4_000_000
"""A grid of up to this many steps (66 min at 1 ms) is compared at every step, bit for bit, in
seconds at most. A longer one (a motion lasting days would take hours) is compared at the steps
next to each pose time, where |Δq| is largest (exactly so but for rounding: see
:func:`_compared_steps`); :attr:`MotionDiff.compared_steps` says how many."""


def joint_names(motion: Motion | Played) -> tuple[str, ...]:
    """The distinct joint names of ``motion``, in order of first appearance."""
    return tuple(dict.fromkeys(motion.joints))


def _held(motion: Motion, elapsed_ms: npt.NDArray[np.int64], holder: Holder) -> Held:
    """What the motors of ``holder`` hold at the playback times ``elapsed_ms`` (S,), going on
    from what it held at the previous chunk of steps."""
    targets, sent = commands_at(motion, elapsed_ms)
    return holder.hold(targets, sent, motion.joints)


def held_targets(
    motion: Motion,
    timestep_ms: int,
    *,
    until_ms: int | None = None,
    names: Sequence[str] | None = None,
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.float64]]:
    """The target each motor holds at each step of a controller stepping every ``timestep_ms``.

    Args:
        motion: the motion played.
        timestep_ms: controller time step, ms.
        until_ms: last playback time to cover, ms (default: the motion's duration); the grid runs
            up to the first multiple of ``timestep_ms`` at or after it.
        names: joint names (default: :func:`joint_names`); a name the motion lacks gives NaN.

    Returns:
        ``elapsed_ms`` int64 (S,) and ``held`` float64 (S, N): the commanded target, or the
        previous one where the step sends none, NaN before the joint is first commanded (and
        where the command is a ``nan`` cell's NaN).

    Raises:
        StreamTooLongError: more steps than :data:`~.player.MAX_HELD_STEPS`.
    """
    import numpy as np

    names = joint_names(motion) if names is None else names
    end = motion.duration_ms if until_ms is None else until_ms
    require_held(-(-end // timestep_ms) + 1, timestep_ms)
    elapsed = np.arange(-(-end // timestep_ms) + 1, dtype=np.int64) * timestep_ms
    return elapsed, _held(motion, elapsed, Holder(names)).targets


def held_pair(
    old: Motion, new: Motion, timestep_ms: int, names: Sequence[str]
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """What both motions hold for the motors ``names`` at the steps that shape it (those next to
    each pose time of either, both ends, and every step of a segment that reaches Webots'
    no-value marker: see :func:`_compared_steps`): a line through them is the line through
    every step of the grid up to the longer motion's end, whatever its duration.

    Returns:
        ``elapsed_ms`` int64 (K,), and the held targets (K, N) of ``old`` and of ``new``, as
        :func:`held_targets` gives them at those steps.
    """
    import numpy as np

    n_steps = -(-max(old.duration_ms, new.duration_ms) // timestep_ms) + 1
    parts: list[tuple[npt.NDArray[np.int64], Held, Held]] = []
    hold_old, hold_new = Holder(names), Holder(names)
    for steps, _weights in compared_steps((old, new), timestep_ms, n_steps):
        elapsed = steps * timestep_ms
        held_old = _held(old, elapsed, hold_old)
        held_new = _held(new, elapsed, hold_new)
        parts.append((elapsed, held_old, held_new))
    return (
        np.concatenate([e for e, _a, _b in parts]),
        np.concatenate([a.targets for _e, a, _b in parts]),
        np.concatenate([b.targets for _e, _a, b in parts]),
    )


@dataclass(frozen=True)
class JointDiff:
    """How one joint's held target differs between two motions.

    Attributes:
        joint: the joint name.
        max_delta: largest |old - new| held target (rad, m for linear joints) over the steps where
            both hold one; 0.0 if they never both do.
        at_ms: the first playback time (ms) where ``max_delta`` occurs, None if never compared.
        old_value, new_value: the held targets there (rad), None if never compared.
        old_only_steps: how many steps only the old motion holds a target for the joint.
        new_only_steps: how many steps only the new motion does.
        presence_at_ms: the first step (ms) where only one of them does, None if none.
    """

    joint: str
    max_delta: float
    at_ms: int | None
    old_value: float | None
    new_value: float | None
    old_only_steps: int = 0
    new_only_steps: int = 0
    presence_at_ms: int | None = None

    def differs(self, tolerance: float) -> bool:
        """Whether the joint is commanded differently (``tolerance`` in rad)."""
        return self.max_delta > tolerance or self.old_only_steps > 0 or self.new_only_steps > 0

    def to_json(self) -> dict[str, Any]:
        return {
            "joint": self.joint,
            "max_delta": self.max_delta,
            "at_ms": self.at_ms,
            "old_value": self.old_value,
            "new_value": self.new_value,
            "old_only_steps": self.old_only_steps,
            "new_only_steps": self.new_only_steps,
            "presence_at_ms": self.presence_at_ms,
        }


@dataclass(frozen=True)
class MotionDiff:
    """The semantic difference between an old and a new motion.

    Attributes:
        timestep_ms: the comparison grid's step, ms.
        tolerance: largest |Δq| (rad) still counted as the same.
        added: joints only the new motion has (its order).
        removed: joints only the old motion has (its order).
        reordered: whether the joints both have appear in a different order.
        old_duration_ms, new_duration_ms: the motions' durations (last pose time), ms.
        old_poses, new_poses: pose counts.
        joints: one :class:`JointDiff` per joint both have, in the old motion's order.
        grid_steps: the steps of the comparison grid (0 to the longer motion's end).
        compared_steps: those compared: all of them, or past :data:`EVERY_STEP_LIMIT` those
            next to each pose time.
    """

    timestep_ms: int
    tolerance: float
    added: tuple[str, ...]
    removed: tuple[str, ...]
    reordered: bool
    old_duration_ms: int
    new_duration_ms: int
    old_poses: int
    new_poses: int
    joints: tuple[JointDiff, ...] = field(default=())
    grid_steps: int = 0
    compared_steps: int = 0

    @property
    def every_step(self) -> bool:
        """Whether every step of the grid was compared (else those next to the pose times)."""
        return self.compared_steps == self.grid_steps

    @property
    def changed(self) -> tuple[JointDiff, ...]:
        """The joints commanded differently beyond the tolerance."""
        return tuple(j for j in self.joints if j.differs(self.tolerance))

    @property
    def same(self) -> bool:
        """No joint added or removed, same duration, every joint within the tolerance."""
        return (
            not self.added
            and not self.removed
            and self.old_duration_ms == self.new_duration_ms
            and not self.changed
        )

    @property
    def largest(self) -> JointDiff | None:
        """The joint with the largest |Δq| (first in order among equals), None without joints."""
        best: JointDiff | None = None
        for j in self.joints:
            if best is None or j.max_delta > best.max_delta:
                best = j
        return best


class _Extremes:
    """Per common joint, over the steps compared so far: the largest |Δq| where both command it
    (its step and the two values), the steps only one commands it, the first such step."""

    def __init__(self, n: int) -> None:
        import numpy as np

        self.n = n
        self.best = np.full(n, -1.0)
        self.best_step = np.full(n, -1, dtype=np.int64)
        self.best_old = np.full(n, np.nan)
        self.best_new = np.full(n, np.nan)
        self.old_only = np.zeros(n, dtype=np.int64)
        self.new_only = np.zeros(n, dtype=np.int64)
        self.presence_first = np.full(n, -1, dtype=np.int64)

    def update(
        self,
        steps: npt.NDArray[np.int64],
        held_old: Held,
        held_new: Held,
        weights: npt.NDArray[np.int64],
    ) -> None:
        """Take in the steps ``steps`` (S,), where the motions hold ``held_old``, ``held_new``;
        each stands for ``weights`` steps of the grid with the same presence (itself and those
        up to the next one taken in)."""
        import numpy as np

        (a, _, has_a), (b, _, has_b) = held_old, held_new
        n = self.n
        if not n:
            return
        with np.errstate(invalid="ignore"):
            delta = a - b  # exactly 0 where two finite values are equal
        np.abs(delta, out=delta)
        odd = np.isnan(delta)  # a NaN command, or two infinities
        if odd.any():
            ao, bo = a[odd], b[odd]
            same = (ao == bo) | (np.isnan(ao) & np.isnan(bo))  # equal infinities, two NaNs
            delta[odd] = np.where(same, 0.0, np.inf)
        both = has_a & has_b
        if not both.all():
            np.copyto(delta, -1.0, where=~both)
        k = np.argmax(delta, axis=0)
        top = delta[k, np.arange(n)]
        better = top > self.best
        self.best = np.where(better, top, self.best)
        self.best_step = np.where(better, steps[k], self.best_step)
        self.best_old = np.where(better, a[k, np.arange(n)], self.best_old)
        self.best_new = np.where(better, b[k, np.arange(n)], self.best_new)
        only_one = has_a != has_b
        if not only_one.any():
            return
        counts = only_one.sum(axis=0)
        first = np.where(counts > 0, steps[np.argmax(only_one, axis=0)], -1)
        self.presence_first = np.where(
            (self.presence_first < 0) & (counts > 0), first, self.presence_first
        )
        self.old_only += weights @ (has_a & ~has_b)
        self.new_only += weights @ (~has_a & has_b)

    def joint_diffs(self, names: Sequence[str], timestep_ms: int) -> list[JointDiff]:
        """One :class:`JointDiff` per joint of ``names`` (the common joints, in order)."""
        joints = []
        for i, name in enumerate(names):
            compared = self.best_step[i] >= 0
            first = self.presence_first[i]
            joints.append(
                JointDiff(
                    joint=name,
                    max_delta=float(self.best[i]) if compared else 0.0,
                    at_ms=int(self.best_step[i] * timestep_ms) if compared else None,
                    old_value=float(self.best_old[i]) if compared else None,
                    new_value=float(self.best_new[i]) if compared else None,
                    old_only_steps=int(self.old_only[i]),
                    new_only_steps=int(self.new_only[i]),
                    presence_at_ms=int(first * timestep_ms) if first >= 0 else None,
                )
            )
        return joints


def compare_motions(
    old: Motion,
    new: Motion | Played,
    *,
    timestep_ms: int = 1,
    tolerance: float = DEFAULT_TOLERANCE_RAD,
) -> MotionDiff:
    """Compare what a robot is commanded by ``old`` and by ``new``.

    Args:
        old, new: the two motions; ``new`` may be one known a window at a time
            (:class:`Played`), whatever its length.
        timestep_ms: controller time step of the comparison grid, ms. The default, 1 ms, compares
            at every playback time any controller can sample (pose times are whole ms).
        tolerance: largest |Δq| (rad, m for linear joints) that still counts as the same.

    Returns:
        a :class:`MotionDiff`; ``diff.same`` answers the question.
    """

    if timestep_ms <= 0:
        raise ValueError(f"timestep_ms must be positive, got {timestep_ms}")
    old_names, new_names = joint_names(old), joint_names(new)
    new_set, old_set = set(new_names), set(old_names)
    common = [n for n in old_names if n in new_set]
    common_in_new = [n for n in new_names if n in old_set]
    end = max(old.duration_ms, new.duration_ms)
    n_steps = -(-end // timestep_ms) + 1
    extremes = _Extremes(len(common))
    hold_old, hold_new = Holder(common), Holder(common)
    if n_steps <= EVERY_STEP_LIMIT:
        chunks = every_step(n_steps)
    elif isinstance(new, Motion):
        chunks = compared_steps((old, new), timestep_ms, n_steps)
    else:
        chunks = played_steps(old, new, timestep_ms, n_steps)
    compared = 0
    for steps, weights in chunks:
        compared += steps.shape[0]
        elapsed = steps * timestep_ms
        if isinstance(new, Motion):
            held_new = _held(new, elapsed, hold_new)
        else:
            held_new = hold_new.hold(*new.commands_at(elapsed), new.joints)
        extremes.update(steps, _held(old, elapsed, hold_old), held_new, weights)
    joints = extremes.joint_diffs(common, timestep_ms)
    return MotionDiff(
        timestep_ms=timestep_ms,
        tolerance=tolerance,
        added=tuple(n for n in new_names if n not in old_set),
        removed=tuple(n for n in old_names if n not in new_set),
        reordered=common != common_in_new,
        old_duration_ms=old.duration_ms,
        new_duration_ms=new.duration_ms,
        old_poses=old.n_poses,
        new_poses=new.n_poses,
        joints=tuple(joints),
        grid_steps=n_steps,
        compared_steps=compared,
    )
