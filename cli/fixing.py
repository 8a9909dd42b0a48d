"""``validate --fix`` / ``--diff``: apply the fixes of :mod:`motiontool.motionfmt.fixes` to
files (atomically, each file whole or not at all), or show them as a unified diff."""

from __future__ import annotations

import difflib
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from motiontool.cli.text import plural
from motiontool.errors import MotionToolError
from motiontool.motionfmt.fileio import atomic_write, is_stdin, read_file
from motiontool.motionfmt.fixes import RobotPlanner, fix_bytes

__all__ = ["FixRun", "fix_files"]


@dataclass
class FixRun:
    """What ``--fix`` changed: fixes applied by code, files changed, the diff text."""

    applied: Counter[str] = field(default_factory=Counter)
    files: list[str] = field(default_factory=list)
    diff: list[bytes] = field(default_factory=list)

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
) -> FixRun:
    """Fix every file (``unsafe``: the unsafe fixes too, and those of ``robot(path, data)``'s
    planner); write each changed file atomically with ``write``, else collect a unified diff.

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
        else:
            name = str(path).encode("utf-8", "surrogateescape")
            # a/ and b/ as git writes them (git apply reads it), but for an absolute path.
            before, after = (b"", b"") if path.is_absolute() else (b"a/", b"b/")
            run.diff += difflib.diff_bytes(
                difflib.unified_diff,
                data.splitlines(keepends=True),
                result.data.splitlines(keepends=True),
                before + name,
                after + name,
            )
    return run
