"""The robot checks' findings of small files, kept on disk: a file checked before against the
same robot is not checked again.

In a pre-commit hook or an editor, most of a small file's 0.2 s is spent importing numpy for
the limits, velocity and collision checks, which then take a few milliseconds. Their findings
depend only on:

- the file's bytes and its absolute path (the findings are stored without it, and take the
  name the file is given when they are read: the hook and the editor name it differently);
- the robot: every fact of its :class:`~motiontool.kinematics.robots.RobotSpec`, its model's
  sha256 included;
- the checks and their options: the robot asked for, the checks, the time step, the collision
  tolerance, grouping, the front end's wording of the hints;
- the code that computes them: the path, size and modification time of every source file of
  motiontool, and of the installed numpy, Pinocchio and coal
  (:mod:`~motiontool.disk_cache`).

The sha256 of all of it is the key (:func:`findings_key`). A file whose key is stored gets its
findings from the store, and numpy is not imported. Only files of at most :data:`MAX_BYTES`
with at most :data:`MAX_FINDINGS` findings are stored: a large file is checked every time (its
findings stream to the report, never all held). Checks whose findings depend on other files
(MT309 compares a file with its siblings) are never stored: they run every time.

The store is ``$XDG_CACHE_HOME/motiontool/lint`` (``~/.cache/motiontool/lint``), pruned to
:data:`MAX_MB` MB and :data:`MAX_RESULTS` entries, least recently used first. A store that
cannot be read or written is not an error: the checks run.
"""

from __future__ import annotations

import functools
import hashlib
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import NamedTuple, TypeVar

from motiontool.disk_cache import (
    BYTES_PER_MB,
    ResultCache,
    cache_root,
    code_stamp,
)
from motiontool.errors import MissingExtraError
from motiontool.motionfmt.diagnostics import Diagnostic, PoseFinding, Run, Severity, Worst

__all__ = [
    "MAX_BYTES",
    "MAX_FINDINGS",
    "MAX_MB",
    "MAX_RESULTS",
    "FindingsCache",
    "Stored",
    "findings_key",
    "lint_cache_dir",
]

MAX_BYTES = 1 << 20
"""The largest file whose findings are stored, bytes (about 4,000 poses of 25 joints)."""
MAX_FINDINGS = 5000
"""The most findings a stored file may have (grouped, as reported)."""
MAX_MB = 100
"""The size the store is pruned to, MB (a clean file's entry is about 100 bytes)."""
MAX_RESULTS = 20_000
"""The most entries the store is pruned to (each takes a block of the disk, however small):
a few versions of each file of a large motion library."""
_T = TypeVar("_T")

_LAYOUT = "motiontool-findings-4"
"""The layout of a stored entry: a change to :func:`_encode` is a new layout."""
_PRUNE_PREFIX = "00"
"""Storing a key that starts with this prunes the store: one store in 256, whatever the
files (no count of the stores is kept)."""
_CODE_FOLDERS = ("motionfmt", "kinematics", "sim", "cli")
"""motiontool's code, below the package's root; its top-level modules are added."""


def lint_cache_dir() -> Path:
    """``$XDG_CACHE_HOME/motiontool/lint`` (``~/.cache/motiontool/lint``)."""
    return cache_root() / "lint"


@functools.cache
def _code_stamp() -> str:
    """What changes when the code that computes findings changes (see the module doc)."""
    return code_stamp(_CODE_FOLDERS, ("numpy", "pinocchio", "coal"))


def findings_key(options: Iterable[str], path: str, data: bytes) -> str:
    """The key (sha256, hex) of the findings of ``data`` (the file ``path``) under the checks'
    ``options`` (each a string that says everything it stands for, such as a ``repr``)."""
    h = hashlib.sha256()
    for part in (_LAYOUT, _code_stamp(), *options, path):
        h.update(part.encode("utf-8", "surrogateescape") + b"\0")
    h.update(data)
    return h.hexdigest()


