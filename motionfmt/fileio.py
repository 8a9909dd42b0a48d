"""Reading motion files (``-``: standard input) and writing them safely (temporary file, then
rename)."""

from __future__ import annotations

import contextlib
import os
import stat
import sys
import tempfile
import weakref
from collections.abc import Iterable
from pathlib import Path

from motiontool.motionfmt.errors import MotionToolError

__all__ = [
    "STDIN",
    "STDIN_NAME",
    "atomic_write",
    "collect_motion_files",
    "is_stdin",
    "read_file",
    "source_name",
]

STDIN = "-"
"""The path that means standard input where a motion file is read."""

STDIN_NAME = "<stdin>"
"""How diagnostics and reports name standard input."""

# Standard input can be read only once; a command that reads '-' twice (play reads each file
# again, diff - -) gets the same bytes. Keyed by the stream, so a new stdin is read afresh.
_stdin_bytes: weakref.WeakKeyDictionary[object, bytes] = weakref.WeakKeyDictionary()


def is_stdin(path: str | Path) -> bool:
    """True for ``-``, the path that stands for standard input."""
    return str(path) == STDIN


def source_name(path: str | Path) -> str:
    """How diagnostics name ``path``: ``<stdin>`` for ``-``, else the path as given."""
    return STDIN_NAME if is_stdin(path) else str(path)


def _read_stdin() -> bytes:
    stream = sys.stdin
    if stream is None:
        raise MotionToolError(f"cannot read '{STDIN}' ({STDIN_NAME}): there is no standard input")
    source: object = getattr(stream, "buffer", stream)
    cached = _stdin_bytes.get(source)
    if cached is not None:
        return cached
    try:
        raw = source.read()  # type: ignore[attr-defined]
    except OSError as exc:
        raise MotionToolError(f"cannot read {STDIN_NAME}: {exc.strerror or exc}") from exc
    data = raw if isinstance(raw, bytes) else str(raw).encode("utf-8", "surrogateescape")
    with contextlib.suppress(TypeError):  # a stream that takes no weak reference: not cached
        _stdin_bytes[source] = data
    return data


def read_file(path: str | Path) -> bytes:
    """The bytes of ``path`` (``-``: standard input, read once).

    Raises:
        MotionToolError: one line, ``cannot read 'PATH': REASON``, whatever the reason (missing,
            a directory, permission denied, a parent that is not a directory).
    """
    if is_stdin(path):
        return _read_stdin()
    try:
        return Path(path).read_bytes()
    except IsADirectoryError as exc:
        raise MotionToolError(
            f"cannot read '{path}': {exc.strerror}, expected a .motion file"
        ) from exc
    except OSError as exc:
        raise MotionToolError(f"cannot read '{path}': {exc.strerror or exc}") from exc


def atomic_write(path: str | Path, data: bytes) -> None:
    """Write ``data`` to ``path`` all or nothing: a temporary file beside it, then a rename.

    Missing parent folders are created; the file's permission bits are kept when it exists.
    """
    p = Path(path)
    directory = p.parent if str(p.parent) else Path()
    try:
        mode = p.stat().st_mode & 0o7777
    except FileNotFoundError:
        umask = os.umask(0)
        os.umask(umask)
        mode = 0o666 & ~umask
    except OSError as exc:
        raise MotionToolError(f"cannot write '{path}': {exc.strerror or exc}") from exc
    try:
        directory.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.", suffix=".tmp", dir=directory)
    except OSError as exc:
        raise MotionToolError(f"cannot write '{path}': {exc.strerror or exc}") from exc
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, mode)
        os.replace(tmp, p)
    except OSError as exc:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise MotionToolError(f"cannot write '{path}': {exc.strerror or exc}") from exc
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def collect_motion_files(paths: Iterable[str | Path]) -> list[Path]:
    """Expand directories to the ``*.motion`` files below them (sorted, recursive).

    Files named explicitly are kept whatever their extension; ``-`` (standard input) is kept
    as is. Raises :class:`MotionToolError` for a path that cannot be read (``cannot read
    'PATH': REASON``, as :func:`read_file`) or a directory with no motion file.
    """
    files: list[Path] = []
    for raw in paths:
        p = Path(raw)
        if is_stdin(raw):
            files.append(p)
            continue
        try:
            mode = p.stat().st_mode
        except OSError as exc:
            raise MotionToolError(f"cannot read '{raw}': {exc.strerror or exc}") from exc
        if stat.S_ISDIR(mode):
            found = sorted(q for q in p.rglob("*.motion") if q.is_file())
            if not found:
                raise MotionToolError(f"no .motion file under '{raw}'")
            files.extend(found)
        else:
            files.append(p)
    return files
