"""Grouped findings: the same finding at consecutive poses, reported once.

A robot check reports a problem at every pose where it is (a joint past its limit on 3,412
poses is 3,412 findings). ``validate`` groups them by default: consecutive findings of one code
with one subject (:attr:`~motiontool.motionfmt.diagnostics.PoseFinding.subject`: the joint and
what is wrong, ``RShoulderRoll above its upper limit 0.314159 rad``) become one finding at the
first one's place, whose message says how many poses, their lines and the worst value::

    RShoulderRoll above its upper limit 0.314159 rad on 3,412 poses, lines 5–3416,
    worst 2 rad at line 17

Consecutive means at poses next to each other: a pose where the finding is not (the joint within
its limits there, or ``*``) ends a group. A finding alone stays as it is, with its own message.

A subject that comes and goes more than :data:`MAX_RUNS` times in one file (a joint that
dithers across its limit, noise in captured data, random values) is one finding for the whole
file, which says in how many runs::

    RKneePitch below its lower limit -0.0923279 rad on 4,211 poses in 1,380 runs,
    lines 5–9001, worst -0.0935 rad at line 77

(``--no-group`` lists every pose.)
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable

from motiontool.motionfmt.diagnostics import Diagnostic, PoseFinding, Run, Severity, Worst

__all__ = ["MAX_RUNS", "group_findings", "grouped_message", "run_finding"]

MAX_RUNS = 10
"""Most runs of one code and subject reported one by one in a file; more make one finding."""


def grouped_message(
    pose: PoseFinding,
    count: int,
    lines: tuple[int, int],
    worst: Worst,
    runs: int = 1,
    amount: str | None = None,
) -> str:
    """``SUBJECT on 3,412 poses, lines 5–3416, worst 2 rad at line 17`` (``on 3,412 poses in
    12 runs`` for ``runs`` of them), then the worst finding's ``amount`` in brackets (see
    :attr:`~motiontool.motionfmt.diagnostics.PoseFinding.amount`)."""
    first, last = lines
    within = f" in {runs:,} runs" if runs > 1 else ""
    said = f" ({amount})" if amount else ""
    return (
        f"{pose.subject} on {count:,} {pose.noun}s{within}, lines {first}\u2013{last}, "
        f"worst {worst.value:.6g} {worst.unit} at line {worst.line}{said}"
    )


class _Open:
    """A group being built: its first, last and worst findings and how many."""

    __slots__ = (
        "count",
        "first",
        "last",
        "last_index",
        "severity",
        "subject",
        "worst",
        "worst_pose",
    )

    def __init__(self, d: Diagnostic, pose: PoseFinding) -> None:
        self.first = self.last = self.worst = d
        self.subject = self.worst_pose = pose
        self.last_index = pose.pose
        self.count = 1
        self.severity = d.severity

    def add(self, d: Diagnostic, pose: PoseFinding) -> None:
        if pose.excess > self.worst_pose.excess:
            self.worst, self.worst_pose = d, pose
        self.last, self.last_index = d, pose.pose
        self.count += 1
        self.severity = max(self.severity, d.severity)

    def merge(self, later: _Open) -> None:
        """Take in the group ``later`` (further in the file): one finding for both."""
        if later.worst_pose.excess > self.worst_pose.excess:
            self.worst, self.worst_pose = later.worst, later.worst_pose
        self.last, self.last_index = later.last, later.last_index
        self.count += later.count
        self.severity = max(self.severity, later.severity)

    def finding(self, runs: int = 1) -> Diagnostic:
        """One finding for the group (the first one itself if it is alone), of ``runs``
        groups merged."""
        worst = self.worst
        w = Worst(
            self.worst_pose.value, self.worst_pose.unit, worst.line, worst.column, worst.time_ms
        )
        return run_finding(
            self.first,
            self.count,
            self.last.line,
            w,
            self.severity,
            runs,
            amount=self.worst_pose.amount,
        )


def run_finding(
    first: Diagnostic,
    count: int,
    last_line: int,
    worst: Worst,
    severity: Severity | None = None,
    runs: int = 1,
    amount: str | None = None,
) -> Diagnostic:
    """The finding that :func:`group_findings` makes of ``count`` consecutive findings of
    ``first``'s code and subject (in ``runs`` runs: see :data:`MAX_RUNS`), from ``first``
    (which has :attr:`~Diagnostic.pose`) to one on ``last_line``, the worst of them ``worst``;
    ``severity``: the worst of their severities (None: ``first``'s); ``amount``: the worst's
    :attr:`~motiontool.motionfmt.diagnostics.PoseFinding.amount`. ``first`` itself when
    ``count`` is 1.

    A check that finds its problems as arrays builds its groups with this, without a
    finding per pose (:meth:`motiontool.kinematics.checks.limits.Limits.grouped`)."""
    pose = first.pose
    if count == 1:
        return first
    if pose is None:
        raise ValueError("run_finding: the first finding has no PoseFinding")
    when = "" if first.time_ms is None else f" from {first.time_ms} ms"
    run = Run(count, last_line, worst, pose.noun, f"{pose.subject}{when}", runs)
    return dataclasses.replace(
        first,
        severity=first.severity if severity is None else severity,
        message=grouped_message(pose, count, (first.line, last_line), worst, runs, amount),
        hint=pose.hint if pose.hint is not None else first.hint,
        pose=None,
        run=run,
    )


def group_findings(diagnostics: Iterable[Diagnostic]) -> list[Diagnostic]:
    """``diagnostics`` with each run of consecutive per-pose findings of one code and subject
    made one finding, and the runs of a subject with more than :data:`MAX_RUNS` of them one
    finding together (see the module's docstring); the others as they are.

    Each code and subject's findings must come in pose order (as a check reports them, or
    sorted by line); the result is not sorted. Besides the result, the groups (three findings
    each) are held until the end.
    """
    out: list[Diagnostic] = []
    open_: dict[tuple[str, str], _Open] = {}
    closed: dict[tuple[str, str], list[_Open]] = {}
    for d in diagnostics:
        pose = d.pose
        if pose is None:
            out.append(d)
            continue
        key = (d.code, pose.subject)
        group = open_.get(key)
        if group is not None and pose.pose == group.last_index + 1:
            group.add(d, pose)
            continue
        if group is not None:
            closed.setdefault(key, []).append(group)
        open_[key] = _Open(d, pose)
    for key, group in open_.items():
        closed.setdefault(key, []).append(group)
    for groups in closed.values():
        if len(groups) <= MAX_RUNS:
            out.extend(group.finding() for group in groups)
            continue
        whole = groups[0]
        for later in groups[1:]:
            whole.merge(later)
        out.append(whole.finding(runs=len(groups)))
    return out
