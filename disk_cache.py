"""What motiontool keeps on disk to compute less, for every layer: where the caches live
(:func:`cache_root`), results as one file per key, bounded in size, least recently used out
(:class:`ResultCache`: batch's simulation results, ``validate``'s robot findings, the
configuration files' tables), and the stamps their keys are made of. At the top of the
package, as :mod:`motiontool.stamps` is, so that each layer's cache
(``kinematics/tables_cache.py``, ``kinematics/checks/findings_cache.py``, ``sim/batch.py``,
``cli/config_cache.py``) says only what it stores and under which key.

A result is ``<directory>/<key[:2]>/<key>.json`` (another suffix for bytes of another format:
the configuration cache, ``cli/config_cache.py``). Reading a result marks it used (its mtime),
so :meth:`ResultCache.prune` removes the results no run has read or written for the longest
time until the folder holds at most ``max_bytes``. ``motiontool cache clean`` empties it.
"""

from __future__ import annotations

import contextlib
import os
import stat
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any, NamedTuple

__all__ = [
    "BYTES_PER_MB",
    "NO_CACHE_ROOT",
    "CacheUsage",
    "ResultCache",
    "cache_root",
    "code_stamp",
    "files_stamp",
    "libraries_stamp",
    "write_replacing",
]

BYTES_PER_MB = 1_000_000
"""A megabyte, as ``--cache-max-mb`` counts it."""


NO_CACHE_ROOT = Path(os.devnull) / "motiontool"
"""The caches' folder where none can be found: a path below the null device, under which no
folder can be made nor any file read, so that every cache is empty and keeps nothing."""


def cache_root() -> Path:
    """Where motiontool keeps what it can compute again: ``$XDG_CACHE_HOME/motiontool``
    (``~/.cache/motiontool``), one folder per cache in it. Without ``XDG_CACHE_HOME`` and a
    home directory (no ``HOME`` and a user the system does not know: a container run as an
    arbitrary user id, ``env -i``), :data:`NO_CACHE_ROOT`: the caches are off, as they are
    where the folder cannot be written."""
    base = os.environ.get("XDG_CACHE_HOME")
    if not base:
        try:
            base = str(Path.home() / ".cache")
        except RuntimeError:  # "Could not determine home directory."
            return NO_CACHE_ROOT
    return Path(base) / "motiontool"


class CacheUsage(NamedTuple):
    """What a cache folder holds: ``results`` files of ``size_bytes`` in all."""

    results: int
    size_bytes: int


class ResultCache(NamedTuple):
    """Results on disk under ``directory``, pruned to ``max_bytes`` and ``max_results``
    (None: unbounded): JSON documents (:meth:`load`, :meth:`store`), or bytes in a format of
    the caller's (:meth:`load_bytes`, :meth:`store_bytes`, files named ``*suffix``)."""

    directory: Path
    max_bytes: int | None = None
    max_results: int | None = None
    suffix: str = ".json"

    def _path(self, key: str) -> Path:
        return self.directory / key[:2] / f"{key}{self.suffix}"

    def load(self, key: str) -> dict[str, Any] | None:
        """The result stored under ``key`` (marked used), or None if there is none, it is
        unreadable or it is not a regular file."""
        data = self.load_bytes(key)
        if data is None:
            return None
        import json  # where a result is read or stored: a --no-cache run needs no JSON

        try:
            doc = json.loads(data)
        except ValueError:
            return None
        return doc if isinstance(doc, dict) else None

    def load_bytes(self, key: str) -> bytes | None:
        """The bytes stored under ``key`` (marked used), or None if there are none, they are
        unreadable or they are not a regular file."""
        path = self._path(key)
        try:
            if not stat.S_ISREG(os.lstat(path).st_mode):
                return None  # not what store writes: a FIFO would block, a link is not ours
            data = path.read_bytes()
        except OSError:
            return None
        with contextlib.suppress(OSError):
            os.utime(path)
        return data

    def store(self, key: str, doc: dict[str, Any]) -> bool:
        """Write ``doc`` under ``key`` as JSON (:meth:`store_bytes`)."""
        import json

        return self.store_bytes(key, json.dumps(doc, sort_keys=True).encode())

    def store_bytes(self, key: str, data: bytes) -> bool:
        """Write ``data`` under ``key`` (:func:`write_replacing`). False where it cannot be
        written: a cache that cannot be written is no error, the result is computed again next
        time."""
        return write_replacing(self._path(key), data)

    def _entries(self) -> list[tuple[float, int, Path]]:
        """(mtime, size in bytes, path) of every result, least recently used first."""
        out = []
        for path in self.directory.glob(f"??/*{self.suffix}"):
            with contextlib.suppress(OSError):
                st = path.stat()
                out.append((st.st_mtime, st.st_size, path))
        return sorted(out)

    def usage(self) -> CacheUsage:
        entries = self._entries()
        return CacheUsage(len(entries), sum(size for _, size, _ in entries))

    def prune(self, max_bytes: int | None = None) -> CacheUsage:
        """Remove the least recently used results until at most ``max_bytes`` (default: the
        cache's own limit; 0 empties it) and at most :attr:`max_results` remain; what was
        removed."""
        limit = self.max_bytes if max_bytes is None else max_bytes
        if limit is None and self.max_results is None:
            return CacheUsage(0, 0)
        entries = self._entries()
        total = sum(size for _, size, _ in entries)
        count = len(entries) if self.max_results is None else self.max_results
        removed = freed = 0
        for i, (_, size, path) in enumerate(entries):
            if (limit is None or total - freed <= limit) and len(entries) - i <= count:
                break
            with contextlib.suppress(OSError):  # gone already, or not ours to remove
                path.unlink()
                removed, freed = removed + 1, freed + size
            with contextlib.suppress(OSError):
                path.parent.rmdir()  # only when it is empty
        return CacheUsage(removed, freed)


