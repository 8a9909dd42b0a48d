"""Canonical spelling of new ``.motion`` content: times, numbers, whole files."""

from __future__ import annotations

import math
import re
from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.motionfmt.nonfinite import refuse_non_finite

if TYPE_CHECKING:
    from motiontool.motionfmt.motion import Motion

__all__ = ["TimeStyle", "check_name", "format_motion", "format_time", "format_value"]

_TIME_SHAPE = re.compile(r"\d+(?::\d+){0,2}")


@dataclass(frozen=True)
class TimeStyle:
    """How a file spells its pose times: number of fields and their zero-padded widths.

    ``TimeStyle((2, 2, 3))`` writes ``00:01:040``; ``TimeStyle((1,))`` writes plain milliseconds.
    """

    widths: tuple[int, ...] = (2, 2, 3)

    @classmethod
    def of(cls, token: str) -> TimeStyle:
        """The style of an existing time token such as ``00:00:040`` or ``1500``."""
        if not _TIME_SHAPE.fullmatch(token):
            return cls()
        return cls(tuple(len(f) for f in token.split(":")))


def format_time(ms: int, style: TimeStyle = TimeStyle()) -> str:
    """Spell ``ms`` (milliseconds, >= 0) in ``style``; ``61040`` -> ``01:01:040``."""
    if ms < 0:
        raise MotionToolError(f"pose times cannot be negative, got {ms} ms")
    w = style.widths
    if len(w) == 1:
        return f"{ms:0{w[0]}d}"
    if len(w) == 2:
        return f"{ms // 1000:0{w[0]}d}:{ms % 1000:0{w[1]}d}"
    return f"{ms // 60000:0{w[0]}d}:{ms // 1000 % 60:0{w[1]}d}:{ms % 1000:0{w[2]}d}"


def format_value(value: float) -> str:
    """The shortest text that reads back to the same double; ``*`` for NaN (no command)."""
    if math.isnan(value):
        return "*"
    if math.isinf(value):
        raise MotionToolError(f"cannot write an infinite joint value ({value})")
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text


def check_name(name: str, what: str) -> str:
    """Return ``name`` if Webots can read it back as one token, else raise."""
    if not name or any(c in name for c in ",\r\n\0"):
        raise MotionToolError(
            f"{what} {name!r} cannot be written: it must be non-empty, without ',', CR, LF or NUL"
        )
    return name


def _pose_line(time_ms: int, name: str, values: Iterable[float], style: TimeStyle) -> str:
    cells = [format_time(time_ms, style), check_name(name, "pose name")]
    cells.extend(format_value(float(v)) for v in values)
    return ",".join(cells)


def format_motion(motion: Motion, *, newline: str = "\n", style: TimeStyle = TimeStyle()) -> str:
    """Write ``motion`` as a new file in the canonical spelling (``00:00:040``, shortest floats).

    A cell that is not commanded is written ``*``; a NaN or infinite command raises
    :class:`~motiontool.motionfmt.nonfinite.NonFiniteCommandError` (Webots would send it to the
    motor; write a number or ``*``).
    """
    refuse_non_finite(motion)
    header = ",".join(["#WEBOTS_MOTION", "V1.0", *(check_name(j, "joint") for j in motion.joints)])
    lines = [header]
    for t, name, row in zip(motion.times_ms, motion.pose_names, motion.values, strict=True):
        lines.append(_pose_line(int(t), name, row, style))
    return newline.join(lines) + newline
