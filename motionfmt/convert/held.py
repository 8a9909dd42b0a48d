"""The targets each motor holds while Webots plays a motion, step by step, and the fewest
keys that a straight-line interpolation needs to give them back: what the robot formats
(NAOqi, URScript, ROS) reproduce. The formats make the stream a chunk of steps at a time
(:func:`held_chunks`, :class:`Corners`), as often as they read it: never held whole, whatever
the motion's duration; :func:`held_stream` holds it, for the tests and small motions.

Webots' player sends a target at every control step where a segment's two ends are numbers
and nothing where one is ``*``; a motor keeps its last target until it gets another. So the
stream to reproduce is :func:`~motiontool.motionfmt.player.hold_targets` of
:func:`~motiontool.motionfmt.player.sample`: per motor, from its first command on, a target at
every step, piecewise linear in time (corners at the poses, a jump where a ``*`` stretch ends).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.motionfmt.convert.base import StreamChunk
from motiontool.motionfmt.nonfinite import refuse_non_finite
from motiontool.motionfmt.player import (
    Holder,
    iter_commands,
    played_steps,
    require_held,
    steps_span,
)

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = [
    "COLLINEAR_RAD",
    "MAX_EXPORT_STEPS",
    "Corners",
    "HeldStream",
    "corner_keys",
    "held_chunks",
    "held_stream",
]


COLLINEAR_RAD = 1e-12
"""How far (rad, m for linear joints) a target may sit off the line between its neighbours
and still be left out of the keys: floating-point rounding of Webots' interpolation only
(a few units in the last place of joint angles of a few radians, ~1e-16 rad)."""


MAX_EXPORT_STEPS = 2_000_000
"""Most control steps a robot export makes (11 h at the Nao's 20 ms): NAOqi's and a ROS
trajectory's memory stays flat, but a longer stream would compute for hours, and a bag or a
URScript program holds a message or a line a step; it is refused in one line before it
starts, as a run that long is (``sim.commands.MAX_RUN_STEPS``)."""


_CHUNK_STEPS = 1 << 13
"""Steps of the command stream made at once (:func:`held_chunks`)."""


@dataclass(frozen=True)
class HeldStream:
    """What each motor holds at each control step.

    Attributes:
        motors: the N motor names (a name two columns share once, as the robot has it).
        elapsed_ms: int64 (S,): Webots' playback time of each step, ms.
        targets: float64 (S, N): the target each motor holds, rad (m); NaN before its first
            command.
    """

    motors: tuple[str, ...]
    elapsed_ms: npt.NDArray[np.int64]
    targets: npt.NDArray[np.float64]


def held_chunks(
    motion: Motion, timestep_ms: int
) -> tuple[tuple[str, ...], Callable[[], Iterator[StreamChunk]]]:
    """The motors (a name two columns share once, as the robot has it) and what makes the
    targets they hold while Webots plays ``motion`` at ``timestep_ms`` (ms), a chunk of steps
    at a time, each time it is called: (elapsed_ms int64 (S,), targets float64 (S, N), rad or
    m, NaN before a motor's first command). Nothing the stream's size is held.

    Raises:
        NonFiniteCommandError: a ``nan`` or ``inf`` command (a robot cannot be sent it).
        PlaybackNeverEndsError: the motion never ends at this step (Webots' clock wraps).
        MotionToolError: more than :data:`MAX_EXPORT_STEPS` steps.
    """
    refuse_non_finite(motion)
    steps = played_steps(motion.duration_ms, timestep_ms)
    if steps > MAX_EXPORT_STEPS:
        raise MotionToolError(
            f"the stream an export sends: {steps_span(steps, timestep_ms)}, more than the "
            f"{MAX_EXPORT_STEPS:,} an export makes (it would compute for hours); trim the "
            "motion first (motiontool trim)"
        )
    motors = tuple(dict.fromkeys(motion.joints))

    def chunks() -> Iterator[StreamChunk]:
        holder = Holder(motors)
        for chunk in iter_commands(motion, timestep_ms, chunk_steps=_CHUNK_STEPS):
            held = holder.hold(chunk.targets, chunk.commanded, motion.joints).targets
            yield chunk.elapsed_ms, held

    return motors, chunks


def held_stream(motion: Motion, timestep_ms: int) -> HeldStream:
    """The targets the motors hold while Webots plays ``motion`` at ``timestep_ms`` (ms),
    held whole (:func:`held_chunks`, past :data:`~.player.MAX_HELD_STEPS` refused).

    Raises:
        NonFiniteCommandError: a ``nan`` or ``inf`` command (a robot cannot be sent it).
        PlaybackNeverEndsError: the motion never ends at this step (Webots' clock wraps).
        StreamTooLongError: more than :data:`~.player.MAX_HELD_STEPS` steps.
    """
    import numpy as np

    motors, chunks = held_chunks(motion, timestep_ms)
    steps = played_steps(motion.duration_ms, timestep_ms)
    require_held(steps, timestep_ms)
    elapsed = np.empty(steps, dtype=np.int64)
    targets = np.empty((steps, len(motors)))
    at = 0
    for chunk_elapsed, chunk_targets in chunks():
        end = at + chunk_elapsed.shape[0]
        elapsed[at:end] = chunk_elapsed
        targets[at:end] = chunk_targets
        at = end
    return HeldStream(motors, elapsed[:at], targets[:at])


class Corners:
    """:func:`corner_keys` of samples given a chunk at a time: the times and values of the
    keys, the same as of the samples given at once. The last two samples are carried to the
    next chunk (a sample is a key by its two neighbours)."""

    def __init__(self) -> None:
        import numpy as np

        self.count = 0
        self._at: list[npt.NDArray[np.int64]] = []  # the keys found, a chunk at a time
        self._values: list[npt.NDArray[np.float64]] = []
        self._tail = (np.zeros(0, dtype=np.int64), np.zeros(0))  # the last two samples

    def add(self, at: npt.NDArray[np.int64], values: npt.NDArray[np.float64]) -> None:
        """Take the samples at the times ``at`` (S,) (after every earlier one) of ``values``
        (S,) float64, all finite."""
        import numpy as np

        if at.shape[0] == 0:
            return
        if self.count == 0:  # the first sample is a key
            self._at.append(at[:1])
            self._values.append(values[:1])
        w_at = np.concatenate((self._tail[0], at))
        w = np.concatenate((self._tail[1], values))
        inner = corner_keys(w)[1:-1]  # w[0] is a key already or decided; w[-1] is not yet
        self._at.append(w_at[inner])
        self._values.append(w[inner])
        self._tail = (w_at[-2:], w[-2:])
        self.count += at.shape[0]

    def keys(self) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.float64]]:
        """The keys' times (K,) and values (K,) once every sample is in: the first, the
        last, and every one off the line between its two neighbours."""
        import numpy as np

        last = (self._tail[0][-1:], self._tail[1][-1:]) if self.count >= 2 else ((), ())
        at = np.concatenate([*self._at, last[0]]).astype(np.int64)
        return at, np.concatenate([*self._values, last[1]]).astype(np.float64)


def corner_keys(values: npt.NDArray[np.float64]) -> npt.NDArray[np.intp]:
    """Indices of the samples (uniform in time) that straight lines between them need: the
    first and the last, and every one that is not on the line between its two neighbours (to
    within :data:`COLLINEAR_RAD`). ``values`` float64 (S,), all finite."""
    import numpy as np

    n = values.shape[0]
    if n <= 2:
        return np.arange(n)
    off = np.abs(values[1:-1] - (values[:-2] + values[2:]) / 2.0)
    inner = np.nonzero(off > COLLINEAR_RAD)[0] + 1
    return np.concatenate(([0], inner, [n - 1]))
