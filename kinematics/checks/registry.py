"""Every robot check, one :class:`CheckEntry` each: its name, whether ``validate`` runs it
by default, the extra it needs, the codes it reports and where its class is.

Everything else that names checks reads this table: :data:`CHECKS` and :data:`DEFAULT_CHECKS`,
:func:`parse_checks`, :func:`~motiontool.kinematics.checks.runner.robot_checks`, the front
end's ``--checks`` help and configuration messages, the robot fixes (a code's fix runs where the
check that finds it runs), and the JSON schemas' check enums (a test ties them to
:data:`CHECKS`). docs/architecture.md, *To add a check*, says what to write.

The table is light: an entry names its class as ``module:Class``, imported when the check is
made for a robot (as :data:`~motiontool.cli.reports.REPORTS` names its writers), so that the
``--checks`` help and a syntax-level ``validate`` import no check and no robot model.
"""

from __future__ import annotations

import difflib
import importlib
from collections.abc import Callable, Iterable, Sequence
from typing import TYPE_CHECKING, NamedTuple, Protocol

from motiontool.errors import MotionToolError
from motiontool.motionfmt.diagnostics import (
    BEYOND_LIMITS,
    CHECK_SKIPPED,
    COUPLED_JOINTS,
    HEAD_PITCH_RANGE,
    NO_ROBOT,
    OFF_BALANCE,
    SELF_COLLISION,
    STREAM_TOO_FAST,
    TOO_FAST,
    UNKNOWN_JOINT,
    UNMIRRORED_COPY,
)

if TYPE_CHECKING:
    from motiontool.kinematics.checks.wording import Wording
    from motiontool.kinematics.robot_spec import RobotSpec
    from motiontool.motionfmt.diagnostics import Diagnostic
    from motiontool.motionfmt.reader import ReadResult

__all__ = [
    "ALWAYS",
    "CHECKS",
    "CHECK_REGISTRY",
    "DEFAULT_CHECKS",
    "DEFAULT_PENETRATION_TOLERANCE_MM",
    "NOTE_CODES",
    "CheckClass",
    "CheckEntry",
    "CheckOptions",
    "check_of_code",
    "parse_checks",
]

Check = Callable[["ReadResult"], Sequence["Diagnostic"]]

DEFAULT_PENETRATION_TOLERANCE_MM = 15.0
"""Self-collisions shallower than this (mm) are not reported.

The Webots robots' collision shapes are bounding primitives, larger than the bodies they stand
for: the Nao's forearm is a capsule, its foot force sensor a 147 x 89 mm box with sharp corners.
In the motions that ship with Webots (``tests/data/corpus/webots``), played as Webots plays them
(targets clamped to the motor limits), such shapes overlap by at most 10.0 mm: the two foot boxes
in the turns (TurnLeft40, TurnRight40, TurnLeft180), the head capsule and an arm raised within
its limits by 7.2 mm (HandWaveLeft, HandsUp) and 6.3 mm (HandHighLeft, HandWave). Those motions
are how the robot is meant to move, so overlaps of that size are artefacts of the shapes. (Left
unclamped, HandWaveLeft's LShoulderRoll of -0.5 rad, past the -0.314 rad limit, would put the
elbow 25 mm into the head: that value is reported as a limit error instead.) Bodies that really
meet go deeper: a hand saluting at the forehead 25 mm into the head, a right forearm folded
across the belly 33 mm into the torso, its hand 49 mm. 15 mm is the artefact ceiling, 10.0 mm,
plus half of it as a margin, well below the real contacts measured. It was chosen once, from
those measurements; ``--collision-tolerance`` sets another (0 reports every overlap).
"""


class CheckOptions(NamedTuple):
    """What a check may be made with, besides its robot.

    Attributes:
        timestep_ms: the controller step of the sampled command stream (None: the robot's).
        penetration_tolerance_mm: the collision check's tolerance (mm).
        wording: the front end's words for the hints' remedies.
    """

    timestep_ms: int | None
    penetration_tolerance_mm: float
    wording: Wording


class CheckClass(Protocol):
    """What an entry names: a check class that makes its check for a robot and a run."""

    @classmethod
    def for_run(cls, spec: RobotSpec, options: CheckOptions) -> Check:
        """The check of ``spec``, made with the options of this run that it takes."""


