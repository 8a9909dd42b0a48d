"""Unit conversions, one home each: a motion file counts milliseconds, the physics seconds,
reports show millimetres of metres (every layer imports these, none spells 1000 itself)."""

from __future__ import annotations

__all__ = ["MM_PER_M", "MS_PER_S"]

MS_PER_S = 1000.0
"""Milliseconds in a second."""

MM_PER_M = 1000.0
"""Millimetres in a metre."""
