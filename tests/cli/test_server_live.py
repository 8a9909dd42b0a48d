"""``motiontool server`` while the user types, driven by a real LSP client over stdio (pygls'
``LanguageClient`` starts ``motiontool server`` as an editor does): only the newest version of a
document is linted and published, ``$/cancelRequest`` cancels a pull that waits on a lint, pull
diagnostics (``textDocument/diagnostic``) answer what push publishes, each finding links its
rule's documentation, and a configuration that cannot be used is a finding on that file."""

from __future__ import annotations

import asyncio
import json
import math
from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import Any

import pytest
from conftest import import_extra
from lsp_session import Session as ServerSession
from lsp_session import run_session as run_server_session
from typer.testing import CliRunner

from motiontool.cli.app import app

lsp = import_extra("lsprotocol.types", "lsp")
LanguageClient = import_extra("pygls.lsp.client", "lsp").LanguageClient
from_fs_path = import_extra("pygls.uris", "lsp").from_fs_path
JsonRpcRequestCancelled = import_extra("pygls.exceptions", "lsp").JsonRpcRequestCancelled

ROOT = Path(__file__).resolve().parents[2]
JOINTS = [
    "HeadYaw", "HeadPitch", "LShoulderPitch", "LShoulderRoll", "LElbowYaw", "LElbowRoll",
    "LWristYaw", "LHipYawPitch", "LHipRoll", "LHipPitch", "LKneePitch", "LAnklePitch",
    "LAnkleRoll", "RHipYawPitch", "RHipRoll", "RHipPitch", "RKneePitch", "RAnklePitch",
    "RAnkleRoll", "RShoulderPitch", "RShoulderRoll", "RElbowYaw", "RElbowRoll", "RWristYaw",
]  # fmt: skip


def big_motion(poses: int, nudge: int = 0, phase: float = 0.0) -> str:
    """A Nao motion of ``poses`` lines, every joint moving (findings: too fast, out of range,
    collisions); ``nudge`` changes one value (a one-line edit), ``phase`` every line."""
    lines = ["#WEBOTS_MOTION,V1.0," + ",".join(JOINTS)]
    for p in range(poses):
        cells = [f"{1.5 * math.sin(0.7 * p + k + phase):.3f}" for k in range(len(JOINTS))]
        if p == 7:
            cells[0] = f"{0.001 * nudge:.3f}"
        ms = 40 * p
        lines.append(
            f"{ms // 60000:02d}:{ms // 1000 % 60:02d}:{ms % 1000:03d},P{p},{','.join(cells)}"
        )
    return "\n".join(lines) + "\n"


class Session(ServerSession):
    """test_server's session, with the edits these tests make."""

    async def next(self, uri: str) -> Any:
        return await asyncio.wait_for(self.queue(uri).get(), timeout=60)

    def open(self, path: Path, text: str) -> str:
        uri: str = from_fs_path(str(path))
        item = lsp.TextDocumentItem(uri=uri, language_id="webots-motion", version=1, text=text)
        self.client.text_document_did_open(lsp.DidOpenTextDocumentParams(item))
        return uri

    def change(self, uri: str, version: int, text: str) -> None:
        self.client.text_document_did_change(
            lsp.DidChangeTextDocumentParams(
                text_document=lsp.VersionedTextDocumentIdentifier(uri=uri, version=version),
                content_changes=[lsp.TextDocumentContentChangeWholeDocument(text=text)],
            )
        )


def run_session(root: Path, body: Callable[[Session], Awaitable[None]]) -> Session:
    """test_server's runner, with this module's session."""
    session = run_server_session(root, body, session_type=Session)
    assert isinstance(session, Session)
    return session


def validate_json(path: Path, cwd: Path, monkeypatch: pytest.MonkeyPatch) -> list[tuple[Any, ...]]:
    monkeypatch.chdir(cwd)
    result = CliRunner().invoke(app, ["validate", str(path), "-f", "json"])
    found = json.loads(result.stdout)["files"][0]["diagnostics"]
    return [(d["code"], d["line"], d["column"], d["message"]) for d in found]


def as_validate(diagnostics: list[Any]) -> list[tuple[Any, ...]]:
    return [
        (
            d.code,
            d.range.start.line + 1,
            d.range.start.character + 1,
            d.message.split("\nhint: ")[0],
        )
        for d in diagnostics
    ]


MOVE = "#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,P1,0\n00:00:040,P2,2.0\n"  # too fast, too far


@pytest.fixture
def nao(tmp_path: Path) -> Path:
    (tmp_path / "pyproject.toml").write_text('[tool.motiontool]\nrobot = "nao"\n')
    return tmp_path


