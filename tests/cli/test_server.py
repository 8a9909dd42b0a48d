"""``motiontool server`` (issue #17 item 5), driven by a real LSP client over stdio: pygls'
``LanguageClient`` starts ``motiontool server`` as a subprocess, as an editor does, then
initialize, didOpen, didChange, publishDiagnostics, hover, codeAction, shutdown.

The published findings must be exactly those of ``motiontool validate`` on the same file with the
same configuration (robot per glob, an ignored code)."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
from conftest import import_extra, pre_commit_env
from lsp_session import Session, motiontool, run_session
from typer.testing import CliRunner

from motiontool.cli.app import app

lsp = import_extra("lsprotocol.types", "lsp")
LanguageClient = import_extra("pygls.lsp.client", "lsp").LanguageClient
from_fs_path = import_extra("pygls.uris", "lsp").from_fs_path

MOTION = (
    "#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n"
    "00:00:000,Pose1,0,0\n"
    "00:00:040,Pose2,2rad,0.1\n"  # MT203 (safe fix)
    "00:01:000,Pose3,3.0,-0.1\n"  # MT302: HeadYaw past its limit (robot nao)
)
PYPROJECT = '[tool.motiontool]\nrobot = "none"\nextend-ignore = ["MT206"]\n[tool.motiontool.robots]\n"nao/**" = "nao"\n'


def open_doc(session: Session, path: Path, text: str, version: int = 1) -> str:
    uri = from_fs_path(str(path))
    assert uri is not None
    session.client.text_document_did_open(
        lsp.DidOpenTextDocumentParams(
            lsp.TextDocumentItem(uri=uri, language_id="webots-motion", version=version, text=text)
        )
    )
    return uri


def validate_json(path: Path, cwd: Path, monkeypatch: pytest.MonkeyPatch) -> list[dict[str, Any]]:
    monkeypatch.chdir(cwd)
    result = CliRunner().invoke(app, ["validate", str(path), "-f", "json"])
    return json.loads(result.stdout)["files"][0]["diagnostics"]  # type: ignore[no-any-return]


@pytest.fixture
def project(tmp_path: Path) -> Path:
    (tmp_path / "pyproject.toml").write_text(PYPROJECT)
    (tmp_path / "nao").mkdir()
    (tmp_path / "nao" / "look.motion").write_text(MOTION)
    (tmp_path / "other.motion").write_text(MOTION)
    return tmp_path


def test_the_editor_sees_what_validate_reports(
    project: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    got: dict[str, list[lsp.Diagnostic]] = {}

    async def body(session: Session) -> None:
        for name in ("nao/look.motion", "other.motion"):
            uri = open_doc(session, project / name, MOTION)
            got[name] = await session.diagnostics(uri)

    run_session(project, body)
    for name, diagnostics in got.items():
        want = validate_json(project / name, project, monkeypatch)
        assert [
            (d.code, d.range.start.line + 1, d.range.start.character + 1) for d in diagnostics
        ] == [(w["code"], w["line"], w["column"]) for w in want]
        assert all(d.source == "motiontool" for d in diagnostics)
        assert [d.message.split("\nhint: ")[0] for d in diagnostics] == [w["message"] for w in want]
    # The configuration applies: nao/ is checked against the Nao (MT302), other.motion is not.
    assert "MT302" in {d.code for d in got["nao/look.motion"]}
    assert "MT302" not in {d.code for d in got["other.motion"]}
    assert "MT206" not in {d.code for d in got["nao/look.motion"]}


def test_changes_are_linted_as_typed_and_fixes_are_code_actions(project: Path) -> None:
    async def body(session: Session) -> None:
        path = project / "other.motion"
        uri = open_doc(session, path, MOTION)
        first = await session.diagnostics(uri)
        assert "MT203" in {d.code for d in first}
        # The user types a NUL-free fix by hand on line 3, then adds a blank line (MT201).
        fixed = MOTION.replace("2rad", "2") + "\n00:01:500,Pose4,0,0\n"
        session.client.text_document_did_change(
            lsp.DidChangeTextDocumentParams(
                text_document=lsp.VersionedTextDocumentIdentifier(uri=uri, version=2),
                content_changes=[lsp.TextDocumentContentChangeWholeDocument(text=fixed)],
            )
        )
        second = await session.diagnostics(uri)
        assert "MT203" not in {d.code for d in second} and "MT201" in {d.code for d in second}
        # Back to the original text: the MT203 fix is a code action with the exact edit.
        session.client.text_document_did_change(
            lsp.DidChangeTextDocumentParams(
                text_document=lsp.VersionedTextDocumentIdentifier(uri=uri, version=3),
                content_changes=[lsp.TextDocumentContentChangeWholeDocument(text=MOTION)],
            )
        )
        third = await session.diagnostics(uri)
        mt203 = next(d for d in third if d.code == "MT203")
        actions = await session.client.text_document_code_action_async(
            lsp.CodeActionParams(
                text_document=lsp.TextDocumentIdentifier(uri=uri),
                range=mt203.range,
                context=lsp.CodeActionContext(diagnostics=[mt203]),
            )
        )
        assert actions is not None
        quick = [
            a for a in actions if isinstance(a, lsp.CodeAction) and a.title.startswith("MT203")
        ]
        assert len(quick) == 1 and quick[0].is_preferred
        assert quick[0].edit is not None and quick[0].edit.changes is not None
        (edit,) = quick[0].edit.changes[uri]
        assert (edit.range.start.line, edit.range.start.character) == (2, 17)
        assert (edit.range.end.character, edit.new_text) == (20, "")
        fix_all = [
            a
            for a in actions
            if isinstance(a, lsp.CodeAction) and a.kind == lsp.CodeActionKind.SourceFixAll
        ]
        assert len(fix_all) == 1 and fix_all[0].edit is not None and fix_all[0].edit.changes
        (whole,) = fix_all[0].edit.changes[uri]
        assert whole.new_text == MOTION.replace("2rad", "2")

    run_session(project, body)


def test_fix_all_leaves_the_codes_the_configuration_leaves_out(project: Path) -> None:
    """ "fix all" makes the edit ``validate --fix`` makes, which fixes only the
    codes reported (here MT204 is ignored for the file, MT203 is not)."""
    (project / "nao" / "motiontool.toml").write_text('robot = "none"\nignore = ["MT204"]\n')
    text = MOTION.replace("00:00:000,Pose1,0,0", "00:00:000,Pose1,0,-9999999.9")

    async def body(session: Session) -> None:
        uri = open_doc(session, project / "nao" / "look.motion", text)
        shown = await session.diagnostics(uri)
        assert "MT203" in {d.code for d in shown} and "MT204" not in {d.code for d in shown}
        everything = lsp.Range(start=lsp.Position(0, 0), end=lsp.Position(4, 0))
        actions = await session.client.text_document_code_action_async(
            lsp.CodeActionParams(
                text_document=lsp.TextDocumentIdentifier(uri=uri),
                range=everything,
                context=lsp.CodeActionContext(diagnostics=[]),
            )
        )
        fix_all = [
            a
            for a in actions or []
            if isinstance(a, lsp.CodeAction) and a.kind == lsp.CodeActionKind.SourceFixAll
        ]
        assert len(fix_all) == 1 and fix_all[0].edit is not None and fix_all[0].edit.changes
        (whole,) = fix_all[0].edit.changes[uri]
        assert whole.new_text == text.replace("2rad", "2")  # the ignored MT204 cell stays

    run_session(project, body)


def test_hover_names_the_joint_time_value_and_limits(project: Path) -> None:
    async def body(session: Session) -> None:
        uri = open_doc(session, project / "nao" / "look.motion", MOTION)
        await session.diagnostics(uri)
        hover = await session.client.text_document_hover_async(
            lsp.HoverParams(
                text_document=lsp.TextDocumentIdentifier(uri=uri),
                position=lsp.Position(line=3, character=17),  # the 3.0 of Pose3
            )
        )
        assert hover is not None and isinstance(hover.contents, lsp.MarkupContent)
        text = hover.contents.value
        assert "**HeadYaw** = 3.0" in text and "Pose3" in text and "1000 ms" in text
        assert "nao: -2.08" in text and "rad" in text
        header = await session.client.text_document_hover_async(
            lsp.HoverParams(
                text_document=lsp.TextDocumentIdentifier(uri=uri),
                position=lsp.Position(line=0, character=30),  # HeadPitch in the header
            )
        )
        assert header is not None and isinstance(header.contents, lsp.MarkupContent)
        assert header.contents.value.startswith("**HeadPitch**: nao:")

    run_session(project, body)


def test_a_bad_config_is_one_error_line(tmp_path: Path) -> None:
    result = CliRunner().invoke(app, ["server", "--config", str(tmp_path / "missing.toml")])
    assert result.exit_code == 2
    assert result.stderr.startswith("motiontool: error: cannot read")


HOOK = """repos:
- repo: local
  hooks:
  - id: motiontool-validate
    name: motiontool validate
    entry: motiontool validate
    language: system
    files: \\.motion$
    require_serial: true
