"""The time token of a pose line as Webots' ``str_to_time`` reads it: 'm:s:ms', 's:ms' or 'ms'
(MT105 if it cannot), a time past a C ``int`` (MT112), a time not after the previous pose's
(MT106)."""

from __future__ import annotations

import re
from typing import TYPE_CHECKING

from motiontool.motionfmt.cscan import INT_MAX, scan_time
from motiontool.motionfmt.diagnostics import Related
from motiontool.motionfmt.lines import PoseLine, separator_hint, show
from motiontool.motionfmt.units import time_fields_ms

if TYPE_CHECKING:
    from motiontool.motionfmt._read_state import ReadState

__all__ = ["pose_time"]


def pose_time(state: ReadState, pose: PoseLine, prev: tuple[int, int]) -> tuple[int | None, bool]:
    """The pose time as Webots reads it (None if it cannot), and whether it is valid and
    after the previous pose's; ``prev`` is (time in ms, line) of that pose."""
    t_tok = pose.tokens[0]
    a0, b0 = pose.spans[0]
    line, c0 = pose.line, pose.c0
    scanned = scan_time(t_tok)
    time_ms: int | None = None if scanned is None else scanned.ms
    if _well_formed_time(t_tok) and (scanned is None or scanned.exact_ms > INT_MAX):
        # Digits Webots accepts, but the arithmetic overflows a C int.
        outcome = "rejects it" if scanned is None else f"reads it as {scanned.ms} ms"
        state.report(
            "MT112",
            line,
            c0 + a0,
            f"pose time {show(t_tok)} is {_exact_time(t_tok)} ms, beyond the {INT_MAX} ms"
            f" a C int holds; Webots {outcome}",
            "motions longer than 24 days are not supported",
            end_column=c0 + b0,
            rejects=scanned is None,  # a wrapped time Webots reads does not reject
        )
    elif scanned is None:
        state.report(
            "MT105",
            line,
            c0 + a0,
            f"expected a pose time ('m:s:ms', 's:ms' or 'ms'), found {show(t_tok)}",
            _time_hint(t_tok),
            end_column=c0 + b0,
        )
    if time_ms is None:
        return None, False
    prev_time, prev_line = prev
    if time_ms <= prev_time:
        stable = f"pose time {time_ms} ms is not after the previous pose's {prev_time} ms"
        state.report(
            "MT106",
            line,
            c0 + a0,
            f"{stable} (line {prev_line})",
            "pose times must strictly increase",
            time_ms=time_ms,
            end_column=c0 + b0,
            related=(Related(prev_line, 1, f"the previous pose, at {prev_time} ms"),),
            stable=stable,
        )
        return time_ms, False
    return time_ms, True


def _well_formed_time(tok: bytes) -> bool:
    """Digits and at most two colons, every field non-empty: the shape Webots accepts."""
    fields = tok.split(b":")
    return len(fields) <= 3 and all(f.isdigit() for f in fields)


def _exact_time(tok: bytes) -> int:
    return time_fields_ms([int(f) for f in tok.split(b":")])


_TIME_CHARS = re.compile(rb"[0-9:]+")


def _time_hint(tok: bytes) -> str:
    stripped = tok.strip(b" \t")
    if stripped.startswith(b"#"):
        return "'#' does not start a comment: .motion files have no comments; remove the line"
    if not stripped:
        return (
            "this line holds only white space, which Webots does not take for a blank line;"
            " delete the spaces"
        )
    if stripped != tok:
        return "remove the white space around the time"
    time = _TIME_CHARS.match(tok)
    separated = time and separator_hint(tok, time.end(), "'time,name,value,...'")
    if separated:
        return separated
    if tok.startswith((b"-", b"+")):
        return "pose times are unsigned milliseconds"
    if b"." in tok:
        return "times are integer milliseconds: write 'm:s:ms', e.g. 00:01:500"
    if tok.count(b":") > 2:
        return "at most two ':' (minutes:seconds:milliseconds)"
    if b":" in tok:
        return "every field of 'm:s:ms' needs at least one digit"
    return "write the time as 'm:s:ms', e.g. 00:01:500"