class CheckEntry(NamedTuple):
    """One robot check.

    Attributes:
        name: what a check list names it by (``limits``); an entry of :data:`ALWAYS` has a
            name only for progress and tests: it cannot be selected.
        default: ``validate`` runs it unless told which checks to run.
        extra: the ``motiontool[...]`` extra whose library it needs (None: the core's): a
            default check whose library is missing is skipped with an MT902 note.
        codes: the codes it reports (keys of
            :data:`~motiontool.motionfmt.diagnostics.CODES`).
        summary: what it checks, in a few words (the docs' checks table).
        where: ``module:Class``, its :class:`CheckClass` in this package (imported when the
            check is made: :attr:`kind`).
        needs_feet: it checks only a robot with feet (sole geometries): asked for by name of
            a robot without, it is refused; picked per file (``auto``), skipped with a note.
    """

    name: str
    default: bool
    extra: str | None
    codes: tuple[str, ...]
    summary: str
    where: str
    needs_feet: bool = False

    @property
    def kind(self) -> type[CheckClass]:
        """The check's class, imported on first use."""
        module, name = self.where.split(":")
        found: type[CheckClass] = getattr(importlib.import_module(f"{__package__}.{module}"), name)
        return found

    def make(self, spec: RobotSpec, options: CheckOptions) -> Check:
        """The check for ``spec`` in a run with ``options``."""
        return self.kind.for_run(spec, options)


CHECK_REGISTRY: tuple[CheckEntry, ...] = (
    CheckEntry(
        "limits",
        True,
        None,
        (BEYOND_LIMITS, HEAD_PITCH_RANGE, COUPLED_JOINTS),
        "positions within the joints' limits (and the real robot's rules, nao-v5)",
        "limits:Limits",
    ),
    CheckEntry(
        "velocity",
        True,
        None,
        (TOO_FAST, STREAM_TOO_FAST),
        "segments and the command stream within maxVelocity",
        "velocity:Velocity",
    ),
    CheckEntry(
        "collision",
        True,
        "kinematics",
        (SELF_COLLISION,),
        "no self-collision at the keyframes and segment midpoints",
        "self_collision:Collision",
    ),
    CheckEntry(
        "balance",
        False,
        "kinematics",
        (OFF_BALANCE,),
        "the centre of mass over the support polygon (robots with feet)",
        "balance:Balance",
        needs_feet=True,
    ),
)
"""The checks a run selects from, in the order they run."""

ALWAYS: tuple[CheckEntry, ...] = (
    CheckEntry(
        "joints",
        True,
        None,
        (UNKNOWN_JOINT,),
        "every column a motor of the robot",
        "joints:UnknownJoints",
    ),
    CheckEntry(
        "mirror",
        True,
        None,
        (UNMIRRORED_COPY,),
        "a Left/Right file is no unmirrored copy of its sibling",
        "unmirrored:UnmirroredCopy",
    ),
)
"""The checks every robot run makes, whatever is selected (they run first)."""

NOTE_CODES = (NO_ROBOT, CHECK_SKIPPED)
"""The robot run's notes about itself (a robot not found, a check skipped): the runner's."""

#: Every check name, in the order they run.
CHECKS: tuple[str, ...] = tuple(c.name for c in CHECK_REGISTRY)
#: What ``validate`` runs unless told otherwise (balance is opt-in).
DEFAULT_CHECKS: tuple[str, ...] = tuple(c.name for c in CHECK_REGISTRY if c.default)


def check_of_code(code: str) -> CheckEntry | None:
    """The entry of :data:`CHECK_REGISTRY` or :data:`ALWAYS` that reports ``code``, or None."""
    return next((c for c in (*CHECK_REGISTRY, *ALWAYS) if code in c.codes), None)


def parse_checks(names: str | Iterable[str]) -> tuple[str, ...]:
    """Check names from ``'limits,velocity'`` (or an iterable of such strings), in run order.

    ``all`` selects every check. Raises :class:`MotionToolError` naming the valid choices.
    """
    items = [names] if isinstance(names, str) else list(names)
    wanted: set[str] = set()
    for raw in (raw.strip() for item in items for raw in item.split(",")):
        wanted.update(_check_names(raw))
    if not wanted:
        raise MotionToolError(f"no check named; choose from {', '.join(CHECKS)} or all")
    return tuple(c for c in CHECKS if c in wanted)


def _check_names(raw: str) -> tuple[str, ...]:
    """The checks one item of a check list names (none for an empty item)."""
    name = raw.lower()
    if not name:
        return ()
    if name == "all":
        return CHECKS
    if name in CHECKS:
        return (name,)
    close = difflib.get_close_matches(name, CHECKS, n=1)
    hint = f"did you mean '{close[0]}'? " if close else ""
    raise MotionToolError(f"unknown check '{raw}'; {hint}choose from {', '.join(CHECKS)} or all")
