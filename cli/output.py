"""Writing a command's output to stdout or to a file (atomically)."""

from __future__ import annotations

import sys
from pathlib import Path

from motiontool.motionfmt.fileio import atomic_write

__all__ = ["emit"]


def emit(text: str, output: Path | None) -> None:
    """Write ``text`` to ``output`` (temporary file, then rename) or to stdout.

    Names read from a file keep undecodable bytes as surrogates; they are written back as the
    original bytes.
    """
    data = text.encode("utf-8", "surrogateescape")
    if output is not None and str(output) != "-":
        atomic_write(output, data)
        return
    sys.stdout.flush()
    sys.stdout.buffer.write(data)
    sys.stdout.buffer.flush()
