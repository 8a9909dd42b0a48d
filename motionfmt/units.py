"""Unit conversions, one home each: a motion file counts milliseconds, the physics seconds,
reports show millimetres of metres (every layer imports these, none spells 1000 itself).

A pose time is written ``m:s:ms``, ``s:ms`` or ``ms`` (``01:02:003`` is 62,003 ms); what each
field is worth is :data:`TIME_FIELD_MS`, read by the reader's three paths, the writer and the
command line alike."""

from __future__ import annotations

from collections.abc import Sequence

__all__ = ["MM_PER_M", "MS_PER_S", "TIME_FIELD_MS", "time_fields_ms"]

MS_PER_S = 1000.0
"""Milliseconds in a second."""

MM_PER_M = 1000.0
"""Millimetres in a metre."""

TIME_FIELD_MS = (60_000, 1_000, 1)
"""What one unit of each field of a pose time ``m:s:ms`` is worth, ms, most significant first:
integers, as Webots' C loader adds them (``m * 60000 + s * 1000 + ms``, in ``int``)."""


def time_fields_ms(fields: Sequence[int]) -> int:
    """The time of 1 to 3 fields, least significant last (``[1, 500]`` for ``1:500``), in ms,
    exactly (no C ``int`` wrap)."""
    weights = TIME_FIELD_MS[len(TIME_FIELD_MS) - len(fields) :]
    return sum(f * w for f, w in zip(fields, weights, strict=True))
