"""A language client talking to a real ``motiontool server`` over stdio (pygls' client): what
the editor tests and their live variants drive the server with."""

from __future__ import annotations

import asyncio
import shutil
import sys
from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import Any

from conftest import import_extra

lsp = import_extra("lsprotocol.types", "lsp")
LanguageClient = import_extra("pygls.lsp.client", "lsp").LanguageClient
from_fs_path = import_extra("pygls.uris", "lsp").from_fs_path

__all__ = ["Session", "motiontool", "run_session"]


def motiontool() -> str:
    found = shutil.which("motiontool", path=str(Path(sys.executable).parent))
    assert found, "motiontool is installed beside this Python (pip install -e .)"
    return found


class Session:
    """A client talking to a running server; published diagnostics by URI, latest first."""

    def __init__(self, client: LanguageClient) -> None:
        self.client = client
        self.result: lsp.InitializeResult | None = None
        self.published: dict[str, asyncio.Queue[lsp.PublishDiagnosticsParams]] = {}
        self.popups: list[str] = []  # window/showMessage

    def queue(self, uri: str) -> asyncio.Queue[lsp.PublishDiagnosticsParams]:
        return self.published.setdefault(uri, asyncio.Queue())

    async def diagnostics(self, uri: str) -> list[lsp.Diagnostic]:
        params = await asyncio.wait_for(self.queue(uri).get(), timeout=60)
        return list(params.diagnostics)


def run_session(
    root: Path,
    body: Callable[[Any], Awaitable[None]],
    *args: str,
    capabilities: lsp.ClientCapabilities | None = None,
    session_type: type[Session] = Session,
) -> Session:
    """Start ``motiontool server ARGS`` in ``root``, initialise it, run ``body`` with a
    ``session_type`` session, shut the server down; the session, with what it gathered."""

    async def main() -> Session:
        client = LanguageClient("test-client", "1")
        session = session_type(client)

        @client.feature(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        def published(params: lsp.PublishDiagnosticsParams) -> None:
            session.queue(params.uri).put_nowait(params)

        @client.feature(lsp.WINDOW_SHOW_MESSAGE)
        def popup(params: lsp.ShowMessageParams) -> None:
            session.popups.append(params.message)

        await client.start_io(motiontool(), "server", *args, cwd=str(root))
        session.result = await client.initialize_async(
            lsp.InitializeParams(
                capabilities=capabilities or lsp.ClientCapabilities(),
                root_uri=from_fs_path(str(root)),
            )
        )
        client.initialized(lsp.InitializedParams())
        try:
            await body(session)
        finally:
            await client.shutdown_async(None)
            client.exit(None)
            await client.stop()
        return session

    return asyncio.run(main())
