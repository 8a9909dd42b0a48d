"""Every robot check, one :class:`CheckEntry` each: its name, whether ``validate`` runs it
by default, the extra it needs, the codes it reports and how it is made for a robot.

Everything else that names checks reads this table: :data:`CHECKS` and :data:`DEFAULT_CHECKS`,
:func:`~motiontool.kinematics.checks.runner.robot_checks`, the front end's ``--checks`` help and
configuration messages, the robot fixes (a code's fix runs where the check that finds it runs),
and the JSON schemas' check enums (a test ties them to :data:`CHECKS`). docs/architecture.md,
*To add a check*, says what to write.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

from motiontool.kinematics.checks.balance import Balance
from motiontool.kinematics.checks.joints import UnknownJoints
from motiontool.kinematics.checks.limits import Limits
from motiontool.kinematics.checks.self_collision import Collision
from motiontool.kinematics.checks.unmirrored import UnmirroredCopy
from motiontool.kinematics.checks.velocity import Velocity
from motiontool.kinematics.checks.wording import Wording
from motiontool.kinematics.robot_spec import RobotSpec
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
    Diagnostic,
)
from motiontool.motionfmt.reader import ReadResult

__all__ = [
    "ALWAYS",
    "CHECKS",
    "CHECK_REGISTRY",
    "DEFAULT_CHECKS",
    "NOTE_CODES",
    "CheckEntry",
    "CheckOptions",
    "check_of_code",
]

Check = Callable[[ReadResult], Sequence[Diagnostic]]


@dataclass(frozen=True)
class CheckOptions:
    """What a check may be made with, besides its robot.

    Attributes:
        timestep_ms: the controller step of the sampled command stream (None: the robot's).
        penetration_tolerance_mm: the collision check's tolerance (mm).
        wording: the front end's words for the hints' remedies.
    """

    timestep_ms: int | None
    penetration_tolerance_mm: float
    wording: Wording


@dataclass(frozen=True)
class CheckEntry:
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
        make: the check for one robot.
        kind: the class of what :attr:`make` returns.
        needs_feet: it checks only a robot with feet (sole geometries): asked for by name of
            a robot without, it is refused; picked per file (``auto``), skipped with a note.
    """

    name: str
    default: bool
    extra: str | None
    codes: tuple[str, ...]
    summary: str
    make: Callable[[RobotSpec, CheckOptions], Check]
    kind: type
    needs_feet: bool = False


CHECK_REGISTRY: tuple[CheckEntry, ...] = (
    CheckEntry(
        "limits",
        True,
        None,
        (BEYOND_LIMITS, HEAD_PITCH_RANGE, COUPLED_JOINTS),
        "positions within the joints' limits (and the real robot's rules, nao-v5)",
        lambda spec, _o: Limits(spec),
        Limits,
    ),
    CheckEntry(
        "velocity",
        True,
        None,
        (TOO_FAST, STREAM_TOO_FAST),
        "segments and the command stream within maxVelocity",
        lambda spec, o: Velocity(spec, o.timestep_ms),
        Velocity,
    ),
    CheckEntry(
        "collision",
        True,
        "kinematics",
        (SELF_COLLISION,),
        "no self-collision at the keyframes and segment midpoints",
        lambda spec, o: Collision(spec, o.penetration_tolerance_mm),
        Collision,
    ),
    CheckEntry(
        "balance",
        False,
        "kinematics",
        (OFF_BALANCE,),
        "the centre of mass over the support polygon (robots with feet)",
        lambda spec, _o: Balance(spec),
        Balance,
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
        lambda spec, o: UnknownJoints(spec, o.wording),
        UnknownJoints,
    ),
    CheckEntry(
        "mirror",
        True,
        None,
        (UNMIRRORED_COPY,),
        "a Left/Right file is no unmirrored copy of its sibling",
        lambda spec, o: UnmirroredCopy(spec, o.wording),
        UnmirroredCopy,
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
