"""Checks on the whole motion Webots reads, once every pose is in: a first pose after 0 ms
(MT206), pose times off the controller's time step (MT209), a playback clock that wraps before
the end (MT115), and joints that ``*`` leaves uncommanded (MT207, MT211)."""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from motiontool.motionfmt.clock import clock_overflow
from motiontool.motionfmt.cscan import INT_MAX
from motiontool.motionfmt.diagnostics import CODES, Diagnostic, Severity
from motiontool.motionfmt.lines import FGETS_PIECE, token_spans

if TYPE_CHECKING:
    from motiontool.motionfmt._read_state import ReadState
    from motiontool.motionfmt.read_result import ReadResult

__all__ = ["check_motion", "step_findings"]

_Where = Callable[[int], tuple[int, int]]
"""A pose's time token: its column and end column, 1-based."""
_Report = Callable[..., None]
"""Records a finding: :meth:`~motiontool.motionfmt._read_state.ReadState.report`'s arguments."""


def check_motion(state: ReadState) -> None:
    """Every check on the motion read so far (its poses are in ``state.result``)."""
    times = state.result.times_ms
    if not times:
        return
    if times[0] > 0:
        _late_first_pose(state)
    step = state.timestep_ms
    if step:
        where = functools.partial(_cell_column, state, cell=0)
        _off_time_step(state.result, step, where, state.report)
        _clock_wraps(state.result, step, where, state.report)
    if state.star_seen:
        _uncommanded(state)


def step_findings(result: ReadResult, step: int) -> list[Diagnostic]:
    """The findings of the pose times of ``result`` (a file read without a time step) at the
    controller time step ``step`` (ms): MT209 on each pose off it, MT115 where the playback
    clock wraps before the end, as the reader makes them when given the step."""
    found: list[Diagnostic] = []

    def report(code: str, line: int, column: int, message: str, hint: str, **kw: Any) -> None:
        severity = CODES[code].severity
        found.append(
            Diagnostic(
                code=code,
                severity=severity,
                path=result.path,
                line=line,
                column=column,
                message=message,
                hint=hint,
                **kw,
            )
        )

    def where(pose: int) -> tuple[int, int]:
        _line, column, end = result.cell_span(pose, None)
        return column, end

    _off_time_step(result, step, where, report)
    _clock_wraps(result, step, where, report)
    return found


def _cell_column(state: ReadState, pose: int, cell: int) -> tuple[int, int]:
    """1-based (column, end column) of token ``cell`` (0 = time) of pose ``pose``."""
    line = state.result.pose_lines[pose]
    col0 = state.pose_cols0[pose] if state.pose_cols0 else 0
    content = state.lines[line - 1][col0 : col0 + FGETS_PIECE]
    a, b = token_spans(content)[cell]
    return col0 + a + 1, col0 + b + 1


def _late_first_pose(state: ReadState) -> None:
    """MT206: Webots commands the first pose at once, whatever its time."""
    res = state.result
    first = res.times_ms[0]
    col, end = _cell_column(state, 0, 0)
    state.report(
        "MT206",
        res.pose_lines[0],
        col,
        f"first pose is at {first} ms: Webots commands it at once (t = 0), so the"
        f" robot jumps to it instead of moving there in {first} ms",
        "add a first pose at 00:00:000 that holds the robot's start position",
        time_ms=first,
        end_column=end,
    )


def _off_time_step(res: ReadResult, step: int, where: _Where, report: _Report) -> None:
    """MT209: a pose time the controller, stepping ``step`` ms at a time, never hits (``where``:
    a pose's time token's column and end column; ``report``: :meth:`ReadState.report`)."""
    for p, t in enumerate(res.times_ms):
        if t % step:
            col, end = where(p)
            lo = t - t % step
            fits = lo + step <= INT_MAX  # the step after may be past a C int (MT115)
            steps = f"steps at {lo} and {lo + step} ms" if fits else f"step at {lo} ms"
            report(
                "MT209",
                res.pose_lines[p],
                col,
                f"pose at {t} ms is not a multiple of the {step} ms time step: the"
                f" controller never commands it exactly ({steps})",
                f"move it to {lo} or {lo + step} ms" if fits else f"move it to {lo} ms",
                time_ms=t,
                end_column=end,
            )


def _clock_wraps(res: ReadResult, step: int, where: _Where, report: _Report) -> None:
    """MT115: Webots' int playback time wraps before the motion ends (see :mod:`.clock`)."""
    overflow = clock_overflow(int(res.times_ms[-1]), step) if step <= INT_MAX else None
    if overflow is None:
        return
    col, end = where(len(res.times_ms) - 1)
    report(
        "MT115",
        res.pose_lines[-1],
        col,
        overflow.message,
        overflow.hint,
        time_ms=res.times_ms[-1],
        end_column=end,
    )


def _uncommanded(state: ReadState) -> None:
    """Report runs of ``*`` cells: the joint gets no command over the segments they touch
    (MT207), or never (MT211)."""
    res = state.result
    header_spans = token_spans(state.lines[0])[2:]
    nan_cells = set(res.nan_commands)  # a literal 'nan' is a command, not a '*'
    width = len(res.joints)
    for j, joint in enumerate(res.joints):
        column = res.cells[j::width]
        undefined = [v != v and (p, j) not in nan_cells for p, v in enumerate(column)]
        if all(undefined):
            a, b = header_spans[j]
            state.report(
                "MT211",
                1,
                a + 1,
                f"{joint} is '*' in every pose: this motion never commands it",
                "remove the column if the motion is not meant to drive this joint",
                joint=joint,
                end_column=b + 1,
            )
            continue
        for p, q in _runs(undefined):
            _uncommanded_run(state, j, p, q)


def _runs(flags: list[bool]) -> list[tuple[int, int]]:
    """(first, last) index of each run of consecutive True in ``flags``."""
    runs = []
    n = len(flags)
    p = 0
    while p < n:
        if not flags[p]:
            p += 1
            continue
        q = p
        while q + 1 < n and flags[q + 1]:
            q += 1
        runs.append((p, q))
        p = q + 1
    return runs


def _uncommanded_run(state: ReadState, j: int, p: int, q: int) -> None:
    """MT207 for joint ``j``, ``*`` from pose ``p`` to pose ``q``."""
    res = state.result
    times = res.times_ms
    joint = res.joints[j]
    start = times[p - 1] if p > 0 else 0
    col, end = _cell_column(state, p, 2 + j)
    if q + 1 < len(times):
        message = (
            f"'*' leaves {joint} uncommanded from {start} ms to {times[q + 1]} ms:"
            " it holds its previous target instead of moving"
        )
        severity = Severity.WARNING
    else:  # a trailing run only holds the last target: worth knowing, not a trap
        message = (
            f"'*' leaves {joint} uncommanded from {start} ms to the end: it holds its last target"
        )
        severity = Severity.INFO
    state.report(
        "MT207",
        res.pose_lines[p],
        col,
        message,
        "write a value where the joint should move; '*' does not interpolate",
        joint=joint,
        time_ms=times[p],
        end_column=end,
        severity=severity,
    )
