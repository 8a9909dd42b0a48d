"""What the process is given besides its arguments: standard streams that may be closed
(``>&-``) and the signals that end it (SIGTERM from ``docker stop`` or a CI timeout, SIGHUP
from a closed terminal), for the entry point (:func:`motiontool.cli.app.main`)."""

from __future__ import annotations

import atexit
import contextlib
import errno
import functools
import gc
import io
import os
import signal
import sys
from collections.abc import Callable
from typing import Any

__all__ = [
    "ENDINGS",
    "Ended",
    "catch_endings",
    "caught",
    "flush_stdout",
    "hold_standard_streams",
    "quiet_stdout",
    "skip_exit_collection",
    "start_up_uncollected",
    "started",
]


def start_up_uncollected() -> None:
    """Turn the garbage collector off while the process starts: importing the command line
    and a command makes tens of thousands of objects that live as long as the process, and
    the collections their allocations set off scan them all again and again (3 ms of a 0.08 s
    hook run). :func:`started` turns it back on. Called by the console script
    (:mod:`motiontool.cli.__main__`) before anything else is imported."""
    gc.disable()


def started() -> None:
    """The command is about to run: what start-up made is moved out of the collector's sight
    (:func:`gc.freeze`: it lives as long as the process) and the collector turned back on
    for the command's own work. Nothing where the collector was on all along (the command line
    called in process, by a test or a library)."""
    if not gc.isenabled():
        gc.freeze()
        gc.enable()


def skip_exit_collection() -> None:
    """Spare the interpreter's exit its garbage collection over every object still alive.

    Python collects once more as it ends, over everything the run imported and made: about
    11 ms after ``validate``'s imports, a tenth of a pre-commit hook's run, and more after
    numpy's. Objects frozen by :func:`gc.freeze` are left out of it. Registered at start-up,
    this exit function runs after every one registered later (Ray's shutdown, Rerun's flush),
    when nothing of the run is left to do; objects held only by reference cycles are then not
    finalized, which Python does not promise at exit either. Module teardown, the flush of the
    standard streams and every ``atexit`` function still run as before.
    """
    atexit.register(gc.freeze)


def quiet_stdout() -> None:
    """Point standard output at the null device, so that the interpreter's last flush of what
    could not be written raises nothing more."""
    with contextlib.suppress(OSError, ValueError):
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, sys.stdout.fileno())
        os.close(null)


class _ClosedStream(io.RawIOBase):
    """A standard stream the process was started without (``>&-``): every write fails, as
    a write to a closed descriptor would, in words a user reads."""

    def writable(self) -> bool:
        return True

    def write(self, data: Any) -> int:
        raise OSError(errno.EBADF, "it is closed")


def hold_standard_streams() -> None:
    """Give a standard descriptor that the process was started without (``>&-``, ``2>&-``,
    ``<&-``) the null device, so that the first file the command opens cannot take its number
    and receive what was meant for the stream; a closed standard output then fails at its first
    write (one line, exit 2), and a command that writes nothing there runs as usual; what is
    written to a closed standard error is dropped (the exit code still says how it ended)."""
    for fd in (0, 1, 2):
        try:
            os.fstat(fd)
        except OSError:
            null = os.open(os.devnull, os.O_RDONLY if fd == 0 else os.O_WRONLY)
            if null != fd:  # the lowest free number: fd itself, unless a lower one was free too
                os.dup2(null, fd)
                os.close(null)
            if fd == 1:
                sys.stdout = io.TextIOWrapper(_ClosedStream(), encoding="utf-8", write_through=True)
            elif fd == 2:
                sys.stderr = open(fd, "w", encoding="utf-8", closefd=False)  # noqa: SIM115


ENDINGS: dict[int, str] = {signal.SIGTERM: "terminated", signal.SIGHUP: "hangup"}
"""The signals that end a command the way Ctrl-C does, and the word its one line says."""


class Ended(BaseException):
    """SIGTERM or SIGHUP, raised where the command is: every ``with`` and ``finally`` on the way
    out runs (temporary files removed, worker processes stopped), then the entry point says so in
    one line and exits 128 + N. Not an :class:`Exception`: nothing on the way mistakes it for
    a failed step and goes on."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum


_signalled: list[int] = []
"""The signal that is ending the command, once one came."""

_caught: list[int] = []
"""The same, once the entry point has caught its :class:`Ended`."""

_AGAIN_S = 0.2
"""How often, seconds, a signal's :class:`Ended` is raised again until the entry point catches
it: code that swallows every exception (a bare ``except:`` in a library, a finalizer) would
otherwise let the command run on as if the signal had never come."""


def _end(signum: int, frame: object) -> None:
    for ending in ENDINGS:  # a second one does not cut the way out short
        signal.signal(ending, signal.SIG_IGN)
    _signalled.append(signum)
    signal.signal(signal.SIGALRM, _again)
    signal.setitimer(signal.ITIMER_REAL, _AGAIN_S, _AGAIN_S)
    raise Ended(signum)


def _again(signum: int, frame: object) -> None:
    """Raise the signal's :class:`Ended` again, unless it is on its way out (the code that
    runs now is a ``finally``, an ``except`` or an ``__exit__`` it passes through) or caught."""
    exc = sys.exc_info()[1]
    while exc is not None:
        if isinstance(exc, Ended):
            return
        exc = exc.__context__
    if not _caught:
        raise Ended(_signalled[0])


def catch_endings(debug: Callable[[], bool]) -> None:
    """Turn SIGTERM and SIGHUP into :class:`Ended`, unless the process was started with them
    ignored (``nohup`` ignores SIGHUP): they stay ignored."""
    for ending in ENDINGS:
        if signal.getsignal(ending) is signal.SIG_DFL:
            signal.signal(ending, _end)
    sys.unraisablehook = functools.partial(_unraisable, sys.unraisablehook, debug)


def _unraisable(
    previous: Callable[[Any], object], debug: Callable[[], bool], unraisable: Any
) -> None:
    """Once a signal came, what a finalizer (``__del__``, a weak reference's callback) raises
    is not shown (``--debug`` shows it): an :class:`Ended` it swallowed is raised again
    (:func:`_again`), and objects the signal cut short in the middle fail as they go."""
    if not _signalled or debug():
        previous(unraisable)


def flush_stdout() -> None:
    """Flush standard output, so that a failed write surfaces in :func:`main`, not in the
    interpreter's exit; nothing for a stream already closed (the LSP server closes it when
    its client says ``exit``)."""
    if sys.stdout is not None and not sys.stdout.closed:
        sys.stdout.flush()


def caught(exc: Ended) -> None:
    """The entry point caught ``exc``: it is not raised again (:func:`_again`)."""
    signal.setitimer(signal.ITIMER_REAL, 0)
    _caught.append(exc.signum)
