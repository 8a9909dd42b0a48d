"""How a number and a count read in the reports for people."""

from __future__ import annotations

__all__ = ["num", "plural"]


def num(x: float) -> str:
    """``x`` in at most 6 significant digits (``0.1``, ``1e-07``, ``123457``)."""
    return f"{x:.6g}"


def plural(n: int, word: str) -> str:
    """``1 file``, ``2 files``: ``n`` and ``word``, with an ``s`` unless ``n`` is 1."""
    return f"{n} {word}{'' if n == 1 else 's'}"
