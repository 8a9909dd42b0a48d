"""batch's result cache: where it lives and the size it is pruned to (the cache itself is
:class:`motiontool.motionfmt.disk_cache.ResultCache`)."""

from __future__ import annotations

from pathlib import Path

from motiontool.motionfmt.disk_cache import BYTES_PER_MB
from motiontool.motionfmt.fileio import cache_root

__all__ = ["DEFAULT_MAX_BYTES", "DEFAULT_MAX_MB", "default_cache_dir"]

DEFAULT_MAX_MB = 500
"""The size the cache is pruned to after a batch, in MB (a Nao run's report is about 10 kB)."""
DEFAULT_MAX_BYTES = DEFAULT_MAX_MB * BYTES_PER_MB
""":data:`DEFAULT_MAX_MB` in bytes."""


def default_cache_dir() -> Path:
    """``$XDG_CACHE_HOME/motiontool/batch`` (``~/.cache/motiontool/batch``)."""
    return cache_root() / "batch"
