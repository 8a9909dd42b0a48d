"""Configuration tables kept on disk, so that a hook run in a configured repository reads its
``[tool.motiontool]`` table without importing a TOML parser: ``tomllib``'s import and the parse
are 3-4 ms of a 0.08 s ``validate`` (docs/speed.md).

An entry holds a configuration file's absolute path, its whole text and the table read from it
(or None: a ``pyproject.toml`` without one), written by :mod:`marshal` (the interpreter's own
format, nothing to import), in ``$XDG_CACHE_HOME/motiontool/config`` under the CRC-32 of the
path. It is used only for the same path, the same text (compared whole: an edit is never
missed) and the same Python; anything else, or an entry that cannot be read, is no entry. An
entry that cannot be written is no error: the file is parsed again next time. ``motiontool
cache clean`` removes them.
"""

from __future__ import annotations

import marshal
import os
import sys
import zlib
from pathlib import Path
from typing import Any, NamedTuple

from motiontool.disk_cache import ResultCache, cache_root

__all__ = ["Entry", "cache", "lookup", "store"]

_FORMAT = f"motiontool configuration 1, Python {sys.version}"
"""What an entry's first item must be: the layout, and the interpreter whose ``tomllib`` parsed
the file and whose ``marshal`` wrote it."""

_KEPT = 1000
"""At most this many entries are kept (a configuration file each)."""


class Entry(NamedTuple):
    """What a configuration file was read as: its table (None: no motiontool table)."""

    table: dict[str, Any] | None


def cache() -> ResultCache:
    """The folder the entries are kept in."""
    return ResultCache(cache_root() / "config", max_results=_KEPT, suffix=".marshal")


def _key(path: str) -> str:
    return f"{zlib.crc32(os.fsencode(path)):08x}"


def lookup(path: Path, text: str) -> Entry | None:
    """What configuration file ``path``, whose text is ``text``, was read as, or None: not
    read before with this text (or the entry cannot be used)."""
    where = os.path.abspath(path)
    data = cache().load_bytes(_key(where))
    if data is None:
        return None
    try:
        kept = marshal.loads(data)
    except (ValueError, EOFError, TypeError):
        return None
    if not (isinstance(kept, tuple) and len(kept) == 4 and kept[:3] == (_FORMAT, where, text)):
        return None
    table = kept[3]
    return Entry(table) if table is None or isinstance(table, dict) else None


def store(path: Path, text: str, table: dict[str, Any] | None) -> None:
    """Keep what configuration file ``path`` (its text ``text``) was read as. A table that
    :mod:`marshal` cannot hold (a TOML date) is not kept."""
    where = os.path.abspath(path)
    try:
        data = marshal.dumps((_FORMAT, where, text, table))
    except ValueError:
        return
    kept = cache()
    if kept.store_bytes(_key(where), data):
        kept.prune()
