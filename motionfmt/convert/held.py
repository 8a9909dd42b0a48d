"""The targets each motor holds while Webots plays a motion, step by step, and the fewest
keys that a straight-line interpolation needs to give them back: what the robot formats
(NAOqi, URScript) reproduce.

Webots' player sends a target at every control step where a segment's two ends are numbers
and nothing where one is ``*``; a motor keeps its last target until it gets another. So the
stream to reproduce is :func:`~motiontool.motionfmt.player.hold_targets` of
:func:`~motiontool.motionfmt.player.sample`: per motor, from its first command on, a target at
every step, piecewise linear in time (corners at the poses, a jump where a ``*`` stretch ends).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.motionfmt.nonfinite import refuse_non_finite
from motiontool.motionfmt.player import Holder, iter_commands, played_steps, require_held

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = ["COLLINEAR_RAD", "HeldStream", "corner_keys", "held_stream"]

COLLINEAR_RAD = 1e-12
"""How far (rad, m for linear joints) a target may sit off the line between its neighbours
and still be left out of the keys: floating-point rounding of Webots' interpolation only
(a few units in the last place of joint angles of a few radians, ~1e-16 rad)."""


_CHUNK_STEPS = 1 << 13
"""Steps of the command stream made at once while :func:`held_stream` holds it."""


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


def held_stream(motion: Motion, timestep_ms: int) -> HeldStream:
    """The targets the motors hold while Webots plays ``motion`` at ``timestep_ms`` (ms).

    Raises:
        NonFiniteCommandError: a ``nan`` or ``inf`` command (a robot cannot be sent it).
        PlaybackNeverEndsError: the motion never ends at this step (Webots' clock wraps).
    """
    import numpy as np

    refuse_non_finite(motion)
    steps = played_steps(motion.duration_ms, timestep_ms)
    require_held(steps, timestep_ms)
    motors = tuple(dict.fromkeys(motion.joints))
    elapsed = np.empty(steps, dtype=np.int64)
    targets = np.empty((steps, len(motors)))
    holder = Holder(motors)
    at = 0
    # A chunk of the stream at a time: only the held targets are the stream's size.
    for chunk in iter_commands(motion, timestep_ms, chunk_steps=_CHUNK_STEPS):
        end = at + chunk.elapsed_ms.shape[0]
        elapsed[at:end] = chunk.elapsed_ms
        targets[at:end] = holder.hold(chunk.targets, chunk.commanded, motion.joints).targets
        at = end
    return HeldStream(motors, elapsed[:at], targets[:at])


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
