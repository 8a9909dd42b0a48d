"""``motiontool server``: a Language Server (pygls) showing ``validate``'s findings in the editor.

Imported only by :func:`motiontool.cli.server.server_command` (pygls is the ``lsp`` extra, and no
other command pays for importing it). What it does:

- on open, change and save of a ``.motion`` document it lints the editor's text exactly as
  ``motiontool validate FILE`` lints the file (:func:`motiontool.cli.lint_run.lint_document`: the
  same configuration, robot, checks and grouping) and publishes the findings;
- code actions: each finding's fix (:mod:`motiontool.motionfmt.fixes`; the unsafe ones say so),
  and "fix all safe findings" (``source.fixAll``), as ``validate --fix`` would edit the file;
- hover on a cell: the joint, the pose and its time (ms), the value and the robot's limits.

Positions: LSP counts lines from 0 and characters in the code units of the encoding the client
and server agreed at ``initialize`` (pygls takes the first of the client's
``general.positionEncodings`` it knows: utf-8, utf-16 or utf-32; utf-16 when none is offered);
findings count lines from 1 and columns in bytes. pygls' :class:`~pygls.workspace.PositionCodec`
for that encoding (``workspace.position_codec``) converts both ways, for every position the
server sends (finding ranges, edits) or receives (hover, code action ranges, incremental edits).
"""

from __future__ import annotations

import asyncio
import bisect
import functools
import logging
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import unquote

from lsprotocol import types as lsp
from pygls.lsp.server import LanguageServer
from pygls.uris import from_fs_path, to_fs_path
from pygls.workspace import PositionCodec

from motiontool import __version__
from motiontool.cli.config import ConfigError
from motiontool.errors import MotionToolError
from motiontool.kinematics.robots import RobotSpec
from motiontool.motionfmt.diagnostics import Diagnostic, Severity
from motiontool.motionfmt.fixes import Fix, fix_bytes
from motiontool.motionfmt.reader import token_spans
from motiontool.motionfmt.validate import FileReport

__all__ = ["DEBOUNCE_S", "Linter", "MotionServer", "Superseded", "build_server", "rules_href"]

logger = logging.getLogger(__name__)

SOURCE = "motiontool"
"""The ``source`` of every published diagnostic (editors show it beside the message)."""

_SEVERITY = {
    Severity.ERROR: lsp.DiagnosticSeverity.Error,
    Severity.WARNING: lsp.DiagnosticSeverity.Warning,
    Severity.INFO: lsp.DiagnosticSeverity.Information,
}

DEBOUNCE_S = 0.05
"""Seconds a document rests after a change that came while it was linted, before it is linted
again: a burst of keystrokes is linted as its last version. A change after a quiet spell is
linted at once."""

Linter = Callable[[Path, bytes, Callable[[], bool]], tuple[FileReport, RobotSpec | None]]
"""Lints a document's bytes as the file at that path: its report and the robot it was checked
against (None: syntax level only). The third argument tells whether a newer version has
superseded these bytes: the linter may then stop, raising :class:`Superseded`."""


class Superseded(Exception):
    """A lint stopped early: a newer version of the document supersedes the one it lints."""


@dataclass
class _Document:
    """The last lint of an open document: what hover and code actions answer from."""

    version: int | None
    report: FileReport
    robot: RobotSpec | None


