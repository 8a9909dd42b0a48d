"""A run shown live in a Rerun viewer as it is simulated, paced at a chosen speed.

:class:`LiveView` says where the run goes (a viewer or server at a URL, or a viewer spawned on
this machine) and how fast; :mod:`motiontool.sim.recording` logs to it what it logs to a
``.rrd`` (the same entities, blueprint and properties: :func:`attach` tees the recording
stream). :class:`Pacer` holds each chunk of the run back until its simulated time has come on
the wall clock, then checks that the viewer is still there: a viewer that went away raises
:class:`ViewerClosed`, which ends the run (the physics is never paced or interrupted inside a
chunk; a live run is simulated in short chunks, :meth:`LiveView.chunk_steps`).
"""

from __future__ import annotations

import os
import shutil
import socket
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING
from urllib.parse import urlsplit

from motiontool.errors import MotionToolError
from motiontool.motionfmt.units import MS_PER_S

if TYPE_CHECKING:
    import rerun

    from motiontool.sim.trace import Trace

__all__ = ["DEFAULT_PORT", "LiveView", "Pacer", "ViewerClosed", "attach", "has_display"]

DEFAULT_PORT = 9876
"""The port of a spawned viewer (Rerun's own default: a viewer already there is reused)."""

CHUNK_S = 0.1
"""Simulated seconds a live run shows at once, s (its chunks of control steps)."""

CHECK_EVERY_S = 0.5
"""Wall-clock seconds between two checks that the viewer is still there, s."""

START_WAIT_S = 5.0
"""Wall-clock seconds a spawned viewer has to start listening after Rerun's own wait, s."""

CONNECT_TIMEOUT_S = 2.0
"""Wall-clock seconds to reach the viewer at each check, s."""


class ViewerClosed(Exception):  # an event, not a fault: the run ends cleanly
    """The viewer went away during the run; the run stopped there."""

    def __init__(self, at_s: float, url: str) -> None:
        super().__init__(f"the Rerun viewer at {url} closed at {at_s:.2f} s simulated")
        self.at_s, self.url = at_s, url


def has_display() -> bool:
    """Whether a window can be opened here: macOS and Windows, or an X11 / Wayland display."""
    if sys.platform in ("darwin", "win32"):
        return True
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


@dataclass(frozen=True)
class LiveView:
    """Where and how fast a run is shown.

    Attributes:
        url: a running viewer or server, ``rerun+http://HOST:PORT/proxy``; None: spawn a viewer
            on this machine (port :data:`DEFAULT_PORT`).
        speed: simulated seconds per wall-clock second (1: real time); None: as fast as the
            machine allows.
        clock, sleep: the wall clock, s, and how to wait on it (a test passes its own).
    """

    url: str | None = None
    speed: float | None = 1.0
    clock: Callable[[], float] = field(default=time.monotonic, repr=False, compare=False)
    sleep: Callable[[float], None] = field(default=time.sleep, repr=False, compare=False)

    @property
    def target(self) -> str:
        """The URL the run streams to."""
        return self.url or f"rerun+http://127.0.0.1:{DEFAULT_PORT}/proxy"

    def chunk_steps(self, timestep_ms: int) -> int | None:
        """Control steps simulated at once: :data:`CHUNK_S` of them when paced, else None (the
        usual chunks)."""
        if self.speed is None:
            return None
        return max(1, round(CHUNK_S * MS_PER_S / timestep_ms))

    def pacer(self) -> Pacer:
        return Pacer(self)


def _address(url: str) -> tuple[str, int]:
    """Host and port of a Rerun URL (``rerun://``, ``rerun+http(s)://``)."""
    parts = urlsplit(url)
    if not parts.scheme.startswith("rerun") or not parts.hostname:
        raise MotionToolError(
            f"'{url}' is not a Rerun viewer's URL; expected rerun+http://HOST:PORT/proxy"
        )
    try:
        port = parts.port
    except ValueError as exc:
        raise MotionToolError(f"'{url}': {exc}; expected rerun+http://HOST:PORT/proxy") from exc
    return parts.hostname, port or DEFAULT_PORT


def _reachable(url: str) -> bool:
    try:
        socket.create_connection(_address(url), timeout=CONNECT_TIMEOUT_S).close()
    except OSError:
        return False
    return True


def _spawn(live: LiveView, rec: rerun.RecordingStream) -> None:
    """A viewer on :data:`DEFAULT_PORT` (the one already there, else a new one), listening."""
    import rerun as rr

    if _reachable(live.target):
        return
    exe = Path(sys.executable).with_name("rerun")
    path = str(exe) if exe.is_file() else shutil.which("rerun")
    if path is None:
        raise MotionToolError("no Rerun viewer to spawn: the 'rerun' program is not installed")
    rr.spawn(
        port=DEFAULT_PORT,
        connect=False,
        executable_path=path,
        hide_welcome_screen=True,
        recording=rec,  # enabled: rerun's global recording is not used, so it is off
    )
    deadline = live.clock() + START_WAIT_S
    while not _reachable(live.target):
        if live.clock() > deadline:
            raise MotionToolError(
                f"the Rerun viewer spawned did not listen on port {DEFAULT_PORT} within "
                f"{START_WAIT_S:g} s"
            )
        live.sleep(0.1)


def attach(rec: rerun.RecordingStream, live: LiveView, file: Path) -> None:
    """Log ``rec`` to ``file`` and, as it is logged, to the live viewer (spawned first where
    ``live`` names none).

    Raises:
        MotionToolError: no viewer at the URL, or none could be spawned.
    """
    import rerun as rr

    if live.url is None:
        _spawn(live, rec)
    elif not _reachable(live.url):
        raise MotionToolError(f"no Rerun viewer or server answers at {live.url}")
    rec.set_sinks(rr.FileSink(str(file)), rr.GrpcSink(live.target))


class Pacer:
    """Holds each chunk of a run back until its time has come (at ``live.speed``; none
    without a speed) and checks, at most every :data:`CHECK_EVERY_S`, that the viewer is still
    there. Put it before the recorder among a run's takers: a chunk is then shown when its
    simulated time has come."""

    def __init__(self, live: LiveView) -> None:
        self.live = live
        self._start: tuple[float, float] | None = None  # (wall clock, simulated time), s
        self._checked = live.clock()

    def add(self, chunk: Trace) -> None:
        live, now = self.live, self.live.clock()
        if self._start is None:
            self._start = (now, float(chunk.time_s[0]))
        if live.speed is not None:
            due = self._start[0] + (float(chunk.time_s[-1]) - self._start[1]) / live.speed
            if due > now:
                live.sleep(due - now)
                now = due
        if now - self._checked >= CHECK_EVERY_S:
            self._checked = now
            if not _reachable(live.target):
                raise ViewerClosed(float(chunk.time_s[0]), live.target)
