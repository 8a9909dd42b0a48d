"""What the robot checks share: a file's poses against one robot's motors, and message pieces.

How a motion is read (the Webots player, ``docs/webots-format.md``): ``*`` sends no command, so the
joint holds its previous target; of two columns with one name (MT205), Webots sends both in
column order, so the later column's command wins where it sends one and the earlier's reaches the
motor where the later sends none. :class:`Table` merges such columns the same way
(:func:`~motiontool.motionfmt.player.hold_targets`), so the checks check what the motor is sent.
"""

from __future__ import annotations

import functools
import weakref
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple, Self, TypeVar

from motiontool.kinematics.checks.registry import CheckOptions
from motiontool.kinematics.checks.wording import PLAIN_WORDING, Wording
from motiontool.kinematics.robots import RobotSpec, fmt_name
from motiontool.motionfmt.diagnostics import Diagnostic, PoseFinding, Severity
from motiontool.motionfmt.findings import Findings
from motiontool.motionfmt.grouping import MAX_RUNS
from motiontool.motionfmt.player import Holder
from motiontool.motionfmt.reader import ReadResult

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

#: The cell type of a (P, K) table: float64 values or bool flags.
_Cell = TypeVar("_Cell", "np.float64", "np.bool_")

_HOLD_POSES = 1 << 14
"""Poses whose held targets are worked out at a time (:attr:`Table.held`)."""

__all__ = [
    "EPS",
    "PoseRuns",
    "RobotCheck",
    "Table",
    "WordedCheck",
    "cell",
    "configurations",
    "fmt_ms",
    "fmt_name",
    "fmt_num",
    "fmt_span",
    "header_diagnostic",
    "pose_runs",
    "read_table",
    "runs",
    "sent_cells",
    "settle_tables",
]

EPS = 1e-9
"""Slack on a comparison with a limit, for values that sit exactly at it: relative on velocities,
absolute (rad, m) on positions. It covers float rounding (a computed target one float step past
the limit it was written at), never a real excess."""


# --------------------------------------------------------------------------- message pieces


def fmt_num(x: float) -> str:
    return f"{x:.6g}"


def fmt_ms(x: float) -> str:
    return f"{x:.0f} ms" if float(x).is_integer() else f"{x:.1f} ms"


def fmt_span(names: Sequence[str]) -> str:
    """``RPhalanx1..8`` for numbered names with one stem, else the names comma-separated."""
    stem = names[0].rstrip("0123456789")
    if len(names) > 2 and all(n.startswith(stem) and n[len(stem) :].isdigit() for n in names):
        return f"{names[0]}..{names[-1][len(stem) :]}"
    return ", ".join(names)


def header_diagnostic(
    result: ReadResult,
    column: int,
    code: str,
    severity: Severity,
    message: str,
    hint: str | None = None,
) -> Diagnostic:
    """A diagnostic on header joint ``column`` (0-based) of ``result`` (line 1; its first
    column past the 4095 bytes of the header that Webots reads)."""
    spans = result.header_spans()
    start, end = spans[column] if column < len(spans) else (1, None)
    return Diagnostic(
        code=code,
        severity=severity,
        path=result.path,
        line=1,
        column=start,
        message=message,
        hint=hint,
        joint=result.joints[column],
        end_column=end,
    )


def runs(indices: Sequence[int], step: int) -> list[list[int]]:
    """Group sorted ``indices`` into runs of consecutive values ``step`` apart."""
    out: list[list[int]] = []
    for i in indices:
        if out and i - out[-1][-1] == step:
            out[-1].append(i)
        else:
            out.append([i])
    return out


class PoseRuns(NamedTuple):
    """Runs of consecutive poses (or segments) where a finding is, as arrays (R,): each run's
    first, last and worst index, how many indices it covers (``size``) and how many runs it
    stands for (1; more where :data:`~motiontool.motionfmt.grouping.MAX_RUNS` made them one)."""

    first: npt.NDArray[np.intp]
    last: npt.NDArray[np.intp]
    worst: npt.NDArray[np.intp]
    size: npt.NDArray[np.intp]
    runs: npt.NDArray[np.intp]


