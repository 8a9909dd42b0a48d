"""Diagnostics: what ``validate`` reports, with stable codes.

Codes are grouped by what they mean for a robot:

* ``MT1xx`` errors: Webots rejects the file (``wbu_motion_new`` returns NULL) or plays something
  other than what is written.
* ``MT2xx`` warnings: Webots accepts the file, but reads or plays it in a way the author probably
  did not intend.
* ``MT3xx`` robot checks (limits, velocities, collisions, balance).
* ``MT9xx`` notes about the validation itself.

A code never changes meaning once released; retired codes are not reused.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field
from typing import NamedTuple

__all__ = [
    "BEYOND_LIMITS",
    "BLANK_LINE_ENDS",
    "CHECK_SKIPPED",
    "CODES",
    "COUPLED_JOINTS",
    "CUT_LINE",
    "EMPTY_CELL",
    "HEAD_PITCH_RANGE",
    "JOINT_TWICE",
    "NO_ROBOT",
    "NO_VALUE_CELL",
    "NUL_BYTE",
    "OFF_BALANCE",
    "SELF_COLLISION",
    "STREAM_TOO_FAST",
    "TOO_FAST",
    "TRAILING_CHARACTERS",
    "UNKNOWN_JOINT",
    "UNMIRRORED_COPY",
    "Code",
    "Diagnostic",
    "FixKind",
    "PoseFinding",
    "Related",
    "Run",
    "Severity",
    "Worst",
]


class Severity(enum.IntEnum):
    """How bad a finding is; ordered so that ``max()`` gives the worst."""

    INFO = 0
    WARNING = 1
    ERROR = 2

    def __str__(self) -> str:
        return self.name.lower()


class FixKind(enum.Enum):
    """What ``validate``'s fix of a code is (:mod:`motiontool.motionfmt.fixes`)."""

    SAFE = "safe"
    """What Webots does stays bit for bit the same."""
    UNSAFE = "unsafe"
    """What the robot does changes, to what the author evidently meant."""
    ROBOT = "robot"
    """Unsafe, and planned with the robot's limits (a
    :data:`~motiontool.motionfmt.fixes.RobotPlanner`)."""


class Code(NamedTuple):
    """A diagnostic code: its identifier, default severity and a one-line title.

    ``rejects``: a file with this finding is one Webots' loader rejects (``wbu_motion_new``
    returns NULL); the first such finding is :attr:`ReadResult.rejected_at
    <motiontool.motionfmt.reader.ReadResult.rejected_at>`. One code is decided per finding
    instead: MT112 (a pose time that overflows a C int) rejects the file only when the wrapped
    time is invalid to Webots; otherwise Webots reads the wrapped time. Its entry says False and
    the reader says which of its findings reject.

    ``fix``: what ``validate``'s fix of it is, or None (no automatic fix). ``also``: another
    severity some of its findings have (MT207's trailing runs are notes), or None.

    A code's other facts live elsewhere, keyed by its id, where the layers put them: the check
    that finds it (:data:`motiontool.kinematics.checks.registry.CHECK_REGISTRY`), and its
    explanation, example and documentation row (:data:`motiontool.cli.rules.RULES`), which
    name the command line's options. docs/architecture.md, *To add a code*, says what to write.
    """

    id: str
    severity: Severity
    title: str
    rejects: bool = False
    fix: FixKind | None = None
    also: Severity | None = None


def _codes(*codes: Code) -> dict[str, Code]:
    return {c.id: c for c in codes}


E, W, I = Severity.ERROR, Severity.WARNING, Severity.INFO  # noqa: E741
SAFE, UNSAFE, ROBOT = FixKind.SAFE, FixKind.UNSAFE, FixKind.ROBOT

# The codes library modules compare findings and fixes with, by name (one spelling each).
CUT_LINE = "MT111"
NUL_BYTE = "MT114"
BLANK_LINE_ENDS = "MT201"
EMPTY_CELL = "MT202"
TRAILING_CHARACTERS = "MT203"
NO_VALUE_CELL = "MT204"
JOINT_TWICE = "MT205"
BEYOND_LIMITS = "MT302"
TOO_FAST = "MT303"
UNKNOWN_JOINT = "MT301"
STREAM_TOO_FAST = "MT304"
HEAD_PITCH_RANGE = "MT305"
COUPLED_JOINTS = "MT306"
SELF_COLLISION = "MT307"
OFF_BALANCE = "MT308"
UNMIRRORED_COPY = "MT309"
NO_ROBOT = "MT901"
CHECK_SKIPPED = "MT902"

