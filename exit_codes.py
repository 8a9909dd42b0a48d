"""What every command's exit status means, one home: the CLI raises these, the play and batch
reports write them into their JSON (``exit_code``), the help text and the docs name them."""

from __future__ import annotations

import signal

__all__ = [
    "BROKEN_PIPE",
    "BY_SIGNAL",
    "CLEAN",
    "ERROR",
    "FINDINGS",
    "HANGUP",
    "INTERRUPTED",
    "SUMMARY",
    "TERMINATED",
]

CLEAN = 0
"""Nothing found, the run clean."""

FINDINGS = 1
"""Findings (a lint problem, a fix that would change the file), or a run that fell, collided
or failed an expectation."""

ERROR = 2
"""A usage, input or I/O error: the command (or a run) could not do its work."""

INTERRUPTED = 128 + signal.SIGINT
"""Ctrl-C (130), as a shell reports a command that SIGINT ended."""

BROKEN_PIPE = 128 + signal.SIGPIPE
"""The reader of standard output went away (141, ``| head``), as a shell reports SIGPIPE."""

TERMINATED = 128 + signal.SIGTERM
"""SIGTERM (143: ``kill``, ``docker stop``, a CI job's timeout), its temporary files removed."""

HANGUP = 128 + signal.SIGHUP
"""SIGHUP (129: the terminal went away), its temporary files removed."""

BY_SIGNAL: dict[int, int] = {
    signal.SIGINT: INTERRUPTED,
    signal.SIGPIPE: BROKEN_PIPE,
    signal.SIGTERM: TERMINATED,
    signal.SIGHUP: HANGUP,
}
"""The exit status of a process that ``signal`` ended, as a shell reports it."""

SUMMARY = (
    f"Exit codes: {CLEAN} clean, {FINDINGS} findings (or a failed run), {ERROR} usage or I/O "
    f"error; ended early: {INTERRUPTED} Ctrl-C, {TERMINATED} SIGTERM, {HANGUP} SIGHUP "
    f"(temporary files removed), {BROKEN_PIPE} a closed pipe."
)
"""The line ``motiontool --help`` ends its description with."""
