"""When to write ANSI colours: only to a terminal, and never when the user says no.

The rules, first match wins:

1. output to a file (``-o report.txt``): never;
2. ``motiontool --no-color ...``: never;
3. ``NO_COLOR`` set to a non-empty value (https://no-color.org): never;
4. ``FORCE_COLOR`` set to a non-empty value: always (for CI logs that render colour);
5. otherwise: when the stream is a terminal.

Rich (the ``batch`` progress bar) reads ``NO_COLOR`` and ``FORCE_COLOR`` itself;
:func:`rich_no_color` adds ``--no-color``.
"""

from __future__ import annotations

import contextvars
import os
from typing import IO, Any

__all__ = ["color_enabled", "rich_no_color", "set_no_color"]

_no_color: contextvars.ContextVar[bool] = contextvars.ContextVar(
    "motiontool_no_color", default=False
)


def set_no_color(value: bool) -> None:
    """Record ``--no-color`` (the root command sets it on every invocation)."""
    _no_color.set(value)


def color_enabled(stream: IO[Any] | None, *, to_file: bool = False) -> bool:
    """Whether text written to ``stream`` (or to a file, with ``to_file``) may carry colour."""
    if to_file or _no_color.get() or os.environ.get("NO_COLOR"):
        return False
    if os.environ.get("FORCE_COLOR"):
        return True
    isatty = getattr(stream, "isatty", None)
    return bool(isatty and isatty())


def rich_no_color() -> bool | None:
    """``no_color`` for a rich ``Console``: True after ``--no-color``, else None (rich then
    follows ``NO_COLOR`` on its own)."""
    return True if _no_color.get() else None
