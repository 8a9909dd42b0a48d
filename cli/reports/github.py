"""``--format github``: GitHub Actions workflow commands, one annotation per finding."""

from __future__ import annotations

import functools
import os
from collections import Counter
from collections.abc import Iterable, Iterator
from pathlib import Path

from motiontool.cli.jsontext import escape_undecodable
from motiontool.cli.reports.common import Context, Totals, Writer, summary, text_column, with_hint
from motiontool.cli.text import plural, shown
from motiontool.motionfmt.diagnostics import CODES, Diagnostic, Severity
from motiontool.motionfmt.validate import FileReport

__all__ = ["SHOWN_PER_KIND", "GithubWriter"]


def _gh_escape(text: str, *, prop: bool = False) -> str:
    text = text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")
    if prop:
        text = text.replace(":", "%3A").replace(",", "%2C")
    return text


_GH_COMMAND = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "notice"}

SHOWN_PER_KIND = 10
"""Annotations of each kind (error, warning, notice) GitHub shows per step; it drops the
others (they stay in the step's log)."""


def _workspace_path(path: str) -> str:
    """``path`` as GitHub places an annotation: relative to the checkout (``GITHUB_WORKSPACE``,
    set by the runner, else the working directory), as written or with links resolved; as
    given for a file outside it."""
    return _relative(os.environ.get("GITHUB_WORKSPACE") or os.getcwd(), os.getcwd(), path)


@functools.lru_cache(maxsize=4096)
def _relative(workspace: str, cwd: str, path: str) -> str:
    """Found once per path, checkout and working directory (a relative ``path`` is from
    ``cwd``): a report asks for each of its findings."""
    roots = (Path(workspace), Path(workspace).resolve())
    for candidate in (Path(os.path.abspath(path)), Path(path).resolve()):
        for root in roots:
            try:
                return candidate.relative_to(root).as_posix()
            except ValueError:
                continue
    return path


def _not_shown(counts: Counter[str]) -> str | None:
    """The closing notice when a kind of annotation passes :data:`SHOWN_PER_KIND` (None:
    GitHub shows them all): how many are not shown, and where every finding is. It is a
    notice unless GitHub shows no more notices, then a warning, as long as one can show."""
    over = {kind: n - SHOWN_PER_KIND for kind, n in counts.items() if n > SHOWN_PER_KIND}
    if not over:
        return None
    noun = {"error": "error", "warning": "warning", "notice": "note"}
    hidden = ", ".join(
        plural(over[k], noun[k]) for k in ("error", "warning", "notice") if k in over
    )
    kind = next((k for k in ("notice", "warning") if counts[k] < SHOWN_PER_KIND), "notice")
    title = _gh_escape("motiontool: annotations not shown", prop=True)
    return (
        f"::{kind} title={title}::GitHub shows {SHOWN_PER_KIND} annotations of each kind per "
        f"step; not shown: {hidden}. Every finding is in this step's log, in --format sarif "
        "uploaded to code scanning, and in a job summary written as docs/ci.md shows."
    )


class GithubWriter(Writer):
    """GitHub Actions workflow commands: one annotation per diagnostic, written as they are
    made, then a summary.

    ``col`` and ``endColumn`` count characters (GitHub's unit), converted from byte columns;
    a run's note (a check skipped for a missing library) is an annotation without a file.
    A name that is not UTF-8 is written as \\xNN, as in the JSON and SARIF reports: the runner
    reads the log as UTF-8. Paths are relative to the checkout (``GITHUB_WORKSPACE``), where
    GitHub looks for them. Where a kind passes what GitHub shows (:data:`SHOWN_PER_KIND`), a
    closing notice says how many are not shown and where they are.
    """

    def __init__(self, context: Context | None = None) -> None:
        super().__init__(context)
        self.counts: Counter[str] = Counter()

    def file(self, f: FileReport, shown_: Iterable[Diagnostic]) -> Iterator[str]:
        for d in shown_:
            raw = f.source_line(d.line)
            col = text_column(raw, d.column, utf16=False)
            path = _gh_escape(_workspace_path(d.path), prop=True)
            props = [f"file={path}", f"line={d.line}", f"col={col}"]
            if d.end_column and d.end_column >= d.column:
                props.append(f"endColumn={text_column(raw, d.end_column, utf16=False)}")
            title = f"{d.code} {CODES[d.code].title}" if d.code in CODES else d.code
            props.append(f"title={_gh_escape(title, prop=True)}")
            self.counts[_GH_COMMAND[d.severity]] += 1
            message = _gh_escape(shown(with_hint(d)))
            yield _utf8(f"::{_GH_COMMAND[d.severity]} {','.join(props)}::{message}\n")

    def tail(self, totals: Totals) -> Iterator[str]:
        out, counts = [], self.counts
        for d in totals.notes:  # about the run: an annotation without a file
            title = _gh_escape(f"{d.code} {CODES[d.code].title}", prop=True)
            counts[_GH_COMMAND[d.severity]] += 1
            text = _gh_escape(shown(with_hint(d)))
            out.append(f"::{_GH_COMMAND[d.severity]} title={title}::{text}")
        closing = _not_shown(counts)
        if closing is not None:
            out.append(closing)
        out.append(summary(totals))
        yield _utf8("\n".join(out) + "\n")


def _utf8(text: str) -> str:
    clean, _count = escape_undecodable(text)
    return str(clean)
