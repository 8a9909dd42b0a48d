"""The ``.motion`` format: Webots-exact reading, lossless editing, canonical writing, playback,
the format's transforms (:mod:`.resample`, :mod:`.retime`; :mod:`.ops`: mirror, concat, trim,
scale) and other formats (:mod:`.convert`). It knows no robot: a robot's limits or mirror map
come in as plain mappings.

May import the standard library, numpy and the top-level modules (errors, extras, stamps,
disk_cache); never ``kinematics``, ``sim`` or ``cli``.
"""

from __future__ import annotations

import typing

from motiontool.lazy_names import lazy_names as _lazy_names

if typing.TYPE_CHECKING:
    from motiontool.errors import MissingExtraError, MotionSyntaxError, MotionToolError
    from motiontool.motionfmt.clock import PlaybackNeverEndsError
    from motiontool.motionfmt.diagnostics import CODES, Code, Diagnostic, Severity
    from motiontool.motionfmt.document import MotionDocument, dumps, loads
    from motiontool.motionfmt.fileio import (
        atomic_write,
        collect_motion_files,
        read_file,
        source_name,
    )
    from motiontool.motionfmt.motion import Motion
    from motiontool.motionfmt.nonfinite import NonFiniteCommandError
    from motiontool.motionfmt.player import (
        CommandStream,
        Held,
        commands_at,
        elapsed_steps,
        hold_targets,
        iter_commands,
        sample,
        step_count,
        targets_at,
    )
    from motiontool.motionfmt.reader import NO_VALUE_MARKER, ReadResult, read_bytes
    from motiontool.motionfmt.validate import (
        Check,
        FileReport,
        ValidationReport,
        validate_bytes,
        validate_paths,
    )
    from motiontool.motionfmt.writer import TimeStyle, format_motion, format_time, format_value

#: Where each public name lives: imported on first use (PEP 562), so that a module that needs
#: the reader (``validate``'s syntax level) does not import the document, the player and the
#: writer with it. ``from motiontool.motionfmt import loads`` works as it always did.
_HOMES: dict[str, str] = {
    "MissingExtraError": "motiontool.errors",
    "MotionSyntaxError": "motiontool.errors",
    "MotionToolError": "motiontool.errors",
    "PlaybackNeverEndsError": "motiontool.motionfmt.clock",
    "CODES": "motiontool.motionfmt.diagnostics",
    "Code": "motiontool.motionfmt.diagnostics",
    "Diagnostic": "motiontool.motionfmt.diagnostics",
    "Severity": "motiontool.motionfmt.diagnostics",
    "MotionDocument": "motiontool.motionfmt.document",
    "dumps": "motiontool.motionfmt.document",
    "loads": "motiontool.motionfmt.document",
    "atomic_write": "motiontool.motionfmt.fileio",
    "collect_motion_files": "motiontool.motionfmt.fileio",
    "read_file": "motiontool.motionfmt.fileio",
    "source_name": "motiontool.motionfmt.fileio",
    "Motion": "motiontool.motionfmt.motion",
    "NonFiniteCommandError": "motiontool.motionfmt.nonfinite",
    "CommandStream": "motiontool.motionfmt.player",
    "Held": "motiontool.motionfmt.player",
    "commands_at": "motiontool.motionfmt.player",
    "elapsed_steps": "motiontool.motionfmt.player",
    "hold_targets": "motiontool.motionfmt.player",
    "iter_commands": "motiontool.motionfmt.player",
    "sample": "motiontool.motionfmt.player",
    "step_count": "motiontool.motionfmt.player",
    "targets_at": "motiontool.motionfmt.player",
    "NO_VALUE_MARKER": "motiontool.motionfmt.reader",
    "ReadResult": "motiontool.motionfmt.reader",
    "read_bytes": "motiontool.motionfmt.reader",
    "Check": "motiontool.motionfmt.validate",
    "FileReport": "motiontool.motionfmt.validate",
    "ValidationReport": "motiontool.motionfmt.validate",
    "validate_bytes": "motiontool.motionfmt.validate",
    "validate_paths": "motiontool.motionfmt.validate",
    "TimeStyle": "motiontool.motionfmt.writer",
    "format_motion": "motiontool.motionfmt.writer",
    "format_time": "motiontool.motionfmt.writer",
    "format_value": "motiontool.motionfmt.writer",
}

__all__ = [
    "CODES",
    "NO_VALUE_MARKER",
    "Check",
    "Code",
    "CommandStream",
    "Diagnostic",
    "FileReport",
    "Held",
    "MissingExtraError",
    "Motion",
    "MotionDocument",
    "MotionSyntaxError",
    "MotionToolError",
    "NonFiniteCommandError",
    "PlaybackNeverEndsError",
    "ReadResult",
    "Severity",
    "TimeStyle",
    "ValidationReport",
    "atomic_write",
    "collect_motion_files",
    "commands_at",
    "dumps",
    "elapsed_steps",
    "format_motion",
    "format_time",
    "format_value",
    "hold_targets",
    "iter_commands",
    "load",
    "loads",
    "read_bytes",
    "read_file",
    "read_motion",
    "sample",
    "source_name",
    "step_count",
    "targets_at",
    "validate_bytes",
    "validate_paths",
]


def load(path: str) -> MotionDocument:
    """Load a file Webots accepts as an editable document (raises :class:`MotionSyntaxError`).

    ``-`` reads standard input, named ``<stdin>``."""
    from motiontool.motionfmt.document import loads
    from motiontool.motionfmt.fileio import read_file, source_name

    return loads(read_file(path), source_name(path))


def read_motion(path: str) -> Motion:
    """Read a file as the :class:`Motion` Webots plays (raises :class:`MotionSyntaxError`).

    ``-`` reads standard input, named ``<stdin>``."""
    from motiontool.motionfmt.fileio import read_file, source_name
    from motiontool.motionfmt.reader import read_bytes

    return read_bytes(read_file(path), source_name(path)).motion


__getattr__, __dir__ = _lazy_names(__name__, _HOMES)
