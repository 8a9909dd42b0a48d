"""Which files git ignores, for folder searches (``respect-gitignore``): git is asked
(``git check-ignore``, once per repository a search finds files in), so that every rule git
follows holds (nested ``.gitignore`` files, ``!`` negation, a file in an ignored folder staying
ignored, ``.git/info/exclude``, the user's ``core.excludesFile``), and a file git tracks is not
ignored.

Only inside a git repository (the closest folder up with a ``.git``), as ruff does: elsewhere a
``.gitignore`` means nothing to git, and nothing is left out. Where git cannot be run (not
installed), nothing is left out either: a file is never skipped on a guess.

Why git and not a pattern library such as ``pathspec``: the core installs numpy and typer
only (tests/test_package.py keeps it so), a repository whose ``.gitignore`` matters has git,
and git is the one authority on what it ignores.
"""

from __future__ import annotations

import os
import subprocess
from collections.abc import Iterable
from pathlib import Path

__all__ = ["git_ignored"]

_GIT_ENV = ("GIT_DIR", "GIT_WORK_TREE", "GIT_INDEX_FILE")
"""Variables a git hook may set (pre-commit runs inside one) that would point ``git -C ROOT``
at another repository or index."""


def git_ignored(paths: Iterable[Path]) -> set[Path]:
    """The ``paths`` (files) that git ignores, each as given."""
    roots: dict[Path, Path | None] = {}
    by_root: dict[Path, list[Path]] = {}
    for path in paths:
        root = _root((Path.cwd() / path).parent, roots)
        if root is not None:
            by_root.setdefault(root, []).append(path)
    ignored: set[Path] = set()
    for root, found in by_root.items():
        ignored.update(_check_ignore(root, found))
    return ignored


def _root(folder: Path, seen: dict[Path, Path | None]) -> Path | None:
    """The closest folder up from ``folder`` (itself included) with a ``.git``, or None (also
    where a folder on the way may not be searched: git could not tell either)."""
    if folder not in seen:
        try:
            here = (folder / ".git").exists()
        except OSError:  # a folder above that this user may not search
            seen[folder] = None
            return None
        if here:
            seen[folder] = folder
        else:
            up = folder.parent
            seen[folder] = None if up == folder else _root(up, seen)
    return seen[folder]


def _check_ignore(root: Path, paths: list[Path]) -> list[Path]:
    """Those of ``paths`` (in the repository at ``root``) git ignores: one ``git check-ignore``
    for them all (none where git cannot answer)."""
    absolute = {str(Path.cwd() / p): p for p in paths}
    env = {k: v for k, v in os.environ.items() if k not in _GIT_ENV}
    try:
        proc = subprocess.run(
            ["git", "-C", str(root), "check-ignore", "--stdin", "-z"],
            input="\0".join(absolute).encode("utf-8", "surrogateescape"),
            capture_output=True,
            env=env,
            check=False,
        )
    except OSError:  # no git: nothing is left out on a guess
        return []
    if proc.returncode not in (0, 1):  # 1: none ignored; else git could not tell
        return []
    names = proc.stdout.decode("utf-8", "surrogateescape").split("\0")
    return [absolute[n] for n in names if n in absolute]