class MotionServer(LanguageServer):
    """The language server; ``lint`` is :data:`Linter`.

    Only the newest version of a document is linted: a change after a quiet spell is linted at
    once (in a worker thread, so requests are answered meanwhile); changes that come while it
    runs supersede it (it stops at its next check, and is dropped, not published), and the
    newest of them is linted once they have rested ``debounce_s`` seconds. Requests waiting on
    a lint (pull diagnostics) are asyncio tasks that ``$/cancelRequest`` cancels."""

    def __init__(self, lint: Linter, debounce_s: float = DEBOUNCE_S) -> None:
        super().__init__(SOURCE, __version__)
        self.lint = lint
        self.debounce_s = debounce_s
        self.documents: dict[str, _Document] = {}
        self.published: dict[str, tuple[int | None, list[lsp.Diagnostic]]] = {}
        self._changed: dict[str, float] = {}  # document URI: loop time of its last change
        self._linting: dict[str, asyncio.Task[None]] = {}
        self._waiting: dict[str, list[asyncio.Future[None]]] = {}
        self._config_of: dict[str, str] = {}  # document URI: its configuration's, in error
        self._pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="motiontool-lint")

    def refresh(self, uri: str) -> None:
        """Lint document ``uri`` as the editor holds it, once it rests, and publish its
        findings (unless a newer change supersedes the version linted)."""
        loop = asyncio.get_running_loop()
        self._changed[uri] = loop.time()
        if uri not in self._linting:
            self._linting[uri] = loop.create_task(self._lint_while_changed(uri))

    def forget(self, uri: str) -> None:
        """Document ``uri`` was closed: no lint of it is published any more."""
        self._changed.pop(uri, None)
        self.documents.pop(uri, None)
        self.published.pop(uri, None)
        self._publish(uri, None, [])
        self._config_fine(uri)

    async def current(self, uri: str) -> tuple[int | None, list[lsp.Diagnostic]]:
        """The findings of the version of ``uri`` the editor holds now (after its lint)."""
        while self._open_version(uri) is not None and (
            uri in self._changed or self.published.get(uri, (None,))[0] != self._open_version(uri)
        ):
            if uri not in self._linting:
                self.refresh(uri)
            waiter = asyncio.get_running_loop().create_future()
            self._waiting.setdefault(uri, []).append(waiter)
            await waiter
        return self.published.get(uri, (None, []))

    def _open_version(self, uri: str) -> int | None:
        doc = self.workspace.text_documents.get(unquote(uri))
        return None if doc is None else doc.version

    async def _lint_while_changed(self, uri: str) -> None:
        """Lint ``uri`` at once (a change after a quiet spell: the edit is seen without a
        wait), then, while changes keep coming during its lints, once they rest."""
        loop = asyncio.get_running_loop()
        first = True
        try:
            while uri in self._changed:
                rest = self._changed[uri] + self.debounce_s - loop.time()
                if rest > 0 and not first:
                    await asyncio.sleep(rest)
                    continue
                del self._changed[uri]
                first = False
                await self._lint_once(uri)
        finally:
            del self._linting[uri]
            for waiter in self._waiting.pop(uri, []):
                if not waiter.done():
                    waiter.set_result(None)

    async def _lint_once(self, uri: str) -> None:
        version = self._open_version(uri)
        if version is None:
            return  # closed
        doc = self.workspace.get_text_document(uri)
        data = doc.source.encode("utf-8", "surrogateescape")
        path = Path(to_fs_path(uri) or uri)
        loop = asyncio.get_running_loop()
        codec = self.workspace.position_codec

        def lint() -> tuple[_Document, list[lsp.Diagnostic]]:  # in the worker thread
            report, robot = self.lint(path, data, lambda: self._superseded(uri, version))
            found = [_diagnostic(report, codec, d) for d in report.diagnostics]
            return _Document(version, report, robot), found

        try:
            linted, found = await loop.run_in_executor(self._pool, lint)
        except Superseded:
            return  # the newer version's lint follows
        except Exception as exc:  # a configuration that cannot be used, or a bug: not a popup
            if not isinstance(exc, MotionToolError):
                logger.exception("linting %s failed", uri)
            if uri not in self._changed and self._open_version(uri) == version:
                self._publish_error(uri, version, exc)
            return
        if self._superseded(uri, version):
            return  # stale: a newer change supersedes it, and its lint follows
        self.documents[uri] = linted
        self._config_fine(uri)
        self._publish(uri, version, found)

    def _superseded(self, uri: str, version: int | None) -> bool:
        """Whether a change came after version ``version`` of ``uri`` was taken to lint (asked
        from the worker thread too: one lookup of each dictionary)."""
        return uri in self._changed or self._open_version(uri) != version

    def _publish(self, uri: str, version: int | None, diagnostics: list[lsp.Diagnostic]) -> None:
        if self._open_version(uri) is not None or uri in self._config_of.values():
            self.published[uri] = (version, diagnostics)
        self.text_document_publish_diagnostics(
            lsp.PublishDiagnosticsParams(uri=uri, diagnostics=diagnostics, version=version)
        )

    def _publish_error(self, uri: str, version: int | None, exc: Exception) -> None:
        """A configuration that cannot be used: the error on the configuration file (where it
        is), and on the document one finding at its start that says it was not linted."""
        where = lsp.Range(start=lsp.Position(0, 0), end=lsp.Position(0, 0))
        related = None
        config_uri = None
        if isinstance(exc, ConfigError) and exc.path is not None:
            config_uri = from_fs_path(str(exc.path)) or str(exc.path)
        if self._config_of.get(uri) != config_uri:
            self._config_fine(uri)
        if isinstance(exc, ConfigError) and config_uri is not None:
            at = lsp.Position(line=max(exc.line - 1, 0), character=max(exc.column - 1, 0))
            spot = lsp.Range(start=at, end=lsp.Position(line=at.line + 1, character=0))
            self._config_of[uri] = config_uri
            self._publish(config_uri, None, [_error(spot, str(exc), "config")])
            related = [lsp.DiagnosticRelatedInformation(lsp.Location(config_uri, spot), str(exc))]
        known = isinstance(exc, MotionToolError)
        message = f"not linted: {exc}" if known else f"not linted: {type(exc).__name__}: {exc}"
        finding = _error(where, message, "config" if isinstance(exc, ConfigError) else None)
        finding.related_information = related
        self._publish(uri, version, [finding])

    def _config_fine(self, uri: str) -> None:
        """Document ``uri`` no longer reports its configuration in error: that file's error is
        cleared once no open document reports it."""
        config_uri = self._config_of.pop(uri, None)
        if config_uri is not None and config_uri not in self._config_of.values():
            self.published.pop(config_uri, None)
            self._publish(config_uri, None, [])


