"""Reading motion files and writing them safely (temporary file, then rename)."""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Iterable
from pathlib import Path

from motiontool.motionfmt.errors import MotionToolError

__all__ = ["atomic_write", "collect_motion_files", "read_file"]


def read_file(path: str | Path) -> bytes:
    """The bytes of ``path``; a one-line :class:`MotionToolError` when it cannot be read."""
    p = Path(path)
    if p.is_dir():
        raise MotionToolError(f"'{path}' is a directory, expected a .motion file")
    try:
        return p.read_bytes()
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

    Files named explicitly are kept whatever their extension. Raises :class:`MotionToolError`
    for a path that does not exist or a directory with no motion file.
    """
    files: list[Path] = []
    for raw in paths:
        p = Path(raw)
        if p.is_dir():
            found = sorted(q for q in p.rglob("*.motion") if q.is_file())
            if not found:
                raise MotionToolError(f"no .motion file under '{raw}'")
            files.extend(found)
        elif p.exists():
            files.append(p)
        else:
            raise MotionToolError(f"'{raw}': no such file or directory")
    return files
