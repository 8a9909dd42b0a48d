"""What every rendering of a validation report shares: the order of findings, the summary
line, columns in characters or UTF-16 units, and the context a renderer gets."""

from __future__ import annotations

import enum
import functools
import os
from collections import Counter
from collections.abc import Callable, Iterable, Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

from motiontool.cli.text import plural
from motiontool.errors import MotionToolError
from motiontool.motionfmt.diagnostics import Diagnostic, Severity
from motiontool.motionfmt.validate import FileReport

if TYPE_CHECKING:
    import sqlite3

    from motiontool.motionfmt.fixes import Fix

__all__ = [
    "PLAIN",
    "Context",
    "Fingerprints",
    "FixCounts",
    "Order",
    "Totals",
    "Writer",
    "fix_json",
    "fix_summary",
    "project_root",
    "relative_path",
    "summary",
    "text_column",
    "with_hint",
]


class Order(enum.StrEnum):
    """Order of the findings in the text, GitHub and SARIF reports."""

    file = "file"  # file by file, by position in each
    severity = "severity"  # errors first, then warnings, then notes (each in file order)


def summary(totals: Totals) -> str:
    """``checked 3 files: 1 error, 2 warnings, 0 notes``, then every check skipped for a
    missing library (MT902): ``; collision check skipped: pip install 'motiontool[kinematics]'``."""
    skipped = "".join(
        f"; {d.message.partition(':')[0]}: {d.hint}" for d in totals.notes if d.code == "MT902"
    )
    hidden = totals.hidden
    not_shown = f"; {plural(hidden, 'finding')} not shown (max-findings)" if hidden else ""
    return (
        f"checked {plural(totals.files, 'file')}: "
        f"{plural(totals.found(Severity.ERROR), 'error')}, "
        f"{plural(totals.found(Severity.WARNING), 'warning')}, "
        f"{plural(totals.found(Severity.INFO), 'note')}{skipped}{not_shown}"
    )


class Totals(NamedTuple):
    """What a report says of the whole run once every file is checked: how many files, the
    findings of each severity (shown or past ``max-findings``, the run's notes included),
    the run's notes (about no file), and how many findings ``max-findings`` leaves out."""

    files: int
    counts: dict[Severity, int]
    notes: list[Diagnostic]
    hidden: int = 0

    def found(self, severity: Severity) -> int:
        """How many findings of ``severity`` the run has."""
        return self.counts.get(severity, 0)


class Writer:
    """A report in one format, written from the files it is handed: a renderer never reads
    or checks a file. The caller checks each file and hands it over
    (:func:`motiontool.cli.validate_report.report_pieces`): :meth:`head`, then :meth:`file`
    for each file in file order (with ``order`` severity: a pass over the files per severity,
    errors first, each file handed with its findings of that severity), then :meth:`tail`
    with the run's :class:`Totals`. A writer that ``counts_first`` (its head says how many)
    is first handed every file to :meth:`count`, and its head gets the totals.

    Attributes:
        order: how the findings are handed (``context.order``; file order for a format that
            writes a file's findings together).
        counts_first: a pass over the files (:meth:`count`) before the head.
        robots_first: the head names the robot of every file (the caller surveys them first).
    """

    counts_first = False
    robots_first = False

    def __init__(self, context: Context | None = None) -> None:
        self.context = PLAIN if context is None else context
        self.order = self.context.order

    def count(self, f: FileReport, shown: Iterable[Diagnostic]) -> None:
        """The first pass of a writer that :attr:`counts_first`."""

    def head(self, totals: Totals | None) -> Iterator[str]:
        """The text before the files (``totals``: known where :attr:`counts_first`)."""
        return iter(())

    def file(self, f: FileReport, shown: Iterable[Diagnostic]) -> Iterator[str]:
        """The text of file ``f`` and its findings ``shown`` (made as they are read)."""
        raise NotImplementedError

    def tail(self, totals: Totals) -> Iterator[str]:
        """The text after the files."""
        return iter(())


