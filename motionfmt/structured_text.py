"""TOML and YAML text read with errors a user can act on: a
:class:`~motiontool.errors.MotionSyntaxError` at the problem's line and column, never a
traceback. The configuration (``pyproject.toml``, ``motiontool.toml``), a folder's
``motions.toml``, joint maps and a JointTrajectory in YAML are read here. Both parsers recurse
once per level of nesting (``tomllib``, ruamel's composer): a file nested deeper than Python's
stack is "nested too deeply to read", not a ``RecursionError``. A value shown in a message is
shortened (:func:`shown`): a few YAML aliases can build a value of millions of items. YAML is
read with ruamel.yaml (extra ``ros``), imported where a YAML file is read.
"""

from __future__ import annotations

import tomllib
from typing import Any

from motiontool.errors import MotionSyntaxError
from motiontool.extras import require

__all__ = ["load_toml", "load_yaml", "shown"]


def load_yaml(text: str, path: str, what: str, *, round_trip: bool = False) -> list[Any]:
    """The documents of ``text`` (the file ``path``, holding ``what``), as plain values, or
    with ``round_trip`` as ruamel's commented maps and lists (their ``lc`` marks give each
    node's line and column).

    Raises:
        MotionSyntaxError: not YAML, or nested too deeply to read.
        MissingExtraError: ruamel.yaml is not installed (extra ``ros``).
    """
    yaml = require("ruamel.yaml", "ros", f"reading {what} (YAML)")
    try:
        return list(yaml.YAML(typ="rt" if round_trip else "safe", pure=True).load_all(text))
    except RecursionError:
        raise MotionSyntaxError(f"nested too deeply to read: expected {what}", path, 1, 1) from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line, col = (mark.line + 1, mark.column + 1) if mark is not None else (1, 1)
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise MotionSyntaxError(f"not YAML: {problem}", path, line, col) from exc


def load_toml(text: str, path: str, what: str) -> dict[str, Any]:
    """``text`` (the TOML file ``path``, holding ``what``) as a table.

    Raises:
        MotionSyntaxError: not TOML (at the line and column ``tomllib`` names; an error at the
            end of the document at its last line), or nested too deeply to read.
    """
    import re

    try:
        return tomllib.loads(text)
    except RecursionError:
        raise MotionSyntaxError(f"nested too deeply to read: expected {what}", path, 1, 1) from None
    except tomllib.TOMLDecodeError as exc:
        message = str(exc)
        at = re.search(r"\s*\(at line (\d+), column (\d+)\)$", message)
        end = re.search(r"\s*\(at end of document\)$", message)
        if at is not None:
            line, col, message = int(at.group(1)), int(at.group(2)), message[: at.start()]
        elif end is not None:
            line, col, message = len(text.splitlines()) or 1, 1, message[: end.start()]
        else:
            line, col = 1, 1
        raise MotionSyntaxError(message, path, line, col) from exc


def shown(value: Any) -> str:
    """``value`` as an error message shows it: its ``repr``, a long or nested one shortened
    (``[[...], [...], ...]``), one short line whatever the value."""
    import reprlib

    short = reprlib.Repr()
    short.maxlevel, short.maxlist, short.maxdict, short.maxstring, short.maxother = 1, 4, 4, 40, 40
    return short.repr(value)
