"""Canonical spelling of new ``.motion`` content: times, numbers, whole files."""

from __future__ import annotations

import math
import re
from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.motionfmt.nonfinite import refuse_non_finite
from motiontool.motionfmt.units import TIME_FIELD_MS

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = [
    "TimeStyle",
    "check_name",
    "format_motion",
    "format_time",
    "format_value",
    "format_values",
    "pose_lines",
    "pose_name",
]

_TIME_SHAPE = re.compile(r"\d+(?::\d+){0,2}")
_MINUTE, _SECOND, _MS = TIME_FIELD_MS


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
    minutes, rest = divmod(ms, _MINUTE) if len(w) == 3 else (0, ms)
    seconds, rest = divmod(rest, _SECOND)
    if len(w) == 2:
        return f"{seconds:0{w[0]}d}:{rest:0{w[1]}d}"
    return f"{minutes:0{w[0]}d}:{seconds:0{w[1]}d}:{rest:0{w[2]}d}"


def format_value(value: float) -> str:
    """The shortest text that reads back to the same double; ``*`` for NaN (no command)."""
    return _spelt([float(value)])[:-1]


def format_values(values: npt.NDArray[np.float64]) -> list[bytes]:
    """:func:`format_value` of each of ``values`` (1-D), as ASCII bytes: the same texts, made
    in one pass (a column of a long file is 100,000 values)."""
    return _spelt(values.tolist()).encode("ascii").split(b",")[:-1]


def _spelt(values: list[float]) -> str:
    """Each of ``values`` in the canonical spelling, each followed by ``,``: Python's shortest
    round-trip ``repr`` without a trailing ``.0``, ``*`` for NaN; an infinite value raises."""
    if not values:
        return ""
    text = ",".join(map(repr, values)) + ","
    if "inf," in text:
        bad = next(v for v in values if math.isinf(v))
        raise MotionToolError(f"cannot write an infinite joint value ({bad})")
    return text.replace(".0,", ",").replace("nan,", "*,")


def check_name(name: str, what: str) -> str:
    """Return ``name`` if Webots can read it back as one token, else raise."""
    if not name or any(c in name for c in ",\r\n\0"):
        raise MotionToolError(
            f"{what} {name!r} cannot be written: it must be non-empty, without ',', CR, LF or NUL"
        )
    return name


def pose_name(time_ms: int) -> str:
    """The name of a pose a command makes at ``time_ms`` (ms): ``Pose1500ms``."""
    return f"Pose{time_ms}ms"


def pose_lines(
    times_ms: Iterable[int],
    names: Iterable[str],
    values: npt.NDArray[np.float64],
    style: TimeStyle = TimeStyle(),
) -> list[str]:
    """New pose lines (without an end), canonically spelt: a pose per time (ms) and name, with
    its row of ``values`` ((P, J), rad or m; NaN: ``*``), made column by column."""
    columns = [
        [format_time(int(t), style) for t in times_ms],
        [check_name(name, "pose name") for name in names],
        *(_spelt(values[:, j].tolist()).split(",")[:-1] for j in range(values.shape[1])),
    ]
    return [",".join(cells) for cells in zip(*columns, strict=True)]


def format_motion(motion: Motion, *, newline: str = "\n", style: TimeStyle = TimeStyle()) -> str:
    """Write ``motion`` as a new file in the canonical spelling (``00:00:040``, shortest floats).

    A cell that is not commanded is written ``*``; a NaN or infinite command raises
    :class:`~motiontool.motionfmt.nonfinite.NonFiniteCommandError` (Webots would send it to the
    motor; write a number or ``*``).
    """
    refuse_non_finite(motion)
    header = ",".join(["#WEBOTS_MOTION", "V1.0", *(check_name(j, "joint") for j in motion.joints)])
    lines = pose_lines(motion.times_ms.tolist(), motion.pose_names, motion.values, style)
    return newline.join([header, *lines]) + newline
