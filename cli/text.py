"""How a number, a count and a file name read in the reports for people."""

from __future__ import annotations

from pathlib import Path

from motiontool.motionfmt.fileio import is_stdin, source_name

__all__ = ["file_name", "num", "plural"]


def file_name(path: str | Path) -> str:
    """A file's name for a title or a summary line: ``<stdin>`` for ``-``, else its last part."""
    return source_name(path) if is_stdin(path) else Path(path).name


def num(x: float) -> str:
    """``x`` in at most 6 significant digits (``0.1``, ``1e-07``, ``123457``)."""
    return f"{x:.6g}"


def plural(n: int, word: str) -> str:
    """``1 file``, ``2 files``: ``n`` and ``word``, with an ``s`` unless ``n`` is 1."""
    return f"{n} {word}{'' if n == 1 else 's'}"
