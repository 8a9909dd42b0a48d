"""What the process is given, beyond its arguments: standard streams that are closed, and
the signals that end it (SIGTERM from ``docker stop`` or a CI timeout, SIGHUP from a closed
terminal). Every case runs the installed console script as a subprocess."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = str(Path(sys.executable).parent / "motiontool")
HEAD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,Pose1,0,0\n00:00:160,Pose2,0.2,0.1\n"


@pytest.fixture
def here(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    (tmp_path / "in.motion").write_bytes(HEAD)
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    return tmp_path


def closed(redirect: str, *args: str) -> subprocess.CompletedProcess[bytes]:
    """``motiontool ARGS`` with a standard stream closed by the shell (``>&-``, ``2>&-``,
    ``<&-``), the others captured."""
    return subprocess.run(
        ["sh", "-c", f'exec "$@" {redirect}', "sh", SCRIPT, *args],
        capture_output=True,
        check=False,
    )


@pytest.mark.parametrize(
    "line",
    [["-V"], ["codes"], ["validate", "in.motion"], ["sample", "in.motion"]],
    ids=lambda c: c[0],
)
def test_a_closed_stdout_is_one_line_and_exit_2(here: Path, line: list[str]) -> None:
    done = closed(">&-", *line)
    assert done.returncode == 2, done.stderr
    assert done.stderr == b"motiontool: error: cannot write to standard output: it is closed\n"


def test_a_closed_stdout_is_no_error_for_a_command_that_writes_nothing_there(here: Path) -> None:
    done = closed(">&-", "validate", "in.motion", "-f", "json", "-o", "report.json")
    assert done.returncode == 0, done.stderr
    assert json.loads((here / "report.json").read_bytes())["summary"]
    assert b"Traceback" not in done.stderr


def test_a_file_opened_while_stdout_is_closed_gets_no_other_output(here: Path) -> None:
    """With descriptor 1 closed, the first file opened would take its number: the tool holds
    it on the null device, so that nothing meant for standard output lands in the file."""
    done = closed(">&-", "sample", "in.motion", "-o", "out.csv")
    assert done.returncode == 0, done.stderr
    assert (here / "out.csv").read_bytes().startswith(b"time_ms,HeadYaw,HeadPitch\n")
    done = closed(">&-", "mirror", "in.motion", "-o", "out.motion")  # it prints a summary
    assert done.returncode == 2
    assert done.stderr.endswith(
        b"motiontool: error: cannot write to standard output: it is closed\n"
    )
    assert (here / "out.motion").read_bytes().startswith(b"#WEBOTS_MOTION,V1.0,HeadYaw,")


@pytest.mark.parametrize(
    ("line", "code"),
    [(["-V"], 0), (["validate", "missing.motion"], 2), (["validate", "in.motion"], 0)],
    ids=["version", "missing", "clean"],
)
def test_a_closed_stderr_changes_no_exit_code(here: Path, line: list[str], code: int) -> None:
    done = closed("2>&-", *line)
    assert done.returncode == code
    if line == ["-V"]:
        assert done.stdout.startswith(b"motiontool ")


def test_a_closed_stdin_is_one_line(here: Path) -> None:
    done = closed("<&-", "validate", "-")
    assert done.returncode == 2
    assert done.stderr == (
        b"motiontool: error: cannot read '-' (<stdin>): there is no standard input\n"
    )
    assert closed("<&-", "validate", "in.motion").returncode == 0


def _lsp(*messages: dict[str, object]) -> bytes:
    out = b""
    for message in messages:
        body = json.dumps({"jsonrpc": "2.0", **message}).encode()
        out += b"Content-Length: %d\r\n\r\n" % len(body) + body
    return out


def test_the_server_exits_0_after_shutdown_and_exit(here: Path) -> None:
    """The LSP client's clean end: ``shutdown``, then ``exit``; the server closes its stdout
    itself before it returns."""
    pytest.importorskip("pygls")
    talk = _lsp(
        {"id": 1, "method": "initialize", "params": {"capabilities": {}}},
        {"method": "initialized", "params": {}},
        {"id": 2, "method": "shutdown"},
        {"method": "exit"},
    )
    done = subprocess.run(
        [SCRIPT, "server"], input=talk, capture_output=True, check=False, timeout=60
    )
    assert (done.returncode, done.stderr) == (0, b"")
    assert b'"id": 2' in done.stdout or b'"id":2' in done.stdout