CODES: dict[str, Code] = _codes(
    # Webots rejects the file, or reads it otherwise than it is written.
    Code("MT100", E, "file is empty", rejects=True),
    Code("MT101", E, "invalid header: the first token must be '#WEBOTS_MOTION'", rejects=True),
    Code("MT102", E, "unsupported version: the second header token must be 'V1.0'", rejects=True),
    Code("MT103", E, "the header names no joint", rejects=True),
    Code("MT104", E, "the file has no pose", rejects=True),
    Code("MT105", E, "invalid pose time", rejects=True),
    Code("MT106", E, "pose times do not strictly increase", rejects=True),
    Code("MT107", E, "pose name missing", rejects=True),
    Code("MT108", E, "invalid value: expected a number or '*'", rejects=True),
    Code("MT109", E, "too few values on a pose line", rejects=True),
    Code("MT110", E, "too many values on a pose line", rejects=True),
    Code(CUT_LINE, E, "line of 4095 bytes or more: Webots cuts it into pieces"),
    # MT112 rejects only where the wrapped time is invalid: the reader decides per finding.
    Code("MT112", E, "pose time out of range: Webots' int milliseconds overflow"),
    Code("MT113", E, "value is nan or infinite"),
    Code(NUL_BYTE, E, "NUL byte: Webots stops reading the line there"),
    Code("MT115", E, "playback time overflows Webots' int at this time step: the motion replays"),
    # Webots accepts the file but plays something else than it seems to say.
    Code(
        BLANK_LINE_ENDS, W, "a blank line ends the motion: every later line is ignored", fix=UNSAFE
    ),
    Code(EMPTY_CELL, W, "empty cell between commas: the following values shift left", fix=UNSAFE),
    Code(TRAILING_CHARACTERS, W, "trailing characters after a number are ignored", fix=SAFE),
    Code(
        NO_VALUE_CELL, W, "-9999999.9 is Webots' marker for 'no value': it reads as '*'", fix=SAFE
    ),
    Code(JOINT_TWICE, W, "joint named twice: the later column wins", fix=SAFE),
    Code("MT206", W, "first pose after t = 0: the robot jumps to it at once"),
    Code("MT207", W, "'*' leaves a joint uncommanded over whole segments", also=I),
    Code("MT208", W, "bytes that are not UTF-8"),
    Code("MT209", W, "pose time is not a multiple of the controller time step"),
    Code("MT210", W, "joint name with leading or trailing white space"),
    Code("MT211", W, "a joint is never commanded: every cell is '*'"),
    # Robot checks (motiontool.kinematics.checks).
    Code(UNKNOWN_JOINT, W, "joint is not a motor of the robot: Webots ignores the column"),
    Code(BEYOND_LIMITS, E, "position outside the joint's limits: the motor is clamped", fix=ROBOT),
    Code(
        TOO_FAST,
        W,
        "segment faster than the joint's maxVelocity: the motor falls behind",
        fix=ROBOT,
    ),
    Code(STREAM_TOO_FAST, W, "command stream faster than maxVelocity at the controller time step"),
    Code(HEAD_PITCH_RANGE, E, "HeadPitch outside the real robot's HeadYaw-dependent range"),
    Code(COUPLED_JOINTS, E, "joints one motor drives on the real robot differ"),
    Code(SELF_COLLISION, W, "self-collision: two bodies of the robot overlap"),
    Code(OFF_BALANCE, W, "static balance: centre of mass outside the support polygon"),
    Code(UNMIRRORED_COPY, I, "a Left/Right file looks like an unmirrored copy of its sibling"),
    # Notes about the validation itself.
    Code(NO_ROBOT, I, "robot checks skipped"),
    Code(CHECK_SKIPPED, I, "check skipped: a library it needs is not installed"),
)