def test_only_the_newest_version_is_published(nao: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = nao / "walk.motion"
    texts = [big_motion(10000, nudge=v) for v in range(12)]
    texts.append(big_motion(10000, phase=0.1))  # every line new: no lint of it is quick
    seen: list[Any] = []

    async def body(session: Session) -> None:
        uri = session.open(path, texts[1])
        assert (await session.next(uri)).version == 1
        for version in range(2, 12):  # ten changes at once: one lint, of the last
            session.change(uri, version, texts[version])
        seen.append(await session.next(uri))
        session.change(uri, 12, texts[12])  # a change while version 12 is linted...
        await asyncio.sleep(0.15)
        session.change(uri, 13, texts[0])  # ...supersedes it: 12 is not published
        seen.append(await session.next(uri))
        await asyncio.sleep(0.5)
        assert session.queue(uri).empty(), [p.version for p in seen]

    run_session(nao, body)
    assert [p.version for p in seen] == [11, 13]
    for params, text in zip(seen, [texts[11], texts[0]], strict=True):
        path.write_text(text)
        assert as_validate(params.diagnostics) == validate_json(path, nao, monkeypatch)
    assert seen[1].diagnostics, "the motion has findings"


def test_pull_diagnostics_and_cancel_request(nao: Path) -> None:
    text = big_motion(10000)
    got: dict[str, Any] = {}

    async def body(session: Session) -> None:
        uri = session.open(nao / "walk.motion", text)
        params = lsp.DocumentDiagnosticParams(text_document=lsp.TextDocumentIdentifier(uri=uri))
        protocol = session.client.protocol
        waiting = protocol.send_request_async(lsp.TEXT_DOCUMENT_DIAGNOSTIC, params, msg_id="p1")
        await asyncio.sleep(0.02)
        protocol.notify(lsp.CANCEL_REQUEST, lsp.CancelParams(id="p1"))
        with pytest.raises(JsonRpcRequestCancelled):
            await asyncio.wait_for(waiting, timeout=60)
        got["pushed"] = await session.next(uri)
        got["full"] = await session.client.text_document_diagnostic_async(params)
        params.previous_result_id = got["full"].result_id
        got["same"] = await session.client.text_document_diagnostic_async(params)

    run_session(nao, body)
    full, pushed = got["full"], got["pushed"]
    assert full.kind == "full" and full.result_id == "1" and full.items
    assert full.items == pushed.diagnostics
    assert got["same"].kind == "unchanged" and got["same"].result_id == "1"


def test_each_finding_links_its_rule(nao: Path) -> None:
    found: list[Any] = []

    async def body(session: Session) -> None:
        uri = session.open(nao / "walk.motion", big_motion(200))
        found.extend((await session.next(uri)).diagnostics)

    run_session(nao, body)
    rules = (ROOT / "docs" / "rules.md").read_text()
    assert found
    for d in found:
        base, anchor = d.code_description.href.split("#")
        assert base == (ROOT / "docs" / "rules.md").as_uri() and anchor == d.code.lower()
        assert f"\n## {d.code}\n" in rules


@pytest.mark.parametrize(
    ("config", "at", "words"),
    [
        ('[tool.motiontool]\nrobot = "nao"\nrobbot = "nao"\n', (2, 0), "unknown key 'robbot'"),
        ('[tool.motiontool]\nrobot = "nao"\nignore = [MT2]\n', (2, 10), "not valid TOML"),
    ],
)
def test_a_broken_configuration_is_a_finding_on_it(
    nao: Path, config: str, at: tuple[int, int], words: str
) -> None:
    pyproject = nao / "pyproject.toml"
    pyproject.write_text(config)
    config_uri = from_fs_path(str(pyproject))
    got: dict[str, Any] = {}

    async def body(session: Session) -> None:
        uri = session.open(nao / "walk.motion", big_motion(50))
        got["config"] = await session.next(config_uri)
        got["doc"] = await session.next(uri)
        # A motion under a configuration of its own is linted; the error stays where it is.
        (nao / "fine").mkdir()
        (nao / "fine" / "motiontool.toml").write_text('robot = "nao"\n')
        assert (await session.next(session.open(nao / "fine" / "a.motion", MOVE))).diagnostics
        assert session.queue(config_uri).empty()
        pyproject.write_text('[tool.motiontool]\nrobot = "nao"\n')  # fixed, then typed on
        session.change(uri, 2, big_motion(50, nudge=1))
        got["cleared"] = await session.next(config_uri)
        got["linted"] = await session.next(uri)

    session = run_session(nao, body)
    (error,) = got["config"].diagnostics
    assert (error.range.start.line, error.range.start.character) == at
    assert words in error.message and error.severity == lsp.DiagnosticSeverity.Error
    (not_linted,) = got["doc"].diagnostics
    assert not_linted.message.startswith("not linted: ") and words in not_linted.message
    assert not_linted.related_information[0].location.uri == config_uri
    assert not got["cleared"].diagnostics and got["linted"].diagnostics
    assert session.popups == [], "no popup, no Python exception name"