def _error(where: lsp.Range, message: str, code: str | None) -> lsp.Diagnostic:
    return lsp.Diagnostic(
        range=where,
        message=message,
        severity=lsp.DiagnosticSeverity.Error,
        code=code,
        source=SOURCE,
    )


# --------------------------------------------------------------------------- positions


def _position(report: FileReport, codec: PositionCodec, line: int, column: int) -> lsp.Position:
    """LSP position of 1-based ``line`` and byte ``column``, in ``codec``'s code units (a
    column past the end of the line stays that many past it)."""
    raw = report.source_line(line)
    head = raw[: max(column - 1, 0)]
    # ASCII is a code unit a byte in every encoding (most lines: no per-character count).
    units = (
        len(head)
        if head.isascii()
        else codec.client_num_units(head.decode("utf-8", "surrogateescape"))
    )
    return lsp.Position(line=line - 1, character=units + max(column - 1 - len(raw), 0))


def _range(
    report: FileReport, codec: PositionCodec, line: int, column: int, end_column: int | None
) -> lsp.Range:
    """From byte ``column`` to ``end_column`` (exclusive; None: the end of the line)."""
    end = len(report.source_line(line)) + 1 if end_column is None else end_column
    return lsp.Range(
        start=_position(report, codec, line, column), end=_position(report, codec, line, end)
    )


def _byte_column(codec: PositionCodec, raw: bytes, character: int) -> int:
    """The 1-based byte column of LSP offset ``character`` (0-based, in ``codec``'s code
    units) in line ``raw``; an offset inside a character means that character."""
    text = raw.decode("utf-8", "surrogateescape")
    at = codec.position_from_client_units([text], lsp.Position(line=0, character=character))
    return len(text[: at.character].encode("utf-8", "surrogateescape")) + 1


# --------------------------------------------------------------------------- diagnostics


def _diagnostic(report: FileReport, codec: PositionCodec, d: Diagnostic) -> lsp.Diagnostic:
    """``d`` as LSP shows it; ``data`` says whether it has a fix and whether that is safe, as
    the text report marks it (:meth:`~FileReport.fix_summary`: the robot's fixes are planned
    only when a code action asks for them, not for every version typed)."""
    summary = report.fix_summary(d)
    return lsp.Diagnostic(
        range=_range(report, codec, d.line, d.column, d.end_column or d.column + 1),
        message=d.message + (f"\nhint: {d.hint}" if d.hint else ""),
        severity=_SEVERITY[d.severity],
        code=d.code,
        code_description=_code_description(d.code),
        source=SOURCE,
        data=None if summary is None else {"fixable": True, "safe": summary[0]},
    )


