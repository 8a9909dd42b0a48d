"""A Rerun server without a viewer (the ``rerun`` program), saving the stream it receives: what
a live view is tested against."""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

__all__ = ["Server", "free_port"]

SERVER_START_S = 30.0
"""Wall-clock seconds the Rerun server has to listen (a loaded machine is slow to start it)."""


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
        return port


class Server:
    """``rerun --port P --save FILE``: a Rerun server without a viewer that saves what it gets."""

    def __init__(self, save: Path) -> None:
        self.port, self.save = free_port(), save
        rerun = Path(sys.executable).with_name("rerun")
        self.proc = subprocess.Popen(
            [str(rerun), "--port", str(self.port), "--save", str(save)],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            start_new_session=True,  # its own group: stopped with the program it starts
        )
        deadline = time.monotonic() + SERVER_START_S
        while not self._listening():
            assert self.proc.poll() is None, "the rerun server exited"
            assert time.monotonic() < deadline, "the rerun server does not listen"
            time.sleep(0.1)

    @property
    def url(self) -> str:
        return f"rerun+http://127.0.0.1:{self.port}/proxy"

    def _listening(self) -> bool:
        try:
            socket.create_connection(("127.0.0.1", self.port), timeout=1).close()
        except OSError:
            return False
        return True

    def stop(self) -> None:
        """Ctrl-C, as a person stops it: it writes what it got and exits."""
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGINT)
            try:
                self.proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGKILL)
                self.proc.wait()