class FixCounts:
    """How many findings shown a fix covers, counted as a report goes: safe, and unsafe only."""

    def __init__(self) -> None:
        self.safe = self.unsafe = 0

    def add(self, fix: tuple[bool, str] | None) -> None:
        """Count a finding's :meth:`~FileReport.fix_summary`."""
        if fix is not None and fix[0]:
            self.safe += 1
        elif fix is not None:
            self.unsafe += 1


def fix_summary(counts: FixCounts) -> str:
    """``; 3 fixable with --fix (1 more with --fix --unsafe-fixes)``, ``; 2 fixable with --fix
    --unsafe-fixes`` where no safe fix exists, or nothing; from ``counts`` made while the
    report was written."""
    safe, unsafe = counts.safe, counts.unsafe
    if not safe:
        return f"; {unsafe} fixable with --fix --unsafe-fixes" if unsafe else ""
    more = f" ({unsafe} more with --fix --unsafe-fixes)" if unsafe else ""
    return f"; {safe} fixable with --fix{more}"


def fix_json(fixes: Sequence[Fix]) -> dict[str, Any] | None:
    """A finding's ``fix`` in the JSON report: safe or not, what it does, its edits (byte
    columns, end exclusive; ``end_column`` null: to the end of the line; ``replacement`` null:
    the line goes)."""
    if not fixes:
        return None
    return {
        "safe": all(f.safe for f in fixes),
        "title": fixes[0].title,
        "edits": [
            {
                "line": f.line,
                "column": f.column,
                "end_column": f.end_column,
                "replacement": None
                if f.replacement is None
                else f.replacement.decode("utf-8", "surrogateescape"),
            }
            for f in fixes
        ],
    }


def with_hint(d: Diagnostic) -> str:
    """The message, then ``(hint: ...)`` where the diagnostic has one."""
    return d.message + (f" (hint: {d.hint})" if d.hint else "")


class Context(NamedTuple):
    """What a renderer may use besides the report.

    Attributes:
        color: ANSI colours (text only; the caller decides: never for a file or a pipe).
        order: the order of findings (formats that list them one by one).
        strict: warnings fail the run too (``--strict``), for formats that say pass or fail.
        robot_line: the text report's first line (which robot checked what), built only by
            the formats that show it.
        robot_json: the JSON report's ``robot`` section and ``stamps`` (with the model hash),
            built only by the formats that ask for it.
        quiet: the findings only (``--quiet``): no robot line or summary in the text report.
    """

    color: bool = False
    order: Order = Order.file
    strict: bool = False
    robot_line: Callable[[], str] = lambda: ""
    robot_json: Callable[[], dict[str, Any]] = lambda: {}
    quiet: bool = False


def text_column(raw: bytes, column: int, *, utf16: bool) -> int:
    """The 1-based byte ``column`` of source line ``raw`` as a 1-based column in characters
    (Unicode code points), or in UTF-16 code units with ``utf16``. An undecodable byte counts
    as one; a column past the end of the line stays that many past it."""
    head = raw[: max(column - 1, 0)]
    if head.isascii():  # a byte, a character, a UTF-16 unit each (most lines)
        return max(column, 1)
    text = head.decode("utf-8", "surrogateescape")
    units = len(text)
    if utf16:
        units += sum(1 for ch in text if ord(ch) > 0xFFFF)
    return units + max(column - 1 - len(head), 0) + 1


PLAIN = Context()
"""No colour, file order, no robot line or section: what a renderer uses when given nothing."""


def project_root() -> Path:
    """The repository the run is in: the closest folder from the working directory up that
    holds ``.git`` (a folder, or a file in a worktree), else the working directory. Reports
    give paths relative to it, as code-scanning and Code Quality dashboards show them."""
    return _root_of(Path.cwd())


@functools.cache
def _root_of(cwd: Path) -> Path:
    for folder in (cwd, *cwd.parents):
        if (folder / ".git").exists():
            return folder
    return cwd


def relative_path(path: str) -> Path | None:
    """``path`` relative to :func:`project_root` (as written, then with links resolved), or
    None for a file outside it (found once per path and working directory: a report asks for
    each of its findings)."""
    return _relative(os.getcwd(), path)


