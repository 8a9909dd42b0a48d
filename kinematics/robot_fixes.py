"""The unsafe fixes that need the robot (:data:`motiontool.motionfmt.fixes.ROBOT_CODES`).

Both change what the robot does, to what the file evidently means on this robot:

- MT302: a value past its joint's limit becomes the limit. Webots clamps the target there
  anyway, so the file then says what the motor does (the command stream changes: the target
  sent is the limit, not the value past it).
- MT303: the segments too fast for a joint's maxVelocity are stretched to the shortest whole
  ms that is not, as ``retime`` fits a motion to its robot
  (:func:`motiontool.motionfmt.retime.fit_limits`, its default margin): later poses move
  later; values never change.

Each is planned on the file's bytes as cell edits (:class:`~motiontool.motionfmt.fixes.Fix`),
the rest of every line kept as it is spelt.
"""

from __future__ import annotations

import math
from bisect import bisect_left, bisect_right
from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING, NamedTuple, cast

from motiontool.kinematics.robot_spec import RobotSpec
from motiontool.motionfmt.diagnostics import BEYOND_LIMITS, TOO_FAST
from motiontool.motionfmt.fixes import ROBOT_CODES, Fix
from motiontool.motionfmt.reader import ReadResult, read_bytes

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["Planner", "clamp_count", "clamp_fixes", "planner", "stretch_fixes"]

CLAMP_TITLE = "clamp the value to the joint's limit (where the motor stops anyway)"
STRETCH_TITLE = "stretch the segments too fast for maxVelocity, as retime fits a motion"
TITLES = {BEYOND_LIMITS: CLAMP_TITLE, TOO_FAST: STRETCH_TITLE}
"""What the fix of each of :data:`~motiontool.motionfmt.fixes.ROBOT_CODES` does, for people."""
_CELLS = 1 << 16
"""Clamped cells whose numbers become Python objects at a time (a file of random values has
millions)."""


class _Cells(NamedTuple):
    """The cells an MT302 fix clamps: file column, pose (from ``first``) and the limit each
    becomes, listed joint by joint."""

    first: int
    cols: npt.NDArray[np.int32]
    poses: npt.NDArray[np.intp]
    bounds: npt.NDArray[np.float64]


def _clamped_cells(
    result: ReadResult,
    spec: RobotSpec,
    joint: str | None,
    lines: tuple[int, int] | None,
    past: float | None,
) -> _Cells | None:
    """The cells :func:`clamp_fixes` clamps (its arguments), or None: no joint checked."""
    import numpy as np

    poses = slice(None)
    if lines is not None:
        pose_lines = result.pose_lines
        poses = slice(bisect_left(pose_lines, lines[0]), bisect_right(pose_lines, lines[1]))
    rows = result.motion.values[poses]
    found = []  # (column, poses, bounds) of each joint's cells past a limit
    for j, name in enumerate(result.joints):
        if name not in spec or (joint is not None and name != joint):
            continue
        limit = spec.joint(name)
        column = rows[:, j]
        with np.errstate(invalid="ignore"):
            above, below = column > limit.upper, column < limit.lower
        if past is not None:
            above, below = (above, below & False) if past > limit.upper else (above & False, below)
        at = np.flatnonzero(np.isfinite(column) & (above | below))
        found.append((j, at, np.where(column[at] > limit.upper, limit.upper, limit.lower)))
    if not found:
        return None
    return _Cells(
        poses.start or 0,
        np.concatenate([np.full(at.shape, j, dtype=np.int32) for j, at, _b in found]),
        np.concatenate([at for _j, at, _b in found]),
        np.concatenate([b for _j, _at, b in found]),
    )


def clamp_count(
    result: ReadResult,
    spec: RobotSpec,
    *,
    joint: str | None = None,
    lines: tuple[int, int] | None = None,
    past: float | None = None,
) -> int:
    """How many edits :func:`clamp_fixes` makes (its arguments), without making them."""
    cells = _clamped_cells(result, spec, joint, lines, past)
    return 0 if cells is None else int(cells.cols.shape[0])