@functools.cache
def rules_href() -> str | None:
    """Where each code's documentation is (a code's is its section, ``#mt106``): the
    ``Rules`` project URL, as SARIF's ``helpUri``; without one (the package names no URL yet),
    docs/rules.md beside the package as a ``file:`` URL where it is there (a source checkout or
    an editable install: a wheel holds no docs/); else None, and no link."""
    from motiontool.cli.reports.sarif import RULES_LABEL, project_urls

    url = project_urls().get(RULES_LABEL)
    if url is not None:
        return url
    rules = Path(__file__).resolve().parent.parent / "docs" / "rules.md"
    return rules.as_uri() if rules.is_file() else None


def _code_description(code: str) -> lsp.CodeDescription | None:
    base = rules_href()
    return None if base is None else lsp.CodeDescription(href=f"{base}#{code.lower()}")


def _edits(report: FileReport, codec: PositionCodec, fixes: Sequence[Fix]) -> list[lsp.TextEdit]:
    """A fix's byte edits as text edits (a deleted line goes with its end of line)."""
    out = []
    for f in fixes:
        if f.replacement is None:
            span = lsp.Range(
                start=lsp.Position(line=f.line - 1, character=0),
                end=lsp.Position(line=f.line, character=0),
            )
            out.append(lsp.TextEdit(range=span, new_text=""))
            continue
        text = f.replacement.decode("utf-8", "surrogateescape")
        out.append(
            lsp.TextEdit(range=_range(report, codec, f.line, f.column, f.end_column), new_text=text)
        )
    return out


def _code_actions(
    uri: str, doc: _Document, codec: PositionCodec, wanted: lsp.Range
) -> list[lsp.CodeAction]:
    """The fixes of the findings in ``wanted``, then "fix all" where a safe fix exists."""
    report = doc.report
    actions = []
    for d in report.diagnostics:
        fixes = report.fix_of(d)
        if not fixes or not wanted.start.line <= d.line - 1 <= wanted.end.line:
            continue
        safe = all(f.safe for f in fixes)
        title = f"{d.code}: {fixes[0].title}" + ("" if safe else " (unsafe: changes the motion)")
        actions.append(
            lsp.CodeAction(
                title=title,
                kind=lsp.CodeActionKind.QuickFix,
                diagnostics=[_diagnostic(report, codec, d)],
                is_preferred=safe,
                edit=lsp.WorkspaceEdit(changes={uri: _edits(report, codec, fixes)}),
            )
        )
    shown = {d.code for d in report.diagnostics}  # as validate --fix: the codes reported only
    fixed = fix_bytes(report.data, report.path, unsafe=False, select=shown.__contains__)
    if fixed.data != report.data:
        whole = _range(report, codec, 1, 1, None)
        last = len(report.data.split(b"\n"))
        whole.end = lsp.Position(line=last, character=0)
        text = fixed.data.decode("utf-8", "surrogateescape")
        actions.append(
            lsp.CodeAction(
                title=f"motiontool: fix all safe findings ({len(fixed.applied)})",
                kind=lsp.CodeActionKind.SourceFixAll,
                edit=lsp.WorkspaceEdit(changes={uri: [lsp.TextEdit(range=whole, new_text=text)]}),
            )
        )
    return actions


# --------------------------------------------------------------------------- hover


def _hover(doc: _Document, codec: PositionCodec, at: lsp.Position) -> lsp.Hover | None:
    """What the cell under the cursor is: joint, pose, time (ms), value, the robot's limits."""
    result = doc.report.read
    line = at.line + 1
    column = _byte_column(codec, doc.report.source_line(line), at.character)
    if line == 1 and result.joints:
        return _joint_hover(doc, _header_cell(doc, column))
    p = bisect.bisect_left(result.pose_lines, line)
    if p >= len(result.pose_lines) or result.pose_lines[p] != line:
        return None
    for j in [None, *range(len(result.joints))]:
        _line, start, end = result.cell_span(p, j)
        if start <= column <= end:
            return _cell_hover(doc, p, j)
    return None


def _header_cell(doc: _Document, column: int) -> int | None:
    """The joint whose header token holds byte ``column`` of line 1 (tokens as the reader cuts
    them: :func:`~motiontool.motionfmt.reader.token_spans`; the first two are not joints)."""
    spans = token_spans(doc.report.source_line(1))
    for k, (start, end) in enumerate(spans[2 : 2 + len(doc.report.read.joints)]):
        if start < column <= end + 1:
            return k
    return None


