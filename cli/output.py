"""Writing a command's output to stdout or to a file (atomically), never over an input."""

from __future__ import annotations

import os
import sys
from collections.abc import Iterable
from pathlib import Path

from motiontool.motionfmt.errors import MotionToolError
from motiontool.motionfmt.fileio import atomic_write, is_stdin

__all__ = ["emit", "emit_bytes", "refuse_overwrite", "same_file"]


def same_file(a: Path, b: Path) -> bool:
    """True when ``a`` and ``b`` name one file: the same path, a symlink to it or a hard link
    (same device and inode); paths that do not both exist are compared resolved."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return a.resolve() == b.resolve()


def refuse_overwrite(
    output: Path | None,
    inputs: Iterable[Path],
    option: str,
    advice: str = "write to another file",
) -> None:
    """Refuse to write ``output`` where it is one of ``inputs`` (through a symlink or a hard
    link too): every command that writes a file calls this before it reads or writes anything.

    ``None`` and ``-`` (stdout) are never an input file; nor is an output that does not exist
    yet.

    Raises:
        MotionToolError: ``OPTION 'OUTPUT' is the input file ['INPUT']; ADVICE``.
    """
    if output is None or is_stdin(output) or not os.path.lexists(output):
        return
    for source in inputs:
        if is_stdin(source) or not same_file(output, source):
            continue
        named = "" if str(source) == str(output) else f" '{source}'"
        raise MotionToolError(f"{option} '{output}' is the input file{named}; {advice}")


def emit(text: str, output: Path | None) -> None:
    """Write ``text`` to ``output`` (temporary file, then rename) or to stdout.

    Names read from a file keep undecodable bytes as surrogates; they are written back as the
    original bytes.
    """
    emit_bytes(text.encode("utf-8", "surrogateescape"), output)


def emit_bytes(data: bytes, output: Path | None) -> None:
    """Write ``data`` to ``output`` (temporary file, then rename) or, for None or ``-``, to
    stdout."""
    if output is not None and str(output) != "-":
        atomic_write(output, data)
        return
    sys.stdout.flush()
    sys.stdout.buffer.write(data)
    sys.stdout.buffer.flush()
