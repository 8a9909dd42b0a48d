"""Which robot checks run, and against which robot: :func:`robot_checks` for one robot,
:class:`RobotChecks` for a ``validate`` run that picks the robot per file."""

from __future__ import annotations

import itertools
import os
from collections.abc import Callable, Iterable, Sequence

from motiontool.errors import MissingExtraError, MotionToolError
from motiontool.extras import install_hint
from motiontool.kinematics.checks._table import Groupable, header_diagnostic, settle_tables
from motiontool.kinematics.checks.findings_cache import (
    MAX_BYTES,
    MAX_FINDINGS,
    FindingsCache,
    findings_key,
)
from motiontool.kinematics.checks.registry import (
    ALWAYS,
    CHECK_REGISTRY,
    CHECKS,
    DEFAULT_CHECKS,
    DEFAULT_PENETRATION_TOLERANCE_MM,
    CheckOptions,
    parse_checks,
)
from motiontool.kinematics.checks.unmirrored import UnmirroredCopy
from motiontool.kinematics.checks.wording import PLAIN_WORDING, Wording
from motiontool.kinematics.robots import (
    AUTO,
    NONE,
    NoRobotDetectedError,
    RobotSpec,
    pick_robot,
    robot_choices,
)
from motiontool.motionfmt.diagnostics import CHECK_SKIPPED, NO_ROBOT, Diagnostic, Severity
from motiontool.motionfmt.findings import Findings
from motiontool.motionfmt.motion_checks import step_findings
from motiontool.motionfmt.reader import ReadResult
from motiontool.motionfmt.validate import run_check

__all__ = [
    "CHECKS",
    "DEFAULT_CHECKS",
    "CheckUnavailableError",
    "RobotChecks",
    "parse_checks",
    "robot_checks",
]

_Check = Callable[[ReadResult], Sequence[Diagnostic]]


class CheckUnavailableError(MotionToolError):
    """A check was asked for that the robot cannot have (``balance`` for a robot without feet).

    Attributes:
        check: the check's name (``balance``).
        robot: the robot's name.
    """

    def __init__(self, check: str, robot: str, why: str) -> None:
        self.check = check
        self.robot = robot
        super().__init__(why)


def robot_checks(
    spec: RobotSpec,
    checks: Iterable[str] = DEFAULT_CHECKS,
    *,
    timestep_ms: int | None = None,
    penetration_tolerance_mm: float = DEFAULT_PENETRATION_TOLERANCE_MM,
    wording: Wording = PLAIN_WORDING,
) -> list[_Check]:
    """The checks of ``spec`` for :func:`motiontool.motionfmt.validate_paths`.

    Args:
        spec: the robot.
        checks: names from :data:`CHECKS`; the unknown-joint check (MT301) and the
            unmirrored-copy note (MT309) always run, and the real robot's rules (``nao-v5``)
            run with ``limits``.
        timestep_ms: controller time step (ms) of the sampled command stream checked by
            ``velocity``; the robot's ``default_timestep_ms`` if None.
        penetration_tolerance_mm: see :data:`DEFAULT_PENETRATION_TOLERANCE_MM` (mm, >= 0).
        wording: the front end's words for the hints' remedies (naming a robot, leaving a
            code out, mirroring a file); plain words by default.

    Raises:
        MotionToolError: an unknown check name or a negative tolerance.
        CheckUnavailableError: a check that needs feet (``balance``) for a robot without.
    """
    names = parse_checks(list(checks))
    if not penetration_tolerance_mm >= 0:
        raise MotionToolError(
            f"the collision tolerance must be a depth >= 0 mm, got {penetration_tolerance_mm}"
        )
    footed = [n for n in names if n in _FOOTED and not spec.feet]
    if footed:
        raise CheckUnavailableError(
            footed[0],
            spec.name,
            f"robot {spec.name} has no feet: the {footed[0]} check needs a humanoid model with "
            "sole geometries (nao, nao-v5)",
        )
    options = CheckOptions(timestep_ms, penetration_tolerance_mm, wording)
    chosen = [c for c in CHECK_REGISTRY if c.name in names]
    return [c.make(spec, options) for c in (*ALWAYS, *chosen)]


