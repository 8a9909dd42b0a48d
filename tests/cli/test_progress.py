"""Long single jobs show progress on a terminal only (issue #17 item 8): ``validate``, ``play``
and ``mirror`` draw a spinner on standard error when it is a terminal (a pseudo-terminal the
test opens), never in a pipe, and the report on standard output is the same either way."""

from __future__ import annotations

import os
import pty
import shutil
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from conftest import ROOT

NOD = ROOT / "motions" / "nao" / "head_no.motion"


def motiontool() -> str:
    found = shutil.which("motiontool", path=str(Path(sys.executable).parent))
    assert found, "motiontool is installed beside this Python (pip install -e .)"
    return found


def run(args: list[str], cwd: Path, *, tty: bool) -> tuple[int, bytes, bytes]:
    """Exit code, stdout, and stderr: a pipe, or the output of a pseudo-terminal."""
    env = {**os.environ, "COLUMNS": "120", "TERM": "xterm"}
    env.pop("NO_COLOR", None)
    if not tty:
        proc = subprocess.run([motiontool(), *args], capture_output=True, cwd=cwd, env=env)
        return proc.returncode, proc.stdout, proc.stderr
    master, slave = pty.openpty()
    with subprocess.Popen(
        [motiontool(), *args], stdout=subprocess.PIPE, stderr=slave, cwd=cwd, env=env
    ) as proc:
        os.close(slave)
        terminal = b""
        while True:
            try:
                chunk = os.read(master, 65536)
            except OSError:  # the terminal's other end closed: the process is done
                break
            if not chunk:
                break
            terminal += chunk
        assert proc.stdout is not None
        out = proc.stdout.read()
    os.close(master)
    return proc.wait(), out, terminal


@pytest.mark.parametrize(
    ("args", "title"),
    [
        (["validate", str(NOD), "--robot", "nao"], b"validate"),
        (["mirror", str(NOD), "-o", "-"], b"mirror"),
    ],
    ids=["validate", "mirror"],
)
def test_a_spinner_on_a_terminal_and_nothing_in_a_pipe(
    tmp_path: Path, args: list[str], title: bytes
) -> None:
    code, out, terminal = run(args, tmp_path, tty=True)
    piped_code, piped_out, piped_err = run(args, tmp_path, tty=False)
    assert (code, out) == (piped_code, piped_out)  # the report does not change
    assert title + b":" in terminal or title in terminal
    assert title + b":" not in piped_err


@pytest.mark.needs("sim")
@pytest.mark.slow
def test_play_shows_it_is_running_on_a_terminal(tmp_path: Path) -> None:
    args = ["play", str(NOD), "--headless", "--robot", "nao"]
    code, out, terminal = run(args, tmp_path, tty=True)
    assert code == 0 and b"play" in terminal
    _, piped_out, piped_err = run(args, tmp_path, tty=False)
    assert b"play:" not in piped_err
    assert len(out.splitlines()) == len(piped_out.splitlines())


def test_a_report_to_the_terminal_ends_the_display_before_its_first_byte(
    capsys: pytest.CaptureFixture[str],
) -> None:
    from motiontool.cli.output import emit_pieces

    seen: list[str] = []

    def pieces() -> Iterator[str]:
        seen.append("made")
        yield "robot: nao\n"
        seen.append("made")
        yield "checked 1 file\n"

    emit_pieces(pieces(), None, before_writing=lambda: seen.append(capsys.readouterr().out))
    assert seen == ["made", "made", ""]  # the display ended before anything was written
    assert capsys.readouterr().out == "robot: nao\nchecked 1 file\n"
