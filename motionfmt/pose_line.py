"""A pose line on the exact path: every check, for the lines the fast path (:mod:`.pose_fast`)
does not take. The line's shape is checked here: a NUL byte (MT114), empty cells (MT202), no pose
name (MT107), too few or too many values (MT109, MT110); its time (:mod:`.pose_time`) and its
value cells (:mod:`.pose_values`) have their own modules."""

from __future__ import annotations

import itertools
import re
from typing import TYPE_CHECKING

from motiontool.motionfmt.diagnostics import EMPTY_CELL, NUL_BYTE
from motiontool.motionfmt.lines import Piece, PoseLine, decode_name, show
from motiontool.motionfmt.pose_time import pose_time
from motiontool.motionfmt.pose_values import pose_values

if TYPE_CHECKING:
    from motiontool.motionfmt._read_state import ReadState

__all__ = ["read_pose_exact"]

_INT_TOKEN = re.compile(rb"-?\d+")
_DIGITS_TOKEN = re.compile(rb"\d+")


def read_pose_exact(
    state: ReadState, piece: Piece, spans: list[tuple[int, int]], prev: tuple[int, int]
) -> int | None:
    """Check one pose line fully; return its time as Webots reads it, or ``None``."""
    pose = PoseLine(piece, spans)
    _pose_nul(state, pose)
    _empty_cells(state, pose)
    time_ms, ok = pose_time(state, pose, prev)
    if len(pose.tokens) < 2:
        _missing_pose_name(state, pose, time_ms)
        return time_ms
    values, nan_columns, values_ok = pose_values(state, pose, time_ms)
    count_ok = _value_count(state, pose, time_ms)
    if ok and values_ok and count_ok and time_ms is not None:
        res = state.result
        res.nan_commands.extend((len(res.times_ms), j) for j in nan_columns)
        res.times_ms.append(time_ms)
        res.pose_names.append(decode_name(pose.tokens[1]))
        state.cells.extend(values)
        state.pose_lines.append(pose.line)
        state.pose_cols0.append(piece.col0)
    return time_ms


def _pose_nul(state: ReadState, pose: PoseLine) -> None:
    """A NUL byte: Webots' C string ends there (the tokens stop before it)."""
    nul = pose.raw.find(b"\0")
    if nul >= 0:
        state.report(
            NUL_BYTE,
            pose.line,
            pose.c0 + nul,
            "NUL byte: Webots' C strings end there, so the rest of the line is lost",
            "remove the NUL byte",
        )


def _empty_cells(state: ReadState, pose: PoseLine) -> None:
    """Empty cells (``,,``), which ``strtok`` collapses."""
    spans, c0 = pose.spans, pose.c0
    for k in range(1, len(spans)):
        gap = pose.raw[spans[k - 1][1] : spans[k][0]]
        if gap.count(b",") > 1:
            where = spans[k - 1][1] + gap.index(b",") + 1
            state.report(
                EMPTY_CELL,
                pose.line,
                c0 + where,
                "empty cell: Webots skips ',,' so every value after it moves one joint left",
                "write '*' for a joint that gets no command in this pose",
                end_column=c0 + where + 1,
            )


def _missing_pose_name(state: ReadState, pose: PoseLine, time_ms: int | None) -> None:
    """A line of one token: no pose name (not reported after a time Webots cannot read)."""
    if time_ms is not None:
        state.report(
            "MT107",
            pose.line,
            pose.c0 + pose.spans[0][1],
            "expected a pose name after the time, found end of line",
            "a pose line is 'time,name,value,...'",
            time_ms=time_ms,
        )


def _value_count(state: ReadState, pose: PoseLine, time_ms: int | None) -> bool:
    """Whether the line has exactly J values, one per joint (MT109, MT110 if not)."""
    n = state.n_joints
    values_toks = pose.tokens[2:]
    if len(values_toks) < n:
        missing = state.result.joints[len(values_toks) :]
        names = ", ".join(missing[:3]) + (", ..." if len(missing) > 3 else "")
        state.report(
            "MT109",
            pose.line,
            pose.c0 + pose.spans[-1][1],
            f"expected {n} values (one per joint), found {len(values_toks)}; no value for {names}",
            "write '*' for a joint that gets no command in this pose",
            time_ms=time_ms,
        )
        return False
    if len(values_toks) > n:
        a, b = pose.spans[2 + n]
        state.report(
            "MT110",
            pose.line,
            pose.c0 + a,
            f"expected {n} values (one per joint), found {len(values_toks)}; extra"
            f" {show(values_toks[n])}",
            _decimal_comma_hint(values_toks) if n else _NO_JOINT_HINT,
            time_ms=time_ms,
            end_column=pose.c0 + b,
        )
        return False
    return True


_NO_JOINT_HINT = "the header names no joint (MT103): list the joints after 'V1.0' on line 1"


def _decimal_comma_hint(values: list[bytes]) -> str | None:
    for a, b in itertools.pairwise(values):
        if _INT_TOKEN.fullmatch(a.strip()) and _DIGITS_TOKEN.fullmatch(b.strip()):
            return (
                f"decimal comma? '{a.strip().decode()},{b.strip().decode()}' splits into two"
                f" values: write '{a.strip().decode()}.{b.strip().decode()}'"
            )
    return None
