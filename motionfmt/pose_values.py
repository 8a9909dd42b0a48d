"""The value cells of a pose line as ``sscanf("%lf")`` reads them: ``*`` and the no-value marker
(no command, MT204), a number with text after it (MT203), nan/inf (MT113), a cell Webots cannot
read (MT108)."""

from __future__ import annotations

import math
import re
from typing import TYPE_CHECKING

from motiontool.motionfmt.cscan import PLAIN_DECIMAL as _PLAIN
from motiontool.motionfmt.cscan import scan_double
from motiontool.motionfmt.diagnostics import NO_VALUE_CELL, TRAILING_CHARACTERS
from motiontool.motionfmt.lines import PoseLine, show

if TYPE_CHECKING:
    from motiontool.motionfmt._read_state import ReadState

__all__ = ["NO_VALUE_MARKER", "cell_value", "pose_values"]

NO_VALUE_MARKER = -9999999.9
"""Webots' internal 'undefined position': a cell holding this number behaves like ``*``."""

_NAN = float("nan")
_NOT_FINITE_HINT = "write a number, or '*' for no command"
_UNIT_SUFFIX = re.compile(rb"\s*(rad|deg|degrees?|m|mm|cm|\xc2\xb0)\s*$", re.IGNORECASE)


def pose_values(
    state: ReadState, pose: PoseLine, time_ms: int | None
) -> tuple[list[float], list[int], bool]:
    """The first J value cells: (values, columns of the ``nan`` commands, all readable)."""
    values: list[float] = []
    nan_columns: list[int] = []
    ok = True
    tokens = pose.tokens
    for j in range(min(state.n_joints, len(tokens) - 2)):
        if _PLAIN.fullmatch(tokens[2 + j]) is not None:  # most cells of most lines
            value = float(tokens[2 + j])  # as scan_double reads it
            if math.isfinite(value) and value != NO_VALUE_MARKER:  # nothing to report
                values.append(value)
                continue
        cell = cell_value(state, pose, j, time_ms)
        if cell is None:
            ok = False
            values.append(_NAN)
            continue
        value, command = cell
        if command and math.isnan(value):
            nan_columns.append(j)
        values.append(value)
    return values, nan_columns, ok


def cell_value(
    state: ReadState, pose: PoseLine, j: int, time_ms: int | None
) -> tuple[float, bool] | None:
    """Value cell ``j`` (0-based joint) as ``sscanf("%lf")`` reads it: (value, whether it is a
    command), NaN for no command (``*``, the -9999999.9 marker); None if Webots cannot read
    it."""
    tok = pose.tokens[2 + j]
    if tok == b"*":
        state.star_seen = True
        return _NAN, False
    scanned = scan_double(tok)
    if scanned is None:
        _unreadable(state, pose, j, time_ms)
        return None
    value, end = scanned
    if tok[end:].strip(b" \t\v\f"):
        _trailing_text(state, pose, j, time_ms, value, end)
    joint = state.result.joints[j]
    if not math.isfinite(value):
        message = f"{joint} = {show(tok)} is not a finite number; Webots sends it to the motor"
        _report_cell(state, pose, j, time_ms, "MT113", 0, message, _NOT_FINITE_HINT)
        return (_NAN if math.isnan(value) else value), True
    if value == NO_VALUE_MARKER:
        message = f"{joint} = {show(tok)} is Webots' 'no value' marker: the cell reads as '*'"
        _report_cell(
            state, pose, j, time_ms, NO_VALUE_CELL, 0, message, "write '*' if no command is meant"
        )
        state.star_seen = True
        return _NAN, False
    return value, True


def _unreadable(state: ReadState, pose: PoseLine, j: int, time_ms: int | None) -> None:
    """MT108: a cell ``sscanf`` reads no number from, with a hint for the usual slips."""
    tok = pose.tokens[2 + j]
    hint = None
    if tok.strip(b" \t") == b"*":
        hint = "'*' must stand alone: remove the white space around it"
    elif tok.strip() == b"":
        hint = "a cell of white space is not empty to Webots: write a number or '*'"
    joint = state.result.joints[j]
    message = f"expected a number or '*' for {joint}, found {show(tok)}"
    _report_cell(state, pose, j, time_ms, "MT108", 0, message, hint)


def _trailing_text(
    state: ReadState, pose: PoseLine, j: int, time_ms: int | None, value: float, end: int
) -> None:
    """MT203: ``sscanf`` stops after the number at ``end`` and Webots ignores the rest."""
    tok = pose.tokens[2 + j]
    rest = tok[end:]
    joint = state.result.joints[j]
    hint = (
        "values are plain numbers in radians (metres for linear joints)"
        if _UNIT_SUFFIX.match(rest)
        else f"write {show(tok[:end].strip())}"
    )
    message = f"{joint} = {show(tok)} reads as {value!r}: Webots ignores {show(rest)}"
    _report_cell(state, pose, j, time_ms, TRAILING_CHARACTERS, end, message, hint)


def _report_cell(
    state: ReadState,
    pose: PoseLine,
    j: int,
    time_ms: int | None,
    code: str,
    offset: int,
    message: str,
    hint: str | None,
) -> None:
    """Report ``code`` on value cell ``j``, from ``offset`` bytes into the cell to its end."""
    a, b = pose.spans[2 + j]
    state.report(
        code,
        pose.line,
        pose.c0 + a + offset,
        message,
        hint,
        joint=state.result.joints[j],
        time_ms=time_ms,
        end_column=pose.c0 + b,
    )