class RobotChecks(Groupable):
    """The robot checks of one ``validate`` run, as one :data:`Check`.

    ``robot='auto'`` picks, per file, the built-in robot that has the most of the header's
    joints, at least half of them (:func:`~motiontool.kinematics.robots.pick_robot`; the others
    get MT301 with a did-you-mean, and the joints it has are checked); a file no built-in robot
    fits is checked at syntax level only and gets an MT901 note whose hint says how to name a
    robot (in the front end's ``wording``) and the robots to choose from. ``'none'`` checks
    nothing. Any other ``robot`` is loaded once (:func:`~motiontool.kinematics.load_robot`)
    and checks every file. Robots and their models are loaded once per process. ``wording``:
    see :func:`robot_checks`.

    A check whose library is not installed (collision and balance need Pinocchio,
    ``motiontool[kinematics]``) is skipped for the rest of the run, with one MT902 note about
    the run (:attr:`notes`, not pinned to a file); the others still run. With
    ``skip_missing=False`` (the checks were asked for by name) it raises
    :class:`~motiontool.errors.MissingExtraError` instead.

    With a ``cache`` (:class:`~motiontool.kinematics.checks.findings_cache.FindingsCache`), a
    small file checked before with the same robot, checks and code gets its findings from it.

    Without ``timestep_ms``, each file is checked at its robot's controller step (the Nao's
    20 ms): the velocity check's command stream, and the pose times the reader checks at a step
    it is given (MT209 off the step, MT115 a clock that wraps:
    :func:`~motiontool.motionfmt.motion_checks.step_findings`), so read the files without one.

    Attributes:
        used: for every file checked, the robot it was checked against (None: skipped).
        skipped: the checks skipped for a missing library, by name, with the error that says
            which extra to install.
        cache: the findings cache, or None (every file is checked).
    """

    def __init__(
        self,
        robot: str = "auto",
        checks: Iterable[str] = DEFAULT_CHECKS,
        *,
        timestep_ms: int | None = None,
        penetration_tolerance_mm: float = DEFAULT_PENETRATION_TOLERANCE_MM,
        wording: Wording = PLAIN_WORDING,
        skip_missing: bool = True,
        cache: FindingsCache | None = None,
    ) -> None:
        self.robot = robot
        self.cache = cache
        self.skip_missing = skip_missing
        self.wording = wording
        self.on_check: Callable[[str], None] | None = None
        """Told which check runs on which file (``big.motion: collision``), for a progress
        display; None: nothing is told."""
        self.checks = parse_checks(list(checks))
        self.used: dict[str, RobotSpec | None] = {}
        self.skipped: dict[str, MissingExtraError] = {}
        self.timestep_ms = timestep_ms
        self.penetration_tolerance_mm = penetration_tolerance_mm
        self._by_robot: dict[str, list[_Check]] = {}
        self._specs: dict[str, RobotSpec] = {}
        spec = None if robot == AUTO else pick_robot(robot)  # UnknownRobotError: exit early
        if spec is not None:
            self._checks_for(spec, strict=True)

    def _checks_for(self, spec: RobotSpec, *, strict: bool = False) -> list[_Check]:
        if spec.name not in self._by_robot:
            names = self.checks
            if not strict and not spec.feet:
                names = tuple(c for c in names if c not in _FOOTED)
            self._specs[spec.name] = spec
            self._by_robot[spec.name] = robot_checks(
                spec,
                names,
                timestep_ms=self.timestep_ms,
                penetration_tolerance_mm=self.penetration_tolerance_mm,
                wording=self.wording,
            )
        return self._by_robot[spec.name]

    def spec_for(self, result: ReadResult) -> RobotSpec | None:
        """The robot ``result`` is checked against, or None (auto, no built-in robot fits)."""
        if self.robot != AUTO:
            return next(iter(self._specs.values()), None)
        return pick_robot(AUTO, result.joints)

    def note(self, result: ReadResult) -> RobotSpec | None:
        """Record in :attr:`used` the robot ``result`` is checked against (or None), and return
        it: what checking the file records, known from its header without checking it."""
        spec = self.spec_for(result)
        self.used[result.path] = spec
        return spec

    def _check(self, result: ReadResult, *, group: bool) -> Findings:
        if self.robot == NONE:
            return Findings.of([])
        spec = self.note(result)
        if spec is None:
            return Findings.of([_skipped(result, self.wording)])
        checks = self._checks_for(spec)
        parts = [self._run(c, result, group=group) for c in checks if isinstance(c, _LIVE)]
        if self.timestep_ms is None:  # the robot's step, as the reader checks one given
            parts.append(step_findings(result, spec.default_timestep_ms))
        own = [c for c in checks if not isinstance(c, _LIVE)]
        parts.append(self._of_the_file(spec, own, result, group=group))
        settle_tables()
        for name in () if spec.feet else [c for c in self.checks if c in _FOOTED]:
            message = f"{name} check skipped: robot {spec.name} has no feet"
            parts.append([Diagnostic(NO_ROBOT, Severity.INFO, result.path, 1, 1, message)])
        return Findings.merge(parts)

    def _of_the_file(
        self, spec: RobotSpec, checks: list[_Check], result: ReadResult, *, group: bool
    ) -> Sequence[Diagnostic]:
        """The findings of ``checks`` (which read no other file) on ``result``: from
        :attr:`cache` where it holds them, else found (and stored where the file is small)."""
        data = result.data
        cache = self.cache if len(data) <= MAX_BYTES else None
        if cache is None:
            return Findings.merge([self._run(c, result, group=group) for c in checks])
        options = (
            self.robot,
            repr(spec),
            repr(self.checks),
            repr(self.timestep_ms),
            repr(self.penetration_tolerance_mm),
            repr(group),
            repr(self.wording),
            repr(self.skip_missing),  # a check asked for by name raises where one skips
        )
        key = findings_key(options, os.path.abspath(result.path), data)
        stored = cache.load(key, result.path)
        if stored is not None:
            for name, exc in stored.skipped.items():  # the run's MT902 note, as if it ran
                self.skipped.setdefault(name, exc)
            return stored.findings
        found = Findings.merge([self._run(c, result, group=group) for c in checks])
        held = list(itertools.islice(found, MAX_FINDINGS + 1))
        if len(held) > MAX_FINDINGS:  # too many to hold: made again as the report reads them
            return found
        names = {_CHECK_NAMES.get(type(c)) for c in checks}
        cache.store(key, held, {n: e for n, e in self.skipped.items() if n in names}, result.path)
        return held

    def _run(self, check: _Check, result: ReadResult, *, group: bool) -> Sequence[Diagnostic]:
        """``check`` on ``result`` (with ``group``, grouped: by its ``grouped`` method where it
        has one); a default check that needs a missing extra is skipped from then on
        (:attr:`notes` says so once); one asked for by name raises."""
        name = _CHECK_NAMES.get(type(check))
        if name in self.skipped:
            return []
        if self.on_check is not None and name is not None:
            self.on_check(f"{result.path}: {name}")
        try:
            return run_check(check, result, group)
        except MissingExtraError as exc:
            if name is None or not self.skip_missing:
                raise
            self.skipped[name] = exc
            return []

    @property
    def notes(self) -> list[Diagnostic]:
        """The run's notes, about no file: one MT902 per check skipped for a missing library
        (``path`` empty, ``line`` and ``column`` 0)."""
        return [_skipped_for_extra(name, exc) for name, exc in self.skipped.items()]


