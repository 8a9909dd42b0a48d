"""``play``'s live view: streamed to a real Rerun server (the ``rerun`` program, headless, saving
what it receives), the same recording as ``--rrd``; paced on an injected clock; a viewer that
goes away ends the run; no display and no server: one line, exit 2."""

from __future__ import annotations

import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import typer
from rerun_server import Server, free_port
from rrds import rrd_contents
from typer.testing import CliRunner

from motiontool.cli.app import app

pytestmark = pytest.mark.needs("sim", "rerun")

runner = CliRunner()

NOD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,A,0,0\n00:00:300,B,0.6,-0.3\n00:00:600,C,0,0\n"


@pytest.fixture
def nod(tmp_path: Path) -> Path:
    path = tmp_path / "nod.motion"
    path.write_bytes(NOD)
    return path


@pytest.fixture
def server(tmp_path: Path) -> Iterator[Server]:
    s = Server(tmp_path / "live.rrd")
    try:
        yield s
    finally:
        s.stop()


def _read(path: Path) -> dict[str, list[Any]]:
    """The recording's contents; a stream saved by a stopped server has no footer (Rerun says
    so in a warning)."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="RRD file has no footer")
        return rrd_contents(path)


def _frames(contents: dict[str, list[Any]]) -> dict[str, int]:
    """Entity -> how many rows it has on the ``sim_time`` timeline."""
    out = {}
    for entity, batches in contents.items():
        rows = [b.num_rows for b in batches if "sim_time" in b.schema.names]
        if rows:
            out[entity] = sum(rows)
    return out


def test_connect_streams_what_rrd_writes(nod: Path, tmp_path: Path, server: Server) -> None:
    live = runner.invoke(app, ["play", str(nod), "--connect", server.url, "--fast"])
    assert live.exit_code == 0, live.output
    assert "result: clean" in live.stdout
    rrd = tmp_path / "run.rrd"
    written = runner.invoke(app, ["play", str(nod), "--headless", "--rrd", str(rrd)])
    assert written.exit_code == 0, written.output
    server.stop()

    streamed, recorded = _read(server.save), _read(rrd)
    assert set(streamed) == set(recorded)
    assert "/world/robot/torso" in streamed and "/joints/Head/HeadYaw/measured" in streamed
    frames = _frames(streamed)
    assert frames == _frames(recorded)
    assert frames["/world/robot/torso"] == 82  # 1.62 s at 20 ms: 81 steps, 82 frames


def test_paced_view_shows_each_chunk_when_its_time_has_come(nod: Path, server: Server) -> None:
    from motiontool.sim import play
    from motiontool.sim.live import LiveView

    now = [0.0]
    slept: list[float] = []

    def sleep(s: float) -> None:
        slept.append(s)
        now[0] += s

    live = LiveView(server.url, speed=2.0, clock=lambda: now[0], sleep=sleep)
    report = play([nod], live=live)
    # 1.62 s simulated, at twice real time: 0.81 s of the injected clock, in 0.1 s chunks.
    assert now[0] == pytest.approx(report.simulated_s / 2)
    assert len(slept) == 17 and max(slept) == pytest.approx(0.05)
    # The same physics as headless, bit for bit; sums over the run differ in the last digit
    # (they are summed a chunk at a time).
    headless = play([nod])
    assert report.base == headless.base
    assert [j.max_error for j in report.joints] == [j.max_error for j in headless.joints]
    rms = [j.rms_error for j in headless.joints]
    assert [j.rms_error for j in report.joints] == pytest.approx(rms, rel=1e-12, abs=0)


def test_a_viewer_that_closes_ends_the_run_with_a_note(nod: Path, server: Server) -> None:
    from motiontool.sim import play
    from motiontool.sim.live import LiveView, ViewerClosed

    now = [0.0]

    def sleep(s: float) -> None:
        now[0] += s
        if now[0] > 0.3:  # the person closes the viewer 0.3 s into the run
            server.stop()

    live = LiveView(server.url, clock=lambda: now[0], sleep=sleep)
    with pytest.raises(ViewerClosed, match=r"closed at 0\.[4-6]\d s simulated"):
        play([nod], live=live)

    from motiontool.cli.live import stopped

    with pytest.raises(typer.Exit) as exit_:
        stopped(ViewerClosed(0.5, server.url))
    assert exit_.value.exit_code == 0


def test_without_a_display_or_a_server_it_says_what_to_pass(
    nod: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    result = runner.invoke(app, ["play", str(nod)])
    assert result.exit_code == 2
    (line,) = result.stderr.splitlines()
    assert "no display to show the run on" in line
    assert all(flag in line for flag in ("--headless", "--rrd", "--connect")), line
    assert "Traceback" not in result.output


def test_nothing_at_the_url_is_one_line_exit_2(nod: Path) -> None:
    url = f"rerun+http://127.0.0.1:{free_port()}/proxy"
    result = runner.invoke(app, ["play", str(nod), "--connect", url, "--fast"])
    assert result.exit_code == 2
    assert result.stderr == f"motiontool: error: no Rerun viewer or server answers at {url}\n"


@pytest.mark.parametrize(
    ("args", "said"),
    [
        (["--headless", "--fast"], "--fast is for the live view"),
        (["--fast", "--speed", "2"], "pass one"),
        (["--speed", "0", "--connect", "rerun+http://127.0.0.1:1/proxy"], "positive number"),
        (["--connect", "http://example.org"], "not a Rerun viewer's URL"),
    ],
)
def test_contradicting_view_options_are_refused(nod: Path, args: list[str], said: str) -> None:
    result = runner.invoke(app, ["play", str(nod), *args])
    assert result.exit_code == 2 and said in result.stderr, result.output
