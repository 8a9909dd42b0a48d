"""batch's result cache on disk: one JSON file per key, bounded in size, least recently used out.

A result is ``<directory>/<key[:2]>/<key>.json``. Reading a result marks it used (its mtime), so
:meth:`ResultCache.prune` removes the results no batch has read or written for the longest time
until the folder holds at most ``max_bytes``. ``motiontool cache clean`` empties it.
"""

from __future__ import annotations

import contextlib
import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from motiontool.motionfmt.fileio import atomic_write, cache_root

__all__ = ["BYTES_PER_MB", "DEFAULT_MAX_MB", "CacheUsage", "ResultCache", "default_cache_dir"]

BYTES_PER_MB = 1_000_000
"""A megabyte, as ``--cache-max-mb`` counts it."""

DEFAULT_MAX_MB = 500
"""The size the cache is pruned to after a batch, in MB (a Nao run's report is about 10 kB)."""


def default_cache_dir() -> Path:
    """``$XDG_CACHE_HOME/motiontool/batch`` (``~/.cache/motiontool/batch``)."""
    return cache_root() / "batch"


@dataclass(frozen=True)
class CacheUsage:
    """What a cache folder holds: ``results`` files of ``size_bytes`` in all."""

    results: int
    size_bytes: int


@dataclass(frozen=True)
class ResultCache:
    """Results on disk under ``directory``, pruned to ``max_bytes`` (None: unbounded)."""

    directory: Path
    max_bytes: int | None = DEFAULT_MAX_MB * BYTES_PER_MB

    def _path(self, key: str) -> Path:
        return self.directory / key[:2] / f"{key}.json"

    def load(self, key: str) -> dict[str, Any] | None:
        """The result stored under ``key`` (marked used), or None if there is none or it is
        unreadable."""
        path = self._path(key)
        try:
            doc = json.loads(path.read_bytes())
        except (OSError, ValueError):
            return None
        with contextlib.suppress(OSError):
            os.utime(path)
        return doc if isinstance(doc, dict) else None

    def store(self, key: str, doc: dict[str, Any]) -> None:
        """Write ``doc`` under ``key`` (atomically)."""
        path = self._path(key)
        path.parent.mkdir(parents=True, exist_ok=True)
        atomic_write(path, json.dumps(doc, sort_keys=True).encode())

    def _entries(self) -> list[tuple[float, int, Path]]:
        """(mtime, size in bytes, path) of every result, least recently used first."""
        out = []
        for path in self.directory.glob("??/*.json"):
            with contextlib.suppress(OSError):
                st = path.stat()
                out.append((st.st_mtime, st.st_size, path))
        return sorted(out)

    def usage(self) -> CacheUsage:
        entries = self._entries()
        return CacheUsage(len(entries), sum(size for _, size, _ in entries))

    def prune(self, max_bytes: int | None = None) -> CacheUsage:
        """Remove the least recently used results until at most ``max_bytes`` (default: the
        cache's own limit; 0 empties it) remain; what was removed."""
        limit = self.max_bytes if max_bytes is None else max_bytes
        if limit is None:
            return CacheUsage(0, 0)
        entries = self._entries()
        total = sum(size for _, size, _ in entries)
        removed = freed = 0
        for _, size, path in entries:
            if total - freed <= limit:
                break
            with contextlib.suppress(OSError):  # gone already, or not ours to remove
                path.unlink()
                removed, freed = removed + 1, freed + size
            with contextlib.suppress(OSError):
                path.parent.rmdir()  # only when it is empty
        return CacheUsage(removed, freed)
