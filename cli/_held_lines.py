"""What ``motiontool plot`` draws dotted: a joint's held target where its column sends no
command (``*``), joined to the last commanded step before each such span.

The command stream is read a chunk of steps at a time, and each line keeps only the points
that shape it: of a run of equal targets its two ends, of a run of steps with nothing to draw
its first. The lines are the same as through every step, and what is held does not grow with
the motion's duration (a plot is one picture, whatever the length).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from motiontool.motionfmt.player import Holder, commands_at
from motiontool.motionfmt.units import MS_PER_S

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

    Line = tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]
    """(x: playback time, s; y: target, rad or m; NaN breaks the line)."""

__all__ = ["held_lines"]

_CHUNK_STEPS = 1 << 14
"""Steps of the stream read at once."""


def held_lines(motion: Motion, timestep_ms: int) -> list[Line]:
    """Per column of ``motion``, the dotted line of its held target at the steps of a
    controller stepping every ``timestep_ms`` (0 to the first multiple at or after the last
    pose): where the column sends no command, and at the step before."""
    import numpy as np

    names = tuple(dict.fromkeys(motion.joints))
    motor = [names.index(j) for j in motion.joints]
    steps = -(-motion.duration_ms // timestep_ms) + 1
    pieces: list[list[Line]] = [[] for _ in motion.joints]
    holder = Holder(names)
    for lo in range(0, steps, _CHUNK_STEPS):
        hi = min(lo + _CHUNK_STEPS, steps)
        ahead = min(hi + 1, steps)  # one step more: whether the next one sends a command
        elapsed = np.arange(lo, ahead, dtype=np.int64) * timestep_ms
        targets, sent = commands_at(motion, elapsed)
        n = hi - lo
        held = holder.hold(targets[:n], sent[:n], motion.joints)
        x = elapsed[:n] / MS_PER_S
        for col, k in enumerate(motor):
            after = sent[1 : n + 1, col] if ahead > hi else np.append(sent[1:n, col], True)
            drawn = ~sent[:n, col] | ~after  # no command here, or none at the next step
            y = np.where(drawn, held.targets[:, k], np.nan)
            keep = _shaping(y)
            pieces[col].append((x[keep], y[keep]))
    return [
        (np.concatenate([p[0] for p in col]), np.concatenate([p[1] for p in col])) for col in pieces
    ]


def _shaping(y: npt.NDArray[np.float64]) -> npt.NDArray[np.intp]:
    """Indices of the points of ``y`` (evenly spaced, NaN: a break) that a line through all of
    them needs: both ends, and every point that is not inside a run of equal values or
    (NaN) that follows a NaN."""
    import numpy as np

    if y.shape[0] <= 2:
        return np.arange(y.shape[0])
    mid, before, after = y[1:-1], y[:-2], y[2:]
    flat = (mid == before) & (mid == after)  # never true of a NaN
    gap = np.isnan(mid) & np.isnan(before)
    inner = np.flatnonzero(~(flat | gap)) + 1
    return np.concatenate(([0], inner, [y.shape[0] - 1]))
