"""Webots' playback clock: the elapsed time of a playing motion is a C ``int`` of milliseconds.

Each step the player sends the targets at ``elapsed``, then stops if ``elapsed >= duration``,
else adds the time step (``docs/webots-format.md``). The addition is C ``int`` arithmetic: where
``elapsed + timestep`` passes 2147483647 ms before the motion ends, it wraps to a negative time.
Webots then sends the first pose's values (``elapsed <= t[0]``) and goes on stepping; the motion
stops only if the wrapping clock ever lands on a time in ``[duration, 2147483647]``, and for most
time steps it never does. Step ``k`` of a forward cycle is at ``wrap(k * timestep)`` until then.
"""

from __future__ import annotations

from typing import NamedTuple

from motiontool.errors import MotionToolError
from motiontool.motionfmt.cscan import INT_MAX

__all__ = [
    "WEBOTS_DEFAULT_TIMESTEP_MS",
    "ClockOverflow",
    "PlaybackNeverEndsError",
    "clock_overflow",
    "end_step",
    "wrap_int",
]

_INT_RANGE = 1 << 32  # a C int holds [-2**31, 2**31 - 1]

WEBOTS_DEFAULT_TIMESTEP_MS = 32
"""Webots' default ``basicTimeStep`` (WorldInfo), ms: the controller step where neither a robot's
world nor ``timestep`` says one (sampling, plotting or exporting without a robot, a URDF or
``example-robot-data`` robot). The one home of this fact (:mod:`.player` re-exports it)."""


def wrap_int(ms: int) -> int:
    """``ms`` as a 32-bit C ``int`` holds it (two's complement wrap-around)."""
    return (ms + (INT_MAX + 1)) % _INT_RANGE - (INT_MAX + 1)


def _check(duration_ms: int, timestep_ms: int) -> None:
    if not 0 <= duration_ms <= INT_MAX:
        raise ValueError(f"duration_ms must be in [0, {INT_MAX}], got {duration_ms}")
    if not 1 <= timestep_ms <= INT_MAX:
        raise ValueError(f"timestep_ms must be in [1, {INT_MAX}] (a C int), got {timestep_ms}")


def _first_multiple_in(a: int, m: int, lo: int, hi: int) -> int | None:
    """The least ``k >= 0`` with ``lo <= (a * k) mod m <= hi`` (``0 <= lo <= hi < m``), or None
    if there is none: Euclid's algorithm on ``(a, m)``, O(log m) steps."""
    a %= m
    if lo == 0:
        return 0
    if a == 0:
        return None
    k = -(-lo // a)
    if a * k <= hi:  # a multiple of a in [lo, hi] before any wrap
        return k
    # No multiple of a in [lo, hi], so lo % a <= hi % a: a * k - m * y lands in [lo, hi] iff
    # (m * y) mod a lies in [a - hi % a, a - lo % a]. The least y gives the least k.
    y = _first_multiple_in(m % a, a, a - hi % a, a - lo % a)
    if y is None:
        return None
    return -(-(lo + m * y) // a)


def end_step(duration_ms: int, timestep_ms: int) -> int | None:
    """The step at which a forward cycle stops: the least ``k`` with ``wrap(k * timestep_ms)
    >= duration_ms``, or None if the motion never stops (the clock wraps and never lands in
    ``[duration_ms, 2147483647]``). Without a wrap, ``ceil(duration_ms / timestep_ms)``.

    Args:
        duration_ms: the last pose's time, ms (0 to 2147483647).
        timestep_ms: the controller time step, ms (1 to 2147483647).
    """
    _check(duration_ms, timestep_ms)
    return _first_multiple_in(timestep_ms, _INT_RANGE, duration_ms, INT_MAX)


class ClockOverflow(NamedTuple):
    """Where Webots' playback clock wraps before a motion ends (see :func:`clock_overflow`).

    Attributes:
        duration_ms: the motion's duration (its last pose's time), ms.
        timestep_ms: the controller time step, ms.
        step: the step whose time advance wraps: elapsed goes from ``step * timestep_ms`` ms
            (below the duration) to ``wrapped_ms``.
        wrapped_ms: the negative time the clock wraps to, ms.
        end_step: the step at which the motion stops after all, or None: it never stops.
    """

    duration_ms: int
    timestep_ms: int
    step: int
    wrapped_ms: int
    end_step: int | None

    @property
    def ends(self) -> bool:
        """Whether the motion stops at all."""
        return self.end_step is not None

    @property
    def message(self) -> str:
        """What Webots does, in one sentence (the MT115 message)."""
        before = self.step * self.timestep_ms
        if self.end_step is None:
            fate = "and the motion never ends"
        else:
            fate = f"and the motion ends only at step {self.end_step}, not at step {self.step + 1}"
        return (
            f"at a {self.timestep_ms} ms time step the playback time passes {INT_MAX} ms, the"
            f" most Webots' int holds, after {before} ms, before the motion ends at"
            f" {self.duration_ms} ms: it wraps to {self.wrapped_ms} ms, Webots sends the first"
            f" pose's values again {fate}"
        )

    @property
    def hint(self) -> str:
        """How to fix it: end the motion by the last step a C int holds."""
        last = INT_MAX // self.timestep_ms * self.timestep_ms
        return f"end the motion by {last} ms (the last step before {INT_MAX} ms at this time step)"


def clock_overflow(duration_ms: int, timestep_ms: int) -> ClockOverflow | None:
    """How Webots' clock wraps while a motion of ``duration_ms`` plays forward every
    ``timestep_ms`` ms, or None where it ends before the clock passes 2147483647 ms."""
    _check(duration_ms, timestep_ms)
    steps = -(-duration_ms // timestep_ms)  # the step at which it would end without a wrap
    if steps * timestep_ms <= INT_MAX:
        return None
    return ClockOverflow(
        duration_ms,
        timestep_ms,
        steps - 1,
        wrap_int(steps * timestep_ms),
        end_step(duration_ms, timestep_ms),
    )


class PlaybackNeverEndsError(MotionToolError):
    """A whole command stream was asked of a motion that never stops at that time step (its
    clock wraps: :func:`clock_overflow`); :func:`motiontool.motionfmt.player.iter_commands`
    streams it step by step instead."""

    def __init__(self, overflow: ClockOverflow) -> None:
        super().__init__(overflow.message)
        self.overflow = overflow