"""

FINDING = re.compile(r"^(\S+\.motion):(\d+):(\d+): \w+ (MT\d{3}):", re.MULTILINE)


def test_validate_the_pre_commit_hook_and_the_editor_agree(project: Path) -> None:
    """Issue #17's acceptance: a repository whose pyproject.toml sets the robot per folder and
    ignores a code gets the same findings from validate, the pre-commit hook and the server."""
    env = pre_commit_env(project / ".cache")
    (project / ".pre-commit-config.yaml").write_text(HOOK)
    subprocess.run(["git", "init", "-q"], cwd=project, env=env, check=True)
    subprocess.run(["git", "add", "."], cwd=project, env=env, check=True)
    names = ["nao/look.motion", "other.motion"]
    cli = subprocess.run(
        [motiontool(), "validate", *names], cwd=project, capture_output=True, text=True
    )
    hook = subprocess.run(
        [sys.executable, "-m", "pre_commit", "run", "--all-files", "--color", "never"],
        cwd=project,
        env=env,
        capture_output=True,
        text=True,
    )
    from_cli = set(FINDING.findall(cli.stdout))
    assert from_cli and hook.returncode == cli.returncode == 1, hook.stdout
    assert set(FINDING.findall(hook.stdout)) == from_cli
    editor: set[tuple[str, str, str, str]] = set()

    async def body(session: Session) -> None:
        for name in names:
            uri = open_doc(session, project / name, MOTION)
            for d in await session.diagnostics(uri):
                place = (name, str(d.range.start.line + 1), str(d.range.start.character + 1))
                editor.add((*place, str(d.code)))

    run_session(project, body)
    assert editor == from_cli


def test_the_editor_stores_saved_text_in_the_findings_cache_not_typed_text(
    project: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("MOTIONTOOL_NO_CACHE", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(project / "xdg"))
    store = project / "xdg" / "motiontool" / "lint"
    counts: list[int] = []

    async def body(session: Session) -> None:
        path = project / "nao" / "look.motion"
        uri = open_doc(session, path, MOTION)  # the text as saved
        await session.diagnostics(uri)
        counts.append(len(list(store.glob("??/*.json"))))
        for version in (2, 3):  # typed, not saved
            session.client.text_document_did_change(
                lsp.DidChangeTextDocumentParams(
                    text_document=lsp.VersionedTextDocumentIdentifier(uri=uri, version=version),
                    content_changes=[
                        lsp.TextDocumentContentChangeWholeDocument(
                            text=MOTION.replace("3.0", f"3.{version}")
                        )
                    ],
                )
            )
            await session.diagnostics(uri)
        counts.append(len(list(store.glob("??/*.json"))))

    run_session(project, body)
    assert counts == [1, 1]
    # The hook (validate) checks the saved file next: its findings come from the editor's entry.
    fresh = CliRunner().invoke(app, ["validate", "--no-cache", str(project / "nao/look.motion")])
    monkeypatch.chdir(project)
    fresh = CliRunner().invoke(app, ["validate", "--no-cache", "nao/look.motion"])
    again = CliRunner().invoke(app, ["validate", "nao/look.motion"])
    assert (again.exit_code, again.stdout) == (fresh.exit_code, fresh.stdout)
    assert len(list(store.glob("??/*.json"))) == 1 and " MT302: " in again.stdout


# A pose name of 1-, 2- and 4-byte UTF-8 characters: "Pösé😀" is 10 UTF-8 code units, 6 UTF-16
# code units and 5 code points, so each encoding gives different columns after it.
WIDE = MOTION.replace("Pose2", "Pösé😀")
_CODECS = {"utf-8": ("utf-8", 1), "utf-16": ("utf-16-le", 2), "utf-32": ("utf-32-le", 4)}


def _units(text: str, encoding: str) -> int:
    codec, width = _CODECS[encoding]
    return len(text.encode(codec)) // width


def _index(line: str, character: int, encoding: str) -> int:
    """The string index of LSP ``character`` in ``line``, counted in ``encoding``'s units."""
    for i in range(len(line) + 1):
        if _units(line[:i], encoding) == character:
            return i
    raise AssertionError(f"{character} is inside a character of {line!r} in {encoding}")