class PoseFinding(NamedTuple):
    """What lets a finding about one pose be grouped with the same finding at the poses next
    to it (:func:`motiontool.motionfmt.grouping.group_findings`).

    Attributes:
        pose: the 0-based index of the pose (of a keyframe segment: its end pose).
        subject: what every finding of a group says, the joint included
            (``RShoulderRoll above its upper limit 0.314159 rad``); findings of one code group
            only with findings of the same subject.
        value: the quantity the finding is about (the position, the speed), in ``unit``.
        unit: its unit (``rad``, ``m``, ``rad/s``).
        excess: how far ``value`` is past what is allowed (any unit, the same for the whole
            subject): the group's worst finding is the one with the largest.
        noun: what one finding is about, for the count (``pose``, ``segment``).
        hint: the group's hint; None: the first finding's.
        amount: how much this finding asks to change, which a group says of its worst one
            (MT303: ``2.8 rad/s above it: that move needs 27.8 ms, not 20 ms``); None:
            the worst value says it.
    """

    pose: int
    subject: str
    value: float
    unit: str
    excess: float
    noun: str = "pose"
    hint: str | None = None
    amount: str | None = None


class Worst(NamedTuple):
    """The worst finding of a group: its value (in ``unit``) and where it is."""

    value: float
    unit: str
    line: int
    column: int
    time_ms: int | None


class Run(NamedTuple):
    """What a grouped finding stands for: ``total`` findings at consecutive poses (in
    ``runs`` runs of them: more than :data:`~motiontool.motionfmt.grouping.MAX_RUNS` of one
    code and subject in a file make one finding), from the finding's own line to
    ``end_line``, the worst of them ``worst``.

    Attributes:
        identity: what identifies the group across edits of the file (its subject and first
            pose time, not its lines or count): what report fingerprints hash.
    """

    total: int
    end_line: int
    worst: Worst
    noun: str
    identity: str
    runs: int = 1


class Related(NamedTuple):
    """Another place a finding names (the previous pose of a time that does not increase):
    SARIF's ``relatedLocations``.

    Attributes:
        line: 1-based line.
        column: 1-based byte column.
        message: what is there, without its line (the location gives it).
    """

    line: int
    column: int
    message: str


@dataclass(frozen=True)
class Diagnostic:
    """One finding in one file.

    Attributes:
        code: stable identifier, a key of :data:`CODES`.
        severity: error, warning or info.
        path: the file as the user named it.
        line: 1-based line number (physical lines, split on ``\\n``).
        column: 1-based byte column of the first byte of the offending token.
        message: what was expected and what was found.
        hint: how to fix it, or ``None``.
        joint: the joint (column) concerned, or ``None``.
        time_ms: the pose time concerned, in milliseconds, or ``None``.
        end_column: 1-based column one past the last byte of the token, or ``None``.
        pose: what lets it be grouped with the same finding at the next poses (the robot
            checks' per-pose findings), or ``None``.
        run: for a grouped finding, the findings it stands for (``None``: one finding).
        related: other places the message names ("(line 3)"), each also a location of its own.
        stable: the message without the lines it names, which move when lines are added
            above (``None``: the message names no line): what identifies the finding.
    """

    code: str
    severity: Severity
    path: str
    line: int
    column: int
    message: str
    hint: str | None = None
    joint: str | None = None
    time_ms: int | None = None
    end_column: int | None = field(default=None, compare=False)
    pose: PoseFinding | None = field(default=None, compare=False, repr=False)
    run: Run | None = field(default=None, compare=False)
    related: tuple[Related, ...] = field(default=(), compare=False, repr=False)
    stable: str | None = field(default=None, compare=False, repr=False)

    @property
    def title(self) -> str:
        """The code's one-line title."""
        return CODES[self.code].title

    @property
    def count(self) -> int:
        """How many findings this one stands for: 1, or a group's count."""
        return 1 if self.run is None else self.run.total

    @property
    def identity(self) -> str:
        """What identifies the finding when lines are added above it: its message without the
        lines it names (:attr:`stable`), or for a grouped finding its subject and first pose
        time (its message names lines)."""
        if self.run is not None:
            return self.run.identity
        return self.message if self.stable is None else self.stable

    def format(self) -> str:
        """``path:line:col: severity CODE: message`` — one line, compiler style."""
        return f"{self.path}:{self.line}:{self.column}: {self.severity} {self.code}: {self.message}"

    def sort_key(self) -> tuple[str, int, int, str]:
        return (self.path, self.line, self.column, self.code)
