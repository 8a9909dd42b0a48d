"""The ``.motion`` format: Webots-exact reading, lossless editing, canonical writing, playback,
the format's transforms (:mod:`.resample`, :mod:`.retime`; :mod:`.ops`: mirror, concat, trim,
scale) and other formats (:mod:`.convert`). It knows no robot: a robot's limits or mirror map
come in as plain mappings.

May import the standard library, numpy and the top-level modules (errors, extras, stamps,
disk_cache); never ``kinematics``, ``sim`` or ``cli``.
"""

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
    return loads(read_file(path), source_name(path))


def read_motion(path: str) -> Motion:
    """Read a file as the :class:`Motion` Webots plays (raises :class:`MotionSyntaxError`).

    ``-`` reads standard input, named ``<stdin>``."""
    return read_bytes(read_file(path), source_name(path)).motion