@functools.lru_cache(maxsize=4096)
def _relative(cwd: str, path: str) -> Path | None:
    root = _root_of(Path(cwd))
    for candidate in (Path(os.path.abspath(path)), Path(path).resolve()):
        try:
            return candidate.relative_to(root)
        except ValueError:
            continue
    return None


class Fingerprints:
    """Stable identities of findings across runs and commits: a hash of the code, the path
    relative to the project and the message (of a grouped finding, which names lines: its
    subject and first pose time, :attr:`Diagnostic.identity`), and the finding's rank among
    identical ones of its severity in its file, in file order; not its line, so that a line
    added above a finding leaves it the same finding.

    The ranks are counted for one file at a time (identical findings are of one file: the
    path is in the key) and forgotten at the next, so that memory does not grow with the
    run; a report by severity reads a file's findings of one severity together, and they
    get the same ranks as in file order. A file with more than :data:`HELD_KEYS` distinct
    findings (one finding per pose of a file of random values, ``--no-group``: millions) has
    them counted in a temporary SQLite table on disk from then on, so that memory does not
    grow with one file either."""

    HELD_KEYS = 1 << 18
    """Distinct findings of a file counted in memory (16 bytes of digest each, about 100
    bytes with the counter's own); past them, on disk."""

    def __init__(self) -> None:
        self._seen: Counter[bytes] = Counter()  # 16 bytes of a digest of key and severity
        self._file: tuple[str, Severity] | None = None
        self._disk: sqlite3.Connection | None = None

    def __call__(self, d: Diagnostic, order: Order = Order.file) -> str:
        import hashlib  # imported by the formats that fingerprint findings only

        block = (d.path, d.severity if order is Order.severity else Severity.INFO)
        if block != self._file:
            self._forget()
            self._file = block
        rel = relative_path(d.path)
        key = f"{d.code}\0{rel.as_posix() if rel else d.path}\0{d.identity}"
        raw = key.encode("utf-8", "surrogateescape")
        seen = hashlib.sha256(raw + f"\0{d.severity}".encode()).digest()[:16]
        return hashlib.sha256(raw + f"\0{self._rank(seen)}".encode()).hexdigest()

    def _rank(self, seen: bytes) -> int:
        """How many times ``seen`` has come in this file, this one included."""
        if self._disk is None:
            self._seen[seen] += 1
            rank = self._seen[seen]
            if len(self._seen) > self.HELD_KEYS:
                self._spill()
            return rank
        import sqlite3

        try:
            self._disk.execute(_BUMP, (seen,))
            row = self._disk.execute("SELECT n FROM seen WHERE k = ?", (seen,)).fetchone()
        except sqlite3.Error as exc:
            raise _no_disk(exc) from exc
        return int(row[0])

    def _spill(self) -> None:
        """Go on counting in a temporary table on disk (deleted when it is closed)."""
        import sqlite3

        try:
            self._disk = sqlite3.connect("")  # '': a private temporary database on disk
            self._disk.execute(
                "CREATE TABLE seen (k BLOB PRIMARY KEY, n INTEGER NOT NULL) WITHOUT ROWID"
            )
            self._disk.executemany("INSERT INTO seen VALUES (?, ?)", self._seen.items())
        except sqlite3.Error as exc:
            raise _no_disk(exc) from exc
        self._seen.clear()

    def _forget(self) -> None:
        """A new file: no finding seen yet."""
        self._seen.clear()
        if self._disk is not None:
            self._disk.close()
            self._disk = None


def _no_disk(exc: Exception) -> MotionToolError:
    import tempfile

    return MotionToolError(
        f"cannot count a file's findings in a temporary file under {tempfile.gettempdir()}: "
        f"{exc}; is that disk full?"
    )


_BUMP = "INSERT INTO seen VALUES (?, 1) ON CONFLICT(k) DO UPDATE SET n = n + 1"
"""Count one more of a finding (SQLite >= 3.24)."""