def _limits(doc: _Document, joint: str) -> str:
    robot = doc.robot
    if robot is None or joint not in robot:
        return (
            "no robot limits (checked at syntax level)"
            if robot is None
            else (f"not a motor of {robot.name}")
        )
    j = robot.joint(joint)
    return (
        f"{robot.name}: {j.lower:g} to {j.upper:g} {j.unit}, at most {j.max_velocity:g} {j.unit}/s"
    )


def _joint_hover(doc: _Document, joint: int | None) -> lsp.Hover | None:
    if joint is None:
        return None
    name = doc.report.read.joints[joint]
    return lsp.Hover(
        contents=lsp.MarkupContent(lsp.MarkupKind.Markdown, f"**{name}**: {_limits(doc, name)}")
    )


def _cell_hover(doc: _Document, pose: int, joint: int | None) -> lsp.Hover:
    result = doc.report.read
    head = f"pose **{result.pose_names[pose]}** at {result.times_ms[pose]} ms"
    if joint is None:
        return lsp.Hover(contents=lsp.MarkupContent(lsp.MarkupKind.Markdown, head))
    name = result.joints[joint]
    value = result.row(pose)[joint]
    shown = "`*` (no command: the joint holds its target)" if value != value else f"{value!r}"
    text = f"**{name}** = {shown}, {head}\n\n{_limits(doc, name)}"
    return lsp.Hover(contents=lsp.MarkupContent(lsp.MarkupKind.Markdown, text))


# --------------------------------------------------------------------------- the server


def build_server(lint: Linter) -> MotionServer:
    """The server with its features registered; ``server.start_io()`` runs it on stdio."""
    server = MotionServer(lint)

    @server.feature(lsp.TEXT_DOCUMENT_DID_OPEN)
    def did_open(ls: MotionServer, params: lsp.DidOpenTextDocumentParams) -> None:
        ls.refresh(params.text_document.uri)

    @server.feature(lsp.TEXT_DOCUMENT_DID_CHANGE)
    def did_change(ls: MotionServer, params: lsp.DidChangeTextDocumentParams) -> None:
        ls.refresh(params.text_document.uri)

    @server.feature(lsp.TEXT_DOCUMENT_DID_SAVE)
    def did_save(ls: MotionServer, params: lsp.DidSaveTextDocumentParams) -> None:
        ls.refresh(params.text_document.uri)

    @server.feature(lsp.TEXT_DOCUMENT_DID_CLOSE)
    def did_close(ls: MotionServer, params: lsp.DidCloseTextDocumentParams) -> None:
        ls.forget(params.text_document.uri)

    @server.feature(
        lsp.TEXT_DOCUMENT_DIAGNOSTIC,
        lsp.DiagnosticOptions(inter_file_dependencies=False, workspace_diagnostics=False),
    )
    async def diagnostic(
        ls: MotionServer, params: lsp.DocumentDiagnosticParams
    ) -> lsp.DocumentDiagnosticReport:
        """Pull diagnostics: the findings of the version the editor holds, once linted; the
        version is the result id (unchanged: no findings sent again)."""
        version, diagnostics = await ls.current(params.text_document.uri)
        result_id = None if version is None else str(version)
        if result_id is not None and params.previous_result_id == result_id:
            return lsp.RelatedUnchangedDocumentDiagnosticReport(result_id=result_id)
        return lsp.RelatedFullDocumentDiagnosticReport(items=diagnostics, result_id=result_id)

    @server.feature(
        lsp.TEXT_DOCUMENT_CODE_ACTION,
        lsp.CodeActionOptions(
            code_action_kinds=[lsp.CodeActionKind.QuickFix, lsp.CodeActionKind.SourceFixAll]
        ),
    )
    def code_action(ls: MotionServer, params: lsp.CodeActionParams) -> list[lsp.CodeAction]:
        doc = ls.documents.get(params.text_document.uri)
        if doc is None:
            return []
        return _code_actions(
            params.text_document.uri, doc, ls.workspace.position_codec, params.range
        )

    @server.feature(lsp.TEXT_DOCUMENT_HOVER)
    def hover(ls: MotionServer, params: lsp.HoverParams) -> lsp.Hover | None:
        doc = ls.documents.get(params.text_document.uri)
        return None if doc is None else _hover(doc, ls.workspace.position_codec, params.position)

    return server