_FOOTED = tuple(c.name for c in CHECK_REGISTRY if c.needs_feet)
"""The checks only a robot with feet can have (balance)."""

_LIVE = (UnmirroredCopy,)
"""The checks whose findings depend on files other than the one checked (MT309 reads its
siblings): run every time, never taken from :attr:`RobotChecks.cache`."""

_CHECK_NAMES: dict[type, str] = {c.kind: c.name for c in CHECK_REGISTRY if c.extra is not None}
"""The checks that need an extra (Pinocchio), by class: skipped with MT902 when it is missing."""


def _skipped_for_extra(name: str, exc: MissingExtraError) -> Diagnostic:
    """MT902, once a run and about no file: check ``name`` is skipped because its library is
    not installed."""
    return Diagnostic(
        code=CHECK_SKIPPED,
        severity=Severity.INFO,
        path="",
        line=0,
        column=0,
        message=f"{name} check skipped: {exc.library} is not installed; every file of this run "
        f"is checked without it",
        hint=install_hint(exc.extra),
    )


def _skipped(result: ReadResult, wording: Wording) -> Diagnostic:
    """MT901 for a file :func:`~motiontool.kinematics.detect_robot` finds no robot for: no
    built-in robot has half of its joints, or two robots with different motors have as many
    (:class:`~motiontool.kinematics.robots.NoRobotDetectedError` says which); the hint says
    how to name a robot and the robots to choose from."""
    joints = result.joints
    why = NoRobotDetectedError(joints)
    message = f"robot checks skipped: {why.detail}; checked at syntax level only"
    hint = f"{wording.name_robot()} ({robot_choices()})"
    if not joints:
        return Diagnostic(NO_ROBOT, Severity.INFO, result.path, 1, 1, message, hint)
    where = why.missing[0] if why.missing else 0
    return header_diagnostic(result, where, NO_ROBOT, Severity.INFO, message, hint)