def pose_runs(mask: npt.NDArray[np.bool_], excess: npt.NDArray[np.float64]) -> PoseRuns:
    """The runs of consecutive True in ``mask`` (P,), the worst of each the first with the
    largest ``excess`` (P,) in it: what :func:`~motiontool.motionfmt.grouping.group_findings`
    makes one finding of (all of them one run, more than
    :data:`~motiontool.motionfmt.grouping.MAX_RUNS`). ``excess`` is a number (or inf)
    wherever ``mask`` holds."""
    import numpy as np

    edges = np.diff(mask.astype(np.int8), prepend=np.int8(0), append=np.int8(0))
    starts = np.flatnonzero(edges == 1)
    ends = np.flatnonzero(edges == -1) - 1
    if starts.size > MAX_RUNS:
        where = np.flatnonzero(mask)
        worst = where[np.argmax(excess[where])]
        one = np.ones(1, dtype=np.intp)
        return PoseRuns(starts[:1], ends[-1:], worst * one, where.size * one, starts.size * one)
    if starts.size == 0:
        return PoseRuns(starts, ends, starts, starts, starts)
    masked = np.where(mask, excess, -np.inf)
    run_max = np.maximum.reduceat(masked, starts)  # the gaps between runs hold -inf
    run_of = np.cumsum(edges[:-1] == 1) - 1  # the run each index is in (or follows)
    at_max = np.flatnonzero(mask & (masked == run_max[np.maximum(run_of, 0)]))
    _runs, first = np.unique(run_of[at_max], return_index=True)
    return PoseRuns(starts, ends, at_max[first], ends - starts + 1, np.ones_like(starts))


# --------------------------------------------------------------------------- the file's table


def sent_cells(defined: npt.NDArray[np.bool_]) -> npt.NDArray[np.bool_]:
    """(P, C) bool: the cell's value is sent to the motor at (or right after) its pose time: it
    is a number (``defined``, :attr:`ReadResult.commanded`: a 'nan' cell is a command, unlike
    '*') and the first or last pose, or a neighbouring pose's cell is a number too (Webots sends
    nothing over a segment that touches a '*')."""
    import numpy as np

    near = np.zeros_like(defined)
    near[[0, -1]] = True
    near[1:] |= defined[:-1]
    near[:-1] |= defined[1:]
    return defined & near