def _position(text: str, index: int, encoding: str) -> lsp.Position:
    before = text[:index].split("\n")
    return lsp.Position(line=len(before) - 1, character=_units(before[-1], encoding))


def _offset(text: str, at: lsp.Position, encoding: str) -> int:
    lines = text.split("\n")
    return sum(len(x) + 1 for x in lines[: at.line]) + _index(
        lines[at.line], at.character, encoding
    )


@pytest.mark.parametrize(
    "offered",
    [["utf-8", "utf-16"], ["utf-16"], ["utf-32", "utf-16"]],
    ids=["utf-8 (Neovim's order)", "utf-16", "utf-32"],
)
def test_positions_use_the_encoding_the_client_and_server_agreed(
    project: Path, offered: list[str]
) -> None:
    """Issue #36 item 14: the server answers the client's first encoding, and every position it
    sends (finding ranges, quick-fix edits) or receives (hover, an incremental change) counts
    in that encoding's code units on a line with a non-ASCII pose name."""
    encoding = offered[0]
    rad = WIDE.index("2rad") + 1
    capabilities = lsp.ClientCapabilities(
        general=lsp.GeneralClientCapabilities(position_encodings=offered)
    )

    async def body(session: Session) -> None:
        assert session.result is not None
        assert session.result.capabilities.position_encoding == encoding
        uri = open_doc(session, project / "other.motion", WIDE)
        mt203 = next(d for d in await session.diagnostics(uri) if d.code == "MT203")
        assert _offset(WIDE, mt203.range.start, encoding) == rad
        assert _offset(WIDE, mt203.range.end, encoding) == rad + len("rad")
        actions = await session.client.text_document_code_action_async(
            lsp.CodeActionParams(
                text_document=lsp.TextDocumentIdentifier(uri=uri),
                range=mt203.range,
                context=lsp.CodeActionContext(diagnostics=[mt203]),
            )
        )
        assert actions is not None
        (quick,) = [a for a in actions if isinstance(a, lsp.CodeAction) and a.title[:5] == "MT203"]
        assert quick.edit is not None and quick.edit.changes is not None
        (edit,) = quick.edit.changes[uri]
        start = _offset(WIDE, edit.range.start, encoding)
        end = _offset(WIDE, edit.range.end, encoding)
        assert WIDE[:start] + edit.new_text + WIDE[end:] == WIDE.replace("2rad", "2")
        # Hover on the 0.1 after the wide pose name: the client counts in its encoding.
        at = _position(WIDE, WIDE.index("0.1"), encoding)
        hover = await session.client.text_document_hover_async(
            lsp.HoverParams(text_document=lsp.TextDocumentIdentifier(uri=uri), position=at)
        )
        assert hover_text(hover).startswith("**HeadPitch** = 0.1, pose **Pösé😀**")
        # An incremental change that deletes 'rad', its range in the client's encoding.
        session.client.text_document_did_change(
            lsp.DidChangeTextDocumentParams(
                text_document=lsp.VersionedTextDocumentIdentifier(uri=uri, version=2),
                content_changes=[
                    lsp.TextDocumentContentChangePartial(
                        range=lsp.Range(
                            start=_position(WIDE, rad, encoding),
                            end=_position(WIDE, rad + 3, encoding),
                        ),
                        text="",
                    )
                ],
            )
        )
        after = await session.diagnostics(uri)
        assert "MT203" not in {d.code for d in after}
        assert hover_text(
            await session.client.text_document_hover_async(
                lsp.HoverParams(
                    text_document=lsp.TextDocumentIdentifier(uri=uri),
                    position=_position(WIDE.replace("2rad", "2"), WIDE.index("2rad"), encoding),
                )
            )
        ).startswith("**HeadYaw** = 2.0, pose **Pösé😀**")

    run_session(project, body, capabilities=capabilities)


def hover_text(hover: lsp.Hover | None) -> str:
    assert hover is not None and isinstance(hover.contents, lsp.MarkupContent)
    return hover.contents.value
