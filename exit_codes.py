"""What every command's exit status means, one home: the CLI raises these, the play and batch
reports write them into their JSON (``exit_code``), the help text and the docs name them."""

from __future__ import annotations

import signal

__all__ = ["BROKEN_PIPE", "CLEAN", "ERROR", "FINDINGS", "INTERRUPTED", "SUMMARY"]

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

SUMMARY = (
    f"Exit codes: {CLEAN} clean, {FINDINGS} findings (or a failed run), {ERROR} usage or I/O error."
)
"""The line ``motiontool --help`` ends its description with."""
