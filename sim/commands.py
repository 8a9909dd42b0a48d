"""The command stream of a run: the targets Webots' player holds at each control step while the
motions play one after another, then while the last targets are held."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.motionfmt import Motion, sample
from motiontool.motionfmt.player import Held, hold_targets

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["command_matrix"]


def command_matrix(
    motions: Sequence[Motion],
    joints: Sequence[str],
    timestep_ms: int,
    initial: npt.NDArray[np.float64],
    *,
    reverse: bool = False,
    loops: int = 1,
    hold_steps: int = 0,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_], list[int], list[str]]:
    """The targets in force at each control step of the sequence ``motions``.

    Args:
        motions: played one after another; each starts at the step after the previous ends.
        joints: the robot's J motors.
        timestep_ms: control step, ms.
        initial: (J,) positions the motors hold before their first command, rad (m).
        reverse, loops: Webots' reverse and loop modes, applied to each motion.
        hold_steps: steps appended after the last motion, with no command.

    Returns:
        targets (S, J) float64 (a step without a command keeps the previous target; before the
        first, ``initial``), commanded (S, J) bool (the motion sent a target at that step), the
        number of steps of each motion, and the motion columns that are not motors (ignored,
        as Webots does, with a warning).
    """
    import numpy as np

    streams = [sample(m, timestep_ms, reverse=reverse, loops=loops) for m in motions]
    motors = set(joints)
    ignored = list(dict.fromkeys(n for s in streams for n in s.joints if n not in motors))
    idle = np.zeros((hold_steps, len(joints)), dtype=np.bool_)  # the hold steps send nothing
    chunks = [(s.targets, s.commanded, s.joints) for s in streams]
    chunks.append((np.full(idle.shape, np.nan), idle, tuple(joints)))
    held: list[Held] = []
    for targets, sent, names in chunks:  # each goes on from what the one before left held
        start = held[-1].targets[-1] if held else initial
        held.append(hold_targets(targets, sent, names, joints, initial=start))
    targets = np.concatenate([h.targets for h in held])
    commanded = np.concatenate([h.sent for h in held])
    if not bool(np.isfinite(targets[commanded]).all()):  # the files are checked first: see play()
        raise MotionToolError("a motion commands a non-finite target (nan or inf): not played")
    lengths = [len(s.elapsed_ms) for s in streams]
    return targets, commanded, lengths, ignored
