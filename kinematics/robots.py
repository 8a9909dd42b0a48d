"""Choosing a robot: by name (``--robot nao``, a model file, ``erd:<name>``), or from a motion's
joint names (``--robot auto``: :func:`rank_robots`, the one rule for which robot fits).

The specs themselves: :mod:`.robot_spec` (what a robot is), :mod:`.builtin_robots` (the shipped
robots, one table, and the names a robot is given by), :mod:`.erd` (URDF/MJCF files and
example-robot-data, through Pinocchio). Their names are re-exported here, where callers have
always found them.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Literal, NamedTuple

from motiontool.errors import MotionToolError
from motiontool.kinematics.builtin_robots import (
    AUTO,
    BUILTIN_ROBOTS,
    NONE,
    BuiltinRobot,
    builtin,
    builtin_robots,
    is_builtin,
    models_dir,
    robot_choices,
)
from motiontool.kinematics.erd import erd, erd_robot_names, from_pinocchio
from motiontool.kinematics.mjcf_table import parse_mjcf_table
from motiontool.kinematics.robot_spec import JointSpec, RobotSpec, fmt_name, unknown_joint_message

__all__ = [
    "AUTO",
    "DETECT_MIN_SHARE",
    "NONE",
    "JointSpec",
    "NoRobotDetectedError",
    "Ranking",
    "RobotError",
    "RobotSpec",
    "UnknownRobotError",
    "builtin_robots",
    "detect_robot",
    "erd_robot_names",
    "fmt_name",
    "load_robot",
    "models_dir",
    "pick_robot",
    "rank_robots",
    "resolve_robot",
    "robot_choices",
    "unknown_joint_message",
]


def load_robot(spec: str) -> RobotSpec:
    """The robot described by ``spec``.

    Args:
        spec: ``nao``, ``nao-v5`` or ``ur5e`` (built in; read without Pinocchio or MuJoCo),
            a path to a ``.urdf`` or ``.xml`` (MJCF) file, or ``erd:<name>`` for a robot of
            example-robot-data (e.g. ``erd:ur5``); the last two are read through Pinocchio.

    Raises:
        UnknownRobotError: a name that is no robot (no ``.urdf``/``.xml`` suffix, no ``erd:``).
        MotionToolError: a missing file, an unknown ``erd:`` robot, or a model Pinocchio
            cannot read.
    """
    if is_builtin(spec):
        return builtin(spec)
    if spec.startswith("erd:"):
        return erd(spec[len("erd:") :])
    suffix = Path(spec).suffix.lower()
    if suffix in (".urdf", ".xml"):
        path = Path(spec)
        if not path.is_file():
            raise MotionToolError(f"robot model file '{spec}' not found")
        fmt: Literal["mjcf", "urdf"] = "urdf" if suffix == ".urdf" else "mjcf"
        return from_pinocchio(path.stem, path, fmt, floating_base=None)
    raise UnknownRobotError(spec)


DETECT_MIN_SHARE = 0.5
"""Share of a file's (distinct) joint names a built-in robot must have to be picked by
:func:`detect_robot`: at least half, so one misspelt name (``RElbowRol``) does not lose the robot
checks, while a file of another robot's joints is not forced onto a robot it does not fit."""


class Ranking(NamedTuple):
    """How the built-in robots fit a motion's joints (:func:`rank_robots`).

    Attributes:
        joints: the joint names, in column order (a name given twice appears twice).
        best: the built-in robot with the most of the distinct names (the first of robots with
            the same motors: ``nao`` before ``nao-v5``); None if no robot has any.
        missing: indices in ``joints`` of the names ``best`` lacks (all of them without one).
        covered: how many distinct names ``best`` has.
        tied: robots with other motors that have as many distinct names as ``best``.
    """

    joints: tuple[str, ...]
    best: str | None
    missing: tuple[int, ...]
    covered: int
    tied: tuple[str, ...]

    @property
    def distinct(self) -> int:
        """How many distinct names ``joints`` holds."""
        return len(set(self.joints))

    @property
    def fits(self) -> bool:
        """Whether ``best`` is the robot: it has at least :data:`DETECT_MIN_SHARE` of the
        distinct names and no robot with other motors has as many."""
        return (
            self.best is not None
            and not self.tied
            and self.covered >= DETECT_MIN_SHARE * self.distinct
        )


def rank_robots(joint_names: Sequence[str]) -> Ranking:
    """How well each built-in robot fits ``joint_names``: the one rule :func:`detect_robot`
    picks by and :class:`NoRobotDetectedError` explains."""
    joints = tuple(joint_names)
    wanted = set(joints)
    best: str | None = None
    best_motors: frozenset[str] = frozenset()
    covered = 0
    tied: list[str] = []
    for robot in BUILTIN_ROBOTS:
        motors = _motors(robot)
        count = len(wanted & motors)
        if count > covered:
            best, best_motors, covered, tied = robot.name, motors, count, []
        elif count == covered and count and motors != best_motors:
            tied.append(robot.name)
    missing = tuple(j for j, joint in enumerate(joints) if joint not in best_motors)
    return Ranking(joints, best, missing, covered, tuple(tied))


def _motors(robot: BuiltinRobot) -> frozenset[str]:
    """The motors of a built-in robot: its model's. An overrides file (``nao-v5``'s) changes
    limits and rules, never the motors, so ranking the robots reads no overrides file and
    builds no spec of a robot it does not pick (:func:`builtin` does that for the one picked)."""
    return frozenset(parse_mjcf_table(models_dir() / robot.model).joint_names)


