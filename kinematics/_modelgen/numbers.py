"""Numbers as the generated files write them: the shortest text that round-trips."""

from __future__ import annotations

from collections.abc import Iterable

__all__ = ["num", "sig", "vec"]


def num(x: float) -> str:
    """Shortest text that round-trips ``x`` (``4`` for 4.0, ``0`` for -0.0)."""
    value = float(x)
    if value == 0.0:
        return "0"
    text = repr(value)
    if text.endswith(".0"):
        text = text[:-2]
    return text


def sig(x: float, digits: int = 9) -> float:
    """``x`` rounded to ``digits`` significant digits (for derived values)."""
    return float(f"{x:.{digits}g}")


def vec(values: Iterable[float]) -> str:
    return " ".join(num(v) for v in values)
