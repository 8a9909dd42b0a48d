"""``validate --fix`` / ``--diff``: apply the fixes of :mod:`motiontool.motionfmt.fixes` to
files (atomically, each file whole or not at all), or show them as a unified diff."""

from __future__ import annotations

import difflib
import functools
from collections import Counter
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from motiontool.cli.output import in_blocks
from motiontool.cli.text import plural
from motiontool.motionfmt.fileio import STDOUT, atomic_write, is_stdin, read_file
from motiontool.motionfmt.fixes import RobotPlanner, fix_bytes

__all__ = ["FixRun", "fix_files"]


@dataclass
class FixRun:
    """What ``--fix`` changed (or ``--diff`` would change): fixes applied by code, files
    changed, and with ``--fix`` standard input's text as fixed (None: no standard input)."""

    applied: Counter[str] = field(default_factory=Counter)
    files: list[str] = field(default_factory=list)
    stdin: bytes | None = None

    def line(self) -> str:
        """``fixed 3 findings in 1 file (MT203 x2, MT204)``, or ``nothing to fix``."""
        total = sum(self.applied.values())
        if not total:
            return "nothing to fix"
        codes = ", ".join(
            f"{code} x{n}" if n > 1 else code for code, n in sorted(self.applied.items())
        )
        return f"fixed {plural(total, 'finding')} in {plural(len(self.files), 'file')} ({codes})"


def fix_files(
    files: Sequence[Path],
    *,
    unsafe: bool,
    write: bool,
    robot: Callable[[Path, bytes], RobotPlanner | None] | None = None,
    diff: Callable[[bytes], object] | None = None,
    named: Callable[[Path], Path] | None = None,
    select: Callable[[Path, str], bool] | None = None,
) -> FixRun:
    """Fix every file (``unsafe``: the unsafe fixes too, and those of ``robot(path, data)``'s
    planner); write each changed file atomically with ``write`` (standard input's text, fixed
    or not, to stdout, as ruff does), else give its unified diff to ``diff``, a block of about
    64 KiB at a time as it is made (never the whole diff held), each file under the name
    ``named(path)`` gives it (standard input's, ``--stdin-filename``); ``select(path, code)``:
    whether the fixes of ``code`` apply to ``path`` (those of a code left out do not, as ruff
    fixes only the rules it selects).

    Raises:
        MotionToolError: a file that cannot be read or written.
    """
    run = FixRun()
    for path in files:
        data = read_file(path)
        planner = robot(path, data) if unsafe and robot is not None else None
        keep = None if select is None else functools.partial(select, path)
        result = fix_bytes(data, str(path), unsafe=unsafe, robot=planner, select=keep)
        if is_stdin(path) and write:
            run.stdin = result.data
            atomic_write(STDOUT, result.data)
        if result.data == data:
            continue
        run.files.append(str(path))
        run.applied.update(f.code for f in result.applied)
        if write and not is_stdin(path):
            atomic_write(path, result.data)
        elif diff is not None:
            name = path if named is None else named(path)
            for block in in_blocks(_unified(name, data, result.data)):
                diff(block)
    return run


def _unified(path: Path, old: bytes, new: bytes) -> Iterator[bytes]:
    """The unified diff of ``path`` from ``old`` to ``new``, line by line, as ``git apply``
    and ``patch -p1`` read it: lines split at ``\\n`` alone (a carriage return stays in its
    line), a last line without one followed by ``\\ No newline at end of file``; ``a/`` and
    ``b/`` before the name as git writes them, but for an absolute path, and the name as git
    writes it (:func:`_quoted`)."""
    name = str(path).encode("utf-8", "surrogateescape")
    before, after = (b"", b"") if path.is_absolute() else (b"a/", b"b/")
    lines = difflib.diff_bytes(
        difflib.unified_diff,
        _lines(old),
        _lines(new),
        _quoted(before + name),
        _quoted(after + name),
    )
    for line in lines:
        yield line if line.endswith(b"\n") else line + b"\n" + NO_NEWLINE


NO_NEWLINE = b"\\ No newline at end of file\n"
"""What follows a diff line that ends its file without a newline (git, GNU diff)."""


def _lines(data: bytes) -> list[bytes]:
    """The lines of ``data``, each with its ``\\n`` but the last where the file has no final
    newline (``bytes.splitlines`` would also split at a lone carriage return)."""
    lines = [line + b"\n" for line in data.split(b"\n")]
    last = lines.pop()[:-1]
    return [*lines, last] if last else lines


_C_ESCAPES = {ord('"'): b'\\"', ord("\\"): b"\\\\", 7: b"\\a", 8: b"\\b", 9: b"\\t"}
_C_ESCAPES |= {10: b"\\n", 11: b"\\v", 12: b"\\f", 13: b"\\r"}
"""The bytes of a name that git writes as a backslash and a character; other control
characters as a backslash and three octal digits."""


def _quoted(name: bytes) -> bytes:
    """``name`` as git writes it in a diff header, and ``git apply`` and GNU ``patch`` read
    it: in double quotes with C escapes (``\\t``, ``\\"``, octal) where it holds a quote, a
    backslash or a control character; else as it is, with a tab after a name that holds a
    space (``patch`` ends a name at a space where no tab follows)."""
    if not any(b < 0x20 or b in b'"\\\x7f' for b in name):
        return name + b"\t" if b" " in name else name
    out = b"".join(
        _C_ESCAPES.get(b, b"\\%03o" % b if b < 0x20 or b == 0x7F else bytes((b,))) for b in name
    )
    return b'"' + out + b'"'
