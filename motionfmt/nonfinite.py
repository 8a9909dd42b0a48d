"""The one check for joint commands that are not finite numbers (MT113).

Webots sends a ``nan`` or ``inf`` cell to the motor as it is. Nothing that writes or edits a
motion passes one on: the writer has no spelling for it, and an edit could not say what it
commands. :func:`refuse_non_finite` finds the first such command (pose by pose, then column by
column) and raises :class:`NonFiniteCommandError` at its cell.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from motiontool.errors import MotionSyntaxError

if TYPE_CHECKING:
    from motiontool.motionfmt.motion import Motion
    from motiontool.motionfmt.reader import ReadResult

__all__ = ["NonFiniteCommandError", "refuse_non_finite"]


class NonFiniteCommandError(MotionSyntaxError):
    """A joint command that is ``nan`` or ``inf`` (MT113).

    Prints as ``path:line:col: message`` when the motion was read from a file. A motion built in
    memory has no cell to point at: its message names the pose time instead, ``located`` is
    False and ``path`` is ``'<motion>'``.

    Attributes:
        joint: the column's joint name.
        value: the command: ``nan``, ``inf`` or ``-inf``.
        time_ms: its pose's time, ms.
        located: whether ``path``, ``line`` and ``column`` point at the cell in a file.
    """

    def __init__(
        self,
        message: str,
        path: str | None = None,
        line: int = 1,
        column: int = 1,
        *,
        joint: str = "",
        value: float = math.nan,
        time_ms: int = 0,
    ) -> None:
        super().__init__(message, "<motion>" if path is None else path, line, column)
        self.located = path is not None
        self.joint = joint
        self.value = value
        self.time_ms = time_ms

    def __str__(self) -> str:
        return super().__str__() if self.located else self.message


def refuse_non_finite(motion: Motion, read: ReadResult | None = None, before: str = "") -> None:
    """Raise :class:`NonFiniteCommandError` at ``motion``'s first commanded ``nan`` / ``inf``.

    Args:
        motion: the motion; cells that are not commanded (``*``) are not looked at.
        read: what ``motion`` was read from (a
            :class:`~motiontool.motionfmt.reader.ReadResult`): the error points at the cell's
            line and column, and says to fix it before ``before`` (``'mirroring'``). Without it
            (a motion built in memory, about to be written) the error names the pose time.
        before: what the caller was about to do, for the located message.
    """
    import numpy as np

    bad = np.argwhere(motion.commanded & ~np.isfinite(motion.values))
    if not bad.shape[0]:
        return
    p, j = (int(x) for x in bad[0])
    joint, value, time_ms = motion.joints[j], float(motion.values[p, j]), int(motion.times_ms[p])
    if read is None:
        raise NonFiniteCommandError(
            f"cannot write {joint} = {value!r} at {time_ms} ms: a joint command must be a finite"
            " number",
            joint=joint,
            value=value,
            time_ms=time_ms,
        )
    line, column, _ = read.cell_span(p, j)
    raise NonFiniteCommandError(
        f"{joint} = {value!r} is not a finite number (MT113): write a number, or '*' for no"
        f" command, before {before}",
        read.path,
        line,
        column,
        joint=joint,
        value=value,
        time_ms=time_ms,
    )