class FindingsCache:
    """The store of :mod:`findings_cache <motiontool.kinematics.checks.findings_cache>`."""

    def __init__(
        self,
        directory: Path | None = None,
        max_mb: float = MAX_MB,
        *,
        max_results: int = MAX_RESULTS,
        read_only: bool = False,
    ) -> None:
        self.results = ResultCache(
            lint_cache_dir() if directory is None else directory,
            round(max_mb * BYTES_PER_MB),
            max_results,
        )
        self.read_only = read_only
        """Read, never store: the editor's unsaved text, one version a keystroke."""

    def load(self, key: str, path: str) -> Stored | None:
        """What is stored under ``key``, its findings on the file named ``path`` (as the user
        names it this time), or None (nothing stored, or unreadable)."""
        doc = self.results.load(key)
        if doc is None or doc.get("layout") != _LAYOUT:
            return None
        try:
            findings = [_decode(item, path) for item in doc["findings"]]
            skipped = {
                _of(name, str): MissingExtraError(*(_of(f, str) for f in _list(fields, 4)))
                for name, fields in doc["skipped"].items()
            }
        except (KeyError, TypeError, ValueError, AttributeError):
            return None
        return Stored(findings, skipped)

    def store(
        self,
        key: str,
        findings: Sequence[Diagnostic],
        skipped: Mapping[str, MissingExtraError],
        path: str,
    ) -> None:
        """Store ``findings`` on the file named ``path`` under ``key`` (the caller keeps to
        :data:`MAX_FINDINGS`), with the checks ``skipped`` for a missing library. They are
        stored without the file's name, which :meth:`load` puts back as it is named then (the
        hook names it from the repository's root, the editor by its absolute path); findings
        whose words name the file are not stored. Nothing is stored where :attr:`read_only`;
        a store that cannot be written is left as it is."""
        import json  # where findings are stored: a --no-cache run needs no JSON

        items = [_encode(d) for d in findings]
        if self.read_only or json.dumps(path)[1:-1] in json.dumps(items):
            return
        doc = {
            "layout": _LAYOUT,
            "findings": items,
            "skipped": {n: [e.module, e.extra, e.what, e.library] for n, e in skipped.items()},
        }
        if self.results.store(key, doc) and key.startswith(_PRUNE_PREFIX):
            self.results.prune()


class Stored(NamedTuple):
    """A file's findings as stored, and the checks that were skipped for a missing library
    (by name, :attr:`RobotChecks.skipped <motiontool.kinematics.checks.RobotChecks.skipped>`):
    their MT902 note belongs to every report the findings go into."""

    findings: list[Diagnostic]
    skipped: dict[str, MissingExtraError]


def _encode(d: Diagnostic) -> list[object]:
    """``d`` as JSON values, its fields in order but its path (floats as JSON writes them:
    exactly)."""
    return [
        d.code,
        int(d.severity),
        d.line,
        d.column,
        d.message,
        d.hint,
        d.joint,
        d.time_ms,
        d.end_column,
        None if d.pose is None else list(d.pose),
        None if d.run is None else list(d.run),  # its worst, a tuple, as a JSON array
    ]


def _decode(item: object, path: str) -> Diagnostic:
    """The :class:`Diagnostic` on file ``path`` that :func:`_encode` wrote; ValueError for
    anything else (a damaged or foreign entry)."""
    code, severity, line, column, message, hint, joint, time_ms, end, pose, run = _list(item, 11)
    return Diagnostic(
        _of(code, str),
        Severity(_of(severity, int)),
        path,
        _of(line, int),
        _of(column, int),
        _of(message, str),
        _or_none(hint, str),
        _or_none(joint, str),
        _or_none(time_ms, int),
        _or_none(end, int),
        None if pose is None else _pose(pose),
        None if run is None else _run(run),
    )


def _pose(item: object) -> PoseFinding:
    pose, subject, value, unit, excess, noun, hint, amount = _list(item, 8)
    return PoseFinding(
        _of(pose, int),
        _of(subject, str),
        _number(value),
        _of(unit, str),
        _number(excess),
        _of(noun, str),
        _or_none(hint, str),
        _or_none(amount, str),
    )


def _run(item: object) -> Run:
    total, end_line, worst, noun, identity, runs = _list(item, 6)
    value, unit, line, column, time_ms = _list(worst, 5)
    return Run(
        _of(total, int),
        _of(end_line, int),
        Worst(
            _number(value), _of(unit, str), _of(line, int), _of(column, int), _or_none(time_ms, int)
        ),
        _of(noun, str),
        _of(identity, str),
        _of(runs, int),
    )


def _list(item: object, n: int) -> list[object]:
    if not isinstance(item, list) or len(item) != n:
        raise ValueError(f"expected a list of {n}")
    return item


def _of(value: object, kind: type[_T]) -> _T:
    if not isinstance(value, kind):
        raise ValueError(f"expected {kind.__name__}")
    return value


def _or_none(value: object, kind: type[_T]) -> _T | None:
    return None if value is None else _of(value, kind)


def _number(value: object) -> float:
    if not isinstance(value, int | float):
        raise ValueError("expected a number")
    return value
