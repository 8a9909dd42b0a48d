"""How a number, a count, a file name and text from the user's input read in the reports for
people."""

from __future__ import annotations

import re
from pathlib import Path

from motiontool.motionfmt.fileio import is_stdin, source_name

__all__ = ["SHOWN_PATH", "SHOWN_RUN", "escaped", "file_name", "num", "plural", "shown"]


def file_name(path: str | Path) -> str:
    """A file's name for a title or a summary line: ``<stdin>`` for ``-``, else its last part."""
    return source_name(path) if is_stdin(path) else Path(path).name


def num(x: float) -> str:
    """``x`` in at most 6 significant digits (``0.1``, ``1e-07``, ``123457``)."""
    return f"{x:.6g}"


def plural(n: int, word: str) -> str:
    """``1 file``, ``2 files``: ``n`` and ``word``, with an ``s`` unless ``n`` is 1."""
    return f"{n} {word}{'' if n == 1 else 's'}"


SHOWN_RUN = 80
"""At most this many characters of a run of text without a space in a message: a name or a
value from the input, echoed (a 4,000-character joint name, a 1 MB pose line)."""

SHOWN_PATH = 240
"""At most this many characters of a run with a ``/`` in it: a path (a finding's location,
``/home/runner/work/...``), shown whole where it is not absurdly long."""

# C0 and C1 controls, DEL, and Unicode's bidirectional overrides and isolates: a terminal acts
# on them (an ESC sequence recolours, moves the cursor, sets the window title; an override
# shows text reversed), where a message means to show them.
_CONTROL = re.compile("[\x00-\x1f\x7f-\x9f\u202a-\u202e\u2066-\u2069]")
_LONG_RUN = re.compile(f"\\S{{{SHOWN_RUN + 1},}}")


def _escape(match: re.Match[str]) -> str:
    """A control character as Python's ``repr`` writes it (``\\t``, ``\\x1b``, ``\\u202e``)."""
    return repr(match.group())[1:-1]


def _cut(match: re.Match[str]) -> str:
    """A run of more than :data:`SHOWN_RUN` (a path: :data:`SHOWN_PATH`) characters, cut to
    that many: its first three quarters, an ellipsis, its end."""
    run = match.group()
    most = SHOWN_PATH if "/" in run else SHOWN_RUN
    if len(run) <= most:
        return run
    head = most * 3 // 4
    return run[:head] + "..." + run[len(run) - (most - head - 3) :]


def shown(text: str) -> str:
    """``text`` (a message, a hint, an error line) as it is safe to print for people: control
    characters from the input escaped (``\\x1b``, as Python writes them), and a run of more
    than :data:`SHOWN_RUN` characters without a space (:data:`SHOWN_PATH` for a path) cut to
    that many, its middle an ellipsis (the quote and the end of a name stay). Machine formats
    (JSON, SARIF) keep the exact text."""
    return _LONG_RUN.sub(_cut, escaped(text))


def escaped(text: str) -> str:
    """``text`` with its control characters escaped, as :func:`shown` does, and not cut (a
    source line that a report shows, a window of it already)."""
    return _CONTROL.sub(_escape, text)
