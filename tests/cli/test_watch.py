"""``motiontool watch`` as a person uses it: the installed script against a real Rerun server
(saving what it receives), the file edited as editors save it, stopped with Ctrl-C."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
import warnings
from collections.abc import Callable
from pathlib import Path

import pytest
from rerun_server import Server

pytestmark = pytest.mark.needs("sim", "rerun", "watch")


NOD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,A,0,0\n00:00:300,B,0.6,-0.3\n00:00:600,C,0,0\n"
WAIT_S = 120.0
"""Wall-clock seconds a save has to be checked and played (a loaded machine is slow)."""


def _wait(what: str, done: Callable[[], bool], proc: subprocess.Popen[bytes]) -> None:
    deadline = time.monotonic() + WAIT_S
    while not done():
        assert proc.poll() is None, f"watch exited ({proc.returncode}) before {what}"
        assert time.monotonic() < deadline, f"no {what} within {WAIT_S:g} s"
        time.sleep(0.1)


def _takes(path: Path) -> int:
    """The recordings (takes) in a stream saved by the server."""
    from rerun.chunk import RrdReader

    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="RRD file has no footer")
        return len(RrdReader(path).recordings())


def test_each_save_is_checked_and_each_clean_one_played(tmp_path: Path) -> None:
    motion = tmp_path / "nod.motion"
    motion.write_bytes(NOD)
    server = Server(tmp_path / "live.rrd")
    out, err = tmp_path / "out.txt", tmp_path / "err.txt"
    script = Path(sys.executable).with_name("motiontool")
    with open(out, "wb") as o, open(err, "wb") as e:
        proc = subprocess.Popen(
            [str(script), "watch", str(motion), "--connect", server.url, "--fast"],
            stdout=o,
            stderr=e,
            cwd=tmp_path,
        )
    try:

        def seen(checks: int, played: int) -> Callable[[], bool]:
            def now() -> bool:
                text = out.read_text(errors="replace")
                return text.count("checked 1 file") >= checks and text.count("result:") >= played

            return now

        _wait("the first take", seen(1, 1), proc)
        with open(motion, "wb") as f:  # a valid change, saved in two writes
            f.write(NOD[:60])
            f.flush()
            f.write(NOD[60:].replace(b"0.6,-0.3", b"0.5,-0.3"))
        _wait("a take of the change", seen(2, 2), proc)
        saved = tmp_path / ".nod.motion.swp"  # an editor's atomic save: a copy renamed over
        saved.write_bytes(NOD.replace(b"0.6,-0.3", b"0.4,-0.3"))
        os.replace(saved, motion)
        _wait("a take of the renamed file", seen(3, 3), proc)
        motion.write_bytes(NOD.replace(b"0.6,-0.3", b"0.4,-a"))  # half typed: invalid
        _wait("the findings of the invalid save", seen(4, 3), proc)
        motion.write_bytes(NOD)  # the fix
        _wait("a take of the fix", seen(5, 4), proc)
        motion.unlink()  # deleted, then created again
        _wait("the deletion said", lambda: "is gone" in err.read_text(), proc)
        motion.write_bytes(NOD)
        _wait("a take of the file created again", seen(6, 5), proc)
        proc.send_signal(signal.SIGINT)
        assert proc.wait(timeout=60) == 130
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        server.stop()
    text = out.read_text()
    assert "HeadPitch" in text and "error MT" in text  # the invalid save's finding, as validate
    assert text.count("result: clean") == 5
    assert "Traceback" not in err.read_text()
    assert _takes(server.save) == 5  # the first take and four clean saves
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "err.txt",
        "live.rrd",
        "nod.motion",
        "out.txt",
    ]


def test_without_a_display_or_a_server_it_says_what_to_pass(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from typer.testing import CliRunner

    from motiontool.cli.app import app

    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    motion = tmp_path / "nod.motion"
    motion.write_bytes(NOD)
    result = CliRunner().invoke(app, ["watch", str(motion)])
    assert result.exit_code == 2
    (line,) = result.stderr.splitlines()
    assert "no display" in line and "--connect" in line, line
