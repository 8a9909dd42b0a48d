"""``validate --fix`` / ``--diff``: apply the fixes of :mod:`motiontool.motionfmt.fixes` to
files (atomically, each file whole or not at all), or show them as a unified diff."""

from __future__ import annotations

import difflib
from collections import Counter
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from motiontool.cli.output import in_blocks
from motiontool.cli.text import plural
from motiontool.errors import MotionToolError
from motiontool.motionfmt.fileio import atomic_write, is_stdin, read_file
from motiontool.motionfmt.fixes import RobotPlanner, fix_bytes

__all__ = ["FixRun", "fix_files"]


@dataclass
class FixRun:
    """What ``--fix`` changed (or ``--diff`` would change): fixes applied by code, files
    changed."""

    applied: Counter[str] = field(default_factory=Counter)
    files: list[str] = field(default_factory=list)

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
) -> FixRun:
    """Fix every file (``unsafe``: the unsafe fixes too, and those of ``robot(path, data)``'s
    planner); write each changed file atomically with ``write``, else give its unified diff
    to ``diff``, a block of about 64 KiB at a time as it is made (never the whole diff held).

    Raises:
        MotionToolError: standard input with ``write`` (a diff is fine), or a file that cannot
            be read or written.
    """
    run = FixRun()
    for path in files:
        if is_stdin(path) and write:
            raise MotionToolError("--fix writes files back: for standard input use --diff")
        data = read_file(path)
        planner = robot(path, data) if unsafe and robot is not None else None
        result = fix_bytes(data, str(path), unsafe=unsafe, robot=planner)
        if result.data == data:
            continue
        run.files.append(str(path))
        run.applied.update(f.code for f in result.applied)
        if write:
            atomic_write(path, result.data)
        elif diff is not None:
            for block in in_blocks(_unified(path, data, result.data)):
                diff(block)
    return run


def _unified(path: Path, old: bytes, new: bytes) -> Iterator[bytes]:
    """The unified diff of ``path`` from ``old`` to ``new``, line by line: ``a/`` and ``b/``
    before the name as git writes them (``git apply`` reads it), but for an absolute path."""
    name = str(path).encode("utf-8", "surrogateescape")
    before, after = (b"", b"") if path.is_absolute() else (b"a/", b"b/")
    return difflib.diff_bytes(
        difflib.unified_diff,
        old.splitlines(keepends=True),
        new.splitlines(keepends=True),
        before + name,
        after + name,
    )