@dataclass
class Table:
    """A file's poses against one robot's motors, a column per motor the file names.

    Column k is motor ``motors[k]`` (an index in ``spec.joints``), named by the file's columns
    ``groups[k]`` (two or more where the header names the motor twice), in the order of the
    last of them. ``source[p, k]`` is the file column whose cell the motor gets at pose p: the
    last one that sends there, else the last one holding a number, else the last one.
    """

    result: ReadResult
    times: npt.NDArray[np.int64]  # (P,) ms
    raw: npt.NDArray[np.float64]  # (P, C) the file's cells, NaN for '*'
    raw_defined: npt.NDArray[np.bool_]  # (P, C) the cell holds a number (a command)
    raw_sent: npt.NDArray[np.bool_]  # (P, C) the cell is sent (:func:`sent_cells`)
    motors: list[int]
    groups: list[list[int]]
    source: npt.NDArray[np.intp]  # (P, K) file column

    def settle(self) -> None:
        """Drop the arrays derived for the checks (made again if asked for): what the findings
        made later keep is the values, the times and the columns."""
        for name in ("held", "commanded", "defined"):
            self.__dict__.pop(name, None)

    def col(self, pose: int, k: int) -> int:
        """The file column of motor ``k``'s cell at ``pose``."""
        return int(self.source[pose, k])

    def _at_source(self, cells: npt.NDArray[_Cell]) -> npt.NDArray[_Cell]:
        """(P, K) ``cells`` of the file column each motor gets; ``cells`` itself (no copy) where
        that is every file column, once, in order (every joint of the file is a motor)."""
        import numpy as np

        row = self.source[0] if self.source.shape[0] else None
        if (
            row is not None
            and self.source.strides[0] == 0  # one row for every pose (:func:`_sources`)
            and np.array_equal(row, np.arange(cells.shape[1]))
        ):
            return cells
        return np.take_along_axis(cells, self.source, axis=1)

    @functools.cached_property
    def values(self) -> npt.NDArray[np.float64]:
        """(P, K) float64: each motor's cell value (rad, m for linear joints), NaN for '*'."""
        return self._at_source(self.raw)

    @functools.cached_property
    def defined(self) -> npt.NDArray[np.bool_]:
        """(P, K) bool: a column of the motor holds a number (a command) at the pose."""
        return self._at_source(self.raw_defined)

    @functools.cached_property
    def commanded(self) -> npt.NDArray[np.bool_]:
        """(P, K) bool: a column of the motor sends its value at (or right after) the pose
        (:func:`sent_cells`)."""
        return self._at_source(self.raw_sent)

    @functools.cached_property
    def held(self) -> npt.NDArray[np.float64]:
        """(P, K) float64: each motor's target at each pose, its last commanded value where no
        column sends one, NaN before the motion first commands it."""
        import numpy as np

        names = [self.result.joints[group[-1]] for group in self.groups]
        held = np.empty((self.raw.shape[0], len(names)))
        holder = Holder(names)
        for lo in range(0, held.shape[0], _HOLD_POSES):  # each block goes on from the last
            hi = lo + _HOLD_POSES
            part = holder.hold(self.raw[lo:hi], self.raw_sent[lo:hi], self.result.joints)
            held[lo:hi] = part.targets
        return held

    def segments(
        self, lo: int = 0, hi: int | None = None
    ) -> tuple[npt.NDArray[np.intp], npt.NDArray[np.bool_]]:
        """Which file column drives each motor over keyframe segments ``lo`` to ``hi - 1``
        (segment s goes from pose s to pose s + 1; all P - 1 by default): (S, K) the last
        column with a number at both ends (Webots interpolates it, and it wins), and (S, K)
        bool whether one does."""
        import numpy as np

        hi = self.times.shape[0] - 1 if hi is None else hi
        both = self.raw_defined[lo:hi] & self.raw_defined[lo + 1 : hi + 1]
        driver = np.zeros((both.shape[0], len(self.groups)), dtype=np.intp)
        driven = np.zeros(driver.shape, dtype=np.bool_)
        for k, group in enumerate(self.groups):
            for c in group:
                driver[both[:, c], k] = c
                driven[:, k] |= both[:, c]
        return driver, driven

    def segment_values(
        self,
        lo: int = 0,
        hi: int | None = None,
        driving: tuple[npt.NDArray[np.intp], npt.NDArray[np.bool_]] | None = None,
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """(start, end) values (S, K) of each motor's keyframe segments ``lo`` to ``hi - 1``
        (all by default) from the column that drives it (:meth:`segments`, or ``driving``
        where the caller has it), NaN where none does."""
        import numpy as np

        hi = self.times.shape[0] - 1 if hi is None else hi
        driver, driven = self.segments(lo, hi) if driving is None else driving
        start = np.take_along_axis(self.raw[lo:hi], driver, axis=1)
        end = np.take_along_axis(self.raw[lo + 1 : hi + 1], driver, axis=1)
        idle = ~driven
        start[idle] = np.nan
        end[idle] = np.nan
        return start, end


def _sources(
    defined: npt.NDArray[np.bool_], sent: npt.NDArray[np.bool_], groups: list[list[int]]
) -> npt.NDArray[np.intp]:
    """(P, K) :attr:`Table.source`: per motor, the last column that sends at the pose, else
    the last one that holds a number there, else the last one. Where every motor has one
    column (no joint named twice), a read-only view of one row: no memory per pose."""
    import numpy as np

    if all(len(group) == 1 for group in groups):
        row = np.array([group[0] for group in groups], dtype=np.intp)
        return np.broadcast_to(row, (defined.shape[0], len(groups)))
    source = np.empty((defined.shape[0], len(groups)), dtype=np.intp)
    for k, group in enumerate(groups):
        source[:, k] = group[-1]
        for mask in (defined, sent):  # later passes and later columns take precedence
            for c in group:
                source[mask[:, c], k] = c
    return source


def read_table(result: ReadResult, motor_index: dict[str, int]) -> Table:
    """``result``'s poses against the robot whose motor indices ``motor_index`` gives."""
    import numpy as np

    by_name: dict[str, list[int]] = {}
    for j, name in enumerate(result.joints):
        if name in motor_index:
            by_name.setdefault(name, []).append(j)
    groups = sorted(by_name.values(), key=lambda group: group[-1])
    defined = result.commanded
    sent = sent_cells(defined)
    return Table(
        result=result,
        times=np.asarray(result.times_ms, dtype=np.int64),
        raw=result.values,
        raw_defined=defined,
        raw_sent=sent,
        motors=[motor_index[result.joints[group[-1]]] for group in groups],
        groups=groups,
        source=_sources(defined, sent, groups),
    )


def cell(
    table: Table,
    code: str,
    severity: Severity,
    pose: int,
    col: int | None,
    message: str,
    hint: str | None = None,
    *,
    time_ms: int | None = None,
    grouping: PoseFinding | None = None,
) -> Diagnostic:
    """A diagnostic on the cell of ``pose`` in file column ``col`` (its time token if None);
    ``grouping``: what lets it be grouped with the same finding at the next poses."""
    result = table.result
    line, column, end = result.cell_span(pose, col)
    return Diagnostic(
        code=code,
        severity=severity,
        path=result.path,
        line=line,
        column=column,
        message=message,
        hint=hint,
        joint=None if col is None else result.joints[col],
        time_ms=int(table.times[pose]) if time_ms is None else time_ms,
        end_column=end,
        pose=grouping,
    )


def configurations(
    table: Table, spec: RobotSpec, lo: int = 0, hi: int | None = None
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Whole-robot configurations at keyframes ``lo`` to ``hi - 1`` (all by default) and the
    segment midpoints after each, in that order.

    Returns (Q (R, M) float64 in ``spec.joints`` order, times (R,) float64 ms): row 2i is pose
    lo + i, row 2i+1 halfway to the next pose (none after the last pose of the file); over the
    whole file, R = 2P - 1 and row r is configuration r. Held targets where no column sends a
    command, 0 for a joint not commanded yet or not in the file, everything clamped to the
    motor limits.
    """
    import numpy as np

    n_poses = table.times.shape[0]
    hi = n_poses if hi is None else min(hi, n_poses)
    seg_hi = min(hi, n_poses - 1)  # the segments lo .. seg_hi - 1 have their midpoint here
    held = table.held
    mid, end = table.segment_values(lo, seg_hi)
    # 1e308 + 1e308 overflows to inf: clipped to the limit below, as the midpoint would be.
    with np.errstate(over="ignore"):
        mid += end
    mid /= 2.0
    np.copyto(mid, held[lo:seg_hi], where=np.isnan(mid))
    del end
    q = np.zeros((hi - lo + seg_hi - lo, len(spec.joints)))
    q[0::2, table.motors] = np.nan_to_num(held[lo:hi], nan=0.0)
    q[1::2, table.motors] = np.nan_to_num(mid, nan=0.0)
    lower = np.array([j.lower for j in spec.joints])
    upper = np.array([j.upper for j in spec.joints])
    np.clip(q, lower, upper, out=q)
    times = np.empty(q.shape[0])
    times[0::2] = table.times[lo:hi]
    times[1::2] = (table.times[lo:seg_hi] + table.times[lo + 1 : seg_hi + 1]) / 2.0
    return q, times


class RobotCheck:
    """Shared state of one robot's checks: the spec and its motor lookup."""

    def __init__(self, spec: RobotSpec) -> None:
        self.spec = spec
        self.motor_index = {name: i for i, name in enumerate(spec.joint_names)}

    @classmethod
    def for_run(cls, spec: RobotSpec, options: CheckOptions) -> Self:
        """The check of ``spec`` in a run (:mod:`~motiontool.kinematics.checks.registry`):
        made from the robot alone, unless the check takes one of the run's ``options``."""
        return cls(spec)

    def table(self, result: ReadResult) -> Table:
        """``result``'s table against this robot: built once for all the checks of one robot
        on one file (:class:`_LastTables`), and shared by the findings they make later."""
        return _LAST_TABLES.get(result, self.spec.name, self.motor_index)


class WordedCheck(RobotCheck):
    """A robot check whose hints say how to fix what it finds in the front end's words
    (:class:`~motiontool.kinematics.checks.wording.Wording`): plain words by default."""

    def __init__(self, spec: RobotSpec, wording: Wording = PLAIN_WORDING) -> None:
        super().__init__(spec)
        self.wording = wording

    @classmethod
    def for_run(cls, spec: RobotSpec, options: CheckOptions) -> Self:
        """The check of ``spec``, its hints in the run's words."""
        return cls(spec, options.wording)


class _LastTables:
    """The tables of the file being checked, by robot name: the checks of a file run one after
    another, so the last file's are the only ones kept here (its findings keep theirs)."""

    def __init__(self) -> None:
        self._result: weakref.ref[ReadResult] | None = None
        self._tables: dict[str, Table] = {}

    def get(self, result: ReadResult, robot: str, motor_index: dict[str, int]) -> Table:
        if self._result is None or self._result() is not result:
            self._result, self._tables = weakref.ref(result), {}
        table = self._tables.get(robot)
        if table is None:
            table = self._tables[robot] = read_table(result, motor_index)
        return table

    def settle(self) -> None:
        """The checks of the file are done: its tables drop what only the checks used (the
        findings still to be made need the values, times and columns only)."""
        for table in self._tables.values():
            table.settle()


_LAST_TABLES = _LastTables()


def settle_tables() -> None:
    """Tell the shared tables that the checks of the file are done (:meth:`_LastTables.settle`)."""
    _LAST_TABLES.settle()


class Groupable:
    """Checks that give their findings one per pose (``__call__``) or with their runs of
    consecutive per-pose findings already grouped (:meth:`grouped`), as
    :func:`~motiontool.motionfmt.grouping.group_findings` would group them. Subclasses write
    :meth:`_check`."""

    def __call__(self, result: ReadResult) -> Findings:
        return self._check(result, group=False)

    def grouped(self, result: ReadResult) -> Findings:
        """The findings with the runs already grouped (the others one per pose)."""
        return self._check(result, group=True)

    def _check(self, result: ReadResult, *, group: bool) -> Findings:
        raise NotImplementedError


class GroupingCheck(Groupable, RobotCheck):
    """A robot check that builds its grouped runs from its arrays (Limits, Velocity)."""