def write_replacing(path: Path, data: bytes) -> bool:
    """Write ``data`` to ``path``: a temporary file beside it, then a rename, so that a reader
    sees all of it or nothing, and whatever was at the path (a FIFO, a link) is replaced, never
    written through. The temporary file's name is drawn before the file is made, inside the
    ``try`` that removes it: a signal at any moment (Ctrl-C, SIGTERM) leaves none behind
    (``tempfile.mkstemp`` makes the file, then calls Python code before it returns its name).
    False where it cannot be written (a read-only or full disk, a file where a folder should
    be)."""
    tmp = path.with_name(f".{os.urandom(6).hex()}.tmp")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.replace(tmp, path)
    except FileExistsError:  # a file where the folder should be, or the name taken: not ours
        return False
    except BaseException as exc:  # OSError; SIGTERM, Ctrl-C: no temporary file left behind
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        if isinstance(exc, OSError):
            return False
        raise
    return True


def files_stamp(paths: Iterable[Path], suffix: str = ".py") -> str:
    """Hash (hex) of the path, size and modification time of each file of ``paths`` and of
    every ``suffix`` file below its folders: what changes when the code in them changes (an
    edit, an upgrade)."""
    import hashlib  # where a stamp is made: reading the configuration cache needs none

    h = hashlib.sha256()
    for top in paths:
        for path, st in _files(top, suffix):
            h.update(f"{path}\0{st.st_size}\0{st.st_mtime_ns}\n".encode("utf-8", "surrogateescape"))
    return h.hexdigest()


def _files(folder: Path, suffix: str) -> Iterator[tuple[str, os.stat_result]]:
    """(path, stat) of the ``suffix`` files below ``folder``, in name order (``__pycache__``
    and links left out), or of ``folder`` itself where it is a file."""
    try:
        with os.scandir(folder) as it:
            entries = sorted(it, key=lambda e: e.name)
    except NotADirectoryError:
        with contextlib.suppress(OSError):
            yield str(folder), os.stat(folder)
        return
    except OSError:
        return
    for e in entries:
        if e.is_dir(follow_symlinks=False):
            if e.name != "__pycache__":
                yield from _files(Path(e.path), suffix)
        elif e.name.endswith(suffix) and e.is_file(follow_symlinks=False):
            with contextlib.suppress(OSError):
                yield e.path, e.stat(follow_symlinks=False)


def code_stamp(folders: Iterable[str], libraries: Iterable[str]) -> str:
    """What changes when the code a cached result was computed by changes: the package's
    ``folders`` (names below its root) and top-level modules (:func:`files_stamp`), and where
    each of ``libraries`` is installed (:func:`libraries_stamp`)."""
    root = Path(__file__).resolve().parent
    top = sorted(p for p in root.glob("*.py") if p.is_file())
    code = files_stamp([*(root / name for name in folders), *top])
    return "\n".join((code, libraries_stamp(*libraries)))


def libraries_stamp(*names: str) -> str:
    """Where each installed library ``names`` is found, with the size and modification time of
    its module file (``-`` where it is not installed), without importing it: what changes when
    one is installed, upgraded or removed."""
    import importlib.util

    parts = []
    for name in names:
        try:
            spec = importlib.util.find_spec(name)
        except (ImportError, ValueError):
            spec = None
        origin = spec.origin if spec is not None else None
        try:
            st = os.stat(origin) if origin else None
        except OSError:
            st = None
        found = "-" if st is None else f"{origin}:{st.st_size}:{st.st_mtime_ns}"
        parts.append(f"{name}:{found}")
    return "\n".join(parts)
