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

import bisect
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from lsprotocol import types as lsp
from pygls.lsp.server import LanguageServer
from pygls.uris import to_fs_path
from pygls.workspace import PositionCodec

from motiontool import __version__
from motiontool.kinematics.robots import RobotSpec
from motiontool.motionfmt.diagnostics import Diagnostic, Severity
from motiontool.motionfmt.fixes import Fix, fix_bytes
from motiontool.motionfmt.reader import token_spans
from motiontool.motionfmt.validate import FileReport

__all__ = ["Linter", "MotionServer", "build_server"]

SOURCE = "motiontool"
"""The ``source`` of every published diagnostic (editors show it beside the message)."""

_SEVERITY = {
    Severity.ERROR: lsp.DiagnosticSeverity.Error,
    Severity.WARNING: lsp.DiagnosticSeverity.Warning,
    Severity.INFO: lsp.DiagnosticSeverity.Information,
}

Linter = Callable[[Path, bytes], tuple[FileReport, RobotSpec | None]]
"""Lints a document's bytes as the file at that path: its report and the robot it was checked
against (None: syntax level only)."""


@dataclass
class _Document:
    """The last lint of an open document: what hover and code actions answer from."""

    version: int | None
    report: FileReport
    robot: RobotSpec | None


class MotionServer(LanguageServer):
    """The language server; ``lint`` is :data:`Linter`."""

    def __init__(self, lint: Linter) -> None:
        super().__init__(SOURCE, __version__)
        self.lint = lint
        self.documents: dict[str, _Document] = {}

    def refresh(self, uri: str) -> None:
        """Lint document ``uri`` as the editor holds it and publish its findings."""
        doc = self.workspace.get_text_document(uri)
        data = doc.source.encode("utf-8", "surrogateescape")
        path = Path(to_fs_path(uri) or uri)
        report, robot = self.lint(path, data)
        self.documents[uri] = _Document(doc.version, report, robot)
        codec = self.workspace.position_codec
        diagnostics = [_diagnostic(report, codec, d) for d in report.diagnostics]
        self.text_document_publish_diagnostics(
            lsp.PublishDiagnosticsParams(uri=uri, diagnostics=diagnostics, version=doc.version)
        )


# --------------------------------------------------------------------------- positions


def _position(report: FileReport, codec: PositionCodec, line: int, column: int) -> lsp.Position:
    """LSP position of 1-based ``line`` and byte ``column``, in ``codec``'s code units (a
    column past the end of the line stays that many past it)."""
    raw = report.source_line(line)
    head = raw[: max(column - 1, 0)]
    units = int(codec.client_num_units(head.decode("utf-8", "surrogateescape")))
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
    fixes = report.fix_of(d)
    return lsp.Diagnostic(
        range=_range(report, codec, d.line, d.column, d.end_column or d.column + 1),
        message=d.message + (f"\nhint: {d.hint}" if d.hint else ""),
        severity=_SEVERITY[d.severity],
        code=d.code,
        source=SOURCE,
        data={"fixable": bool(fixes), "safe": all(f.safe for f in fixes)} if fixes else None,
    )


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
        uri = params.text_document.uri
        ls.documents.pop(uri, None)
        ls.text_document_publish_diagnostics(lsp.PublishDiagnosticsParams(uri=uri, diagnostics=[]))

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