def detect_robot(joint_names: Sequence[str]) -> str | None:
    """The built-in robot whose motors include the most of ``joint_names``.

    A robot is picked when it has at least :data:`DETECT_MIN_SHARE` of the distinct names (the
    names it lacks are reported by the checks: MT301, with a did-you-mean). Of robots with the
    same motors, the first is preferred (``nao`` over ``nao-v5``). None if no robot reaches the
    share, if two robots with different motors tie (the file does not say which it is for), or
    if ``joint_names`` is empty (:func:`rank_robots`).
    """
    ranking = rank_robots(joint_names)
    return ranking.best if ranking.fits else None


class RobotError(MotionToolError):
    """No robot could be chosen; the message says why and what to choose from."""


class UnknownRobotError(RobotError):
    """A robot name that is no built-in robot, keyword, model file or ``erd:`` robot.

    Attributes:
        requested: the name as given.
        choices: the names accepted besides a model path and ``erd:<name>``: the keywords the
            caller accepts (``auto``, ``none``), then the built-in robots.
        suggestion: the choice closest to ``requested`` (a did-you-mean), or None.
    """

    def __init__(self, requested: str, keywords: Sequence[str] = ()) -> None:
        self.requested = requested
        self.choices = (*keywords, *builtin_robots())
        close = difflib.get_close_matches(requested, self.choices, n=1)
        self.suggestion = close[0] if close else None
        hint = f"did you mean '{self.suggestion}'? " if self.suggestion else ""
        super().__init__(f"unknown robot '{requested}'; {hint}choose {robot_choices(*keywords)}")


class NoRobotDetectedError(RobotError):
    """``auto``, and no built-in robot fits the joints (:func:`detect_robot` finds none).

    Attributes:
        joint_names: the joints a robot was sought for, in column order.
        best: the built-in robot that has the most of them (None: none has any).
        covered: how many of the distinct names ``best`` has.
        missing: indices in ``joint_names`` of the joints ``best`` lacks (all of them when
            ``best`` is None).
        tied: robots with other motors that have as many of the joints as ``best``.
        suggestion: ``best``'s motor closest to the first joint it lacks (a did-you-mean).
        detail: why, in words: ``no built-in robot has half of its joints or more: nao has 1
            of 3, not 'HeadYw', 'Tail' (did you mean 'HeadYaw'?)``.
        reason: the message without its remedy (``no robot fits the motion: <detail>``), for a
            caller that says how its user names a robot.
    """

    def __init__(self, joint_names: Sequence[str]) -> None:
        ranking = rank_robots(joint_names)
        self.joint_names = ranking.joints
        self.best = ranking.best
        self.missing = ranking.missing
        self.covered = ranking.covered
        self.tied = ranking.tied
        self.suggestion: str | None = None
        self.detail = self._detail(ranking)
        self.reason = f"no robot fits the motion: {self.detail}"
        super().__init__(f"{self.reason}; name the robot explicitly ({robot_choices()})")

    def _detail(self, ranking: Ranking) -> str:
        joints, count = ranking.joints, ranking.distinct
        if ranking.best is None:
            return f"no built-in robot ({', '.join(builtin_robots())}) has any of its joints"
        if ranking.tied:
            return (
                f"{' and '.join([ranking.best, *ranking.tied])} have {ranking.covered} of its"
                f" {count} joints each, so the joints do not say which robot it is for"
            )
        first = joints[ranking.missing[0]]
        close = difflib.get_close_matches(first, builtin(ranking.best).joint_names, n=1)
        self.suggestion = close[0] if close else None
        lacked = ", ".join(f"'{fmt_name(joints[j])}'" for j in ranking.missing[:3])
        more = f" and {len(ranking.missing) - 3} more" if len(ranking.missing) > 3 else ""
        guess = f" (did you mean '{self.suggestion}'?)" if self.suggestion else ""
        return (
            f"no built-in robot has half of its joints or more: {ranking.best} has "
            f"{ranking.covered} of {count}, not {lacked}{more}{guess}"
        )


def resolve_robot(requested: str, joint_names: Iterable[str] = ()) -> RobotSpec:
    """The robot named ``requested``, for joints ``joint_names``, where a robot is needed.

    Args:
        requested: :data:`AUTO` (the built-in robot :func:`detect_robot` picks for
            ``joint_names``), or what :func:`load_robot` takes.
        joint_names: the motion's joint names (header order); for several motions, the joints
            of all of them (a name given twice counts once). Used by :data:`AUTO` only.

    Raises:
        NoRobotDetectedError: :data:`AUTO`, and no built-in robot fits ``joint_names``.
        UnknownRobotError: a name that is no robot (its choices include :data:`AUTO`).
        MotionToolError: a model file that is missing or that Pinocchio cannot read.
    """
    if requested == AUTO:
        names = list(dict.fromkeys(joint_names))
        found = detect_robot(names)
        if found is None:
            raise NoRobotDetectedError(names)
        return builtin(found)
    return _load(requested, (AUTO,))


def pick_robot(requested: str, joint_names: Sequence[str] = ()) -> RobotSpec | None:
    """:func:`resolve_robot` where a robot is optional: :data:`NONE` gives None, and so does
    :data:`AUTO` when no built-in robot fits ``joint_names``.

    Raises:
        UnknownRobotError: a name that is no robot (its choices include :data:`AUTO` and
            :data:`NONE`).
        MotionToolError: a model file that is missing or that Pinocchio cannot read.
    """
    if requested == NONE:
        return None
    if requested == AUTO:
        found = detect_robot(joint_names)
        return None if found is None else builtin(found)
    return _load(requested, (AUTO, NONE))


def _load(requested: str, keywords: tuple[str, ...]) -> RobotSpec:
    """:func:`load_robot`, its unknown-robot error naming ``keywords`` too."""
    try:
        return load_robot(requested)
    except UnknownRobotError:
        raise UnknownRobotError(requested, keywords) from None