def clamp_fixes(
    result: ReadResult,
    spec: RobotSpec,
    *,
    joint: str | None = None,
    lines: tuple[int, int] | None = None,
    past: float | None = None,
) -> list[Fix]:
    """MT302: each finite value of a motor past its limit becomes the limit (``repr``); only
    ``joint``'s cells (every column that names it), only on ``lines`` (first, last) and only
    those past the same limit as the value ``past``, where given."""
    import numpy as np

    cells = _clamped_cells(result, spec, joint, lines, past)
    if cells is None:
        return []
    first, cols, poses_at, bounds = cells
    # Made pose by pose (cell_span tokenises a pose's line once and keeps only a few poses),
    # listed joint by joint.
    fixes: list[Fix | None] = [None] * cols.shape[0]
    said: dict[tuple[int, float], tuple[str, bytes, str]] = {}  # one text per joint and bound
    order = np.argsort(poses_at, kind="stable")
    for lo in range(0, order.shape[0], _CELLS):  # Python numbers for a block of cells at a time
        k = order[lo : lo + _CELLS]
        js = cols[k].tolist()
        spans = result.cell_spans((first + poses_at[k]).tolist(), js)
        for i, j, bound, (line, start, end) in zip(
            k.tolist(), js, bounds[k].tolist(), spans, strict=True
        ):
            if (j, bound) not in said:
                name = result.joints[j]
                title = f"{CLAMP_TITLE}: {name} = {bound!r} {spec.joint(name).unit}"
                said[j, bound] = (name, repr(bound).encode(), title)
            name, text, title = said[j, bound]
            fixes[i] = Fix(BEYOND_LIMITS, line, start, end, text, False, title, name)
    return cast("list[Fix]", fixes)  # every entry was set


def stretch_fixes(
    data: bytes, path: str, result: ReadResult, spec: RobotSpec, step_ms: int | None = None
) -> list[Fix]:
    """MT303: the new time of every pose that moves, written in the file's time style; none
    for a motion with a nan/inf command (it has no speed to fit: MT113 first), or one whose
    stretched times would pass the longest a ``.motion`` file holds. A stretched segment that
    was a whole number of controller steps (``step_ms``, ms; None: whole ms) stays one, so the
    fix brings no MT209."""
    import numpy as np

    # A clean file needs neither the retimer nor the document that writes the new times.
    from motiontool.motionfmt.document import MotionDocument
    from motiontool.motionfmt.retime import TimeOverflowError, fit_limits

    motion = result.motion
    if not bool(np.isfinite(motion.values[motion.commanded]).all()):
        return []
    limits = {j.name: j.max_velocity for j in spec.joints if math.isfinite(j.max_velocity)}
    times = [int(t) for t in result.times_ms]
    try:
        fitted = fit_limits(times, result.joints, result.motion.values, limits, step_ms=step_ms)
    except TimeOverflowError:  # the stretched motion would not fit in Webots' time: no fix
        return []
    if list(fitted.times_ms) == times:
        return []
    doc = MotionDocument(data, path)
    doc.set_times(list(fitted.times_ms))
    new_lines = doc.to_bytes().split(b"\n")
    moved = [
        p for p, (old, new) in enumerate(zip(times, fitted.times_ms, strict=True)) if old != new
    ]
    cells: list[int | None] = [None] * len(moved)  # the time cells, in the file and edited
    fixes = []
    for (line, start, end), (_line, a, b) in zip(
        result.cell_spans(moved, cells), doc.result.cell_spans(moved, cells), strict=True
    ):
        text = new_lines[line - 1][a - 1 : b - 1]
        fixes.append(Fix(TOO_FAST, line, start, end, text, False, STRETCH_TITLE))
    return fixes


class Planner(NamedTuple):
    """The robot fixes of ``codes`` for ``spec``
    (a :class:`~motiontool.motionfmt.fixes.RobotPlanner`): none for a file Webots rejects."""

    spec: RobotSpec
    path: str
    codes: frozenset[str] = ROBOT_CODES
    step_ms: int | None = None

    @property
    def titles(self) -> Mapping[str, str]:
        return TITLES

    def __call__(self, data: bytes) -> list[Fix]:
        result = read_bytes(data, self.path)
        if not result.accepted or not result.times_ms or not result.joints:
            return []
        return self._clamps(result) + self.stretch(data, result)

    def _clamps(self, result: ReadResult) -> list[Fix]:
        return clamp_fixes(result, self.spec) if BEYOND_LIMITS in self.codes else []

    def clamps(
        self, result: ReadResult, joint: str, lines: tuple[int, int], past: float | None
    ) -> list[Fix]:
        if BEYOND_LIMITS not in self.codes:
            return []
        return clamp_fixes(result, self.spec, joint=joint, lines=lines, past=past)

    def clamp_count(
        self, result: ReadResult, joint: str, lines: tuple[int, int], past: float | None
    ) -> int:
        if BEYOND_LIMITS not in self.codes:
            return 0
        return clamp_count(result, self.spec, joint=joint, lines=lines, past=past)

    def stretch(self, data: bytes, result: ReadResult) -> list[Fix]:
        if TOO_FAST not in self.codes:
            return []
        return stretch_fixes(data, self.path, result, self.spec, self.step_ms)


def planner(
    spec: RobotSpec, path: str, codes: Iterable[str] = ROBOT_CODES, *, step_ms: int | None = None
) -> Planner:
    """A planner of the fixes of ``codes`` (both by default) for ``spec``, for
    :func:`motiontool.motionfmt.fixes.fix_bytes` and the reports; stretches keep pose times
    on the controller's step ``step_ms`` (ms; None: whole ms)."""
    return Planner(spec, path, frozenset(codes), step_ms)
