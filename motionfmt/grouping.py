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
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable

from motiontool.motionfmt.diagnostics import Diagnostic, PoseFinding, Run, Severity, Worst

__all__ = ["group_findings", "grouped_message", "run_finding"]


def grouped_message(pose: PoseFinding, count: int, lines: tuple[int, int], worst: Worst) -> str:
    """``SUBJECT on 3,412 poses, lines 5–3416, worst 2 rad at line 17``."""
    first, last = lines
    return (
        f"{pose.subject} on {count:,} {pose.noun}s, lines {first}\u2013{last}, "
        f"worst {worst.value:.6g} {worst.unit} at line {worst.line}"
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

    def finding(self) -> Diagnostic:
        """One finding for the group (the first one itself if it is alone)."""
        worst = self.worst
        w = Worst(
            self.worst_pose.value, self.worst_pose.unit, worst.line, worst.column, worst.time_ms
        )
        return run_finding(self.first, self.count, self.last.line, w, self.severity)


def run_finding(
    first: Diagnostic, count: int, last_line: int, worst: Worst, severity: Severity | None = None
) -> Diagnostic:
    """The finding that :func:`group_findings` makes of ``count`` consecutive findings of
    ``first``'s code and subject, from ``first`` (which has :attr:`~Diagnostic.pose`) to one on
    ``last_line``, the worst of them ``worst``; ``severity``: the worst of their severities
    (None: ``first``'s). ``first`` itself when ``count`` is 1.

    A check that finds its problems as arrays builds its groups with this, without a
    finding per pose (:meth:`motiontool.kinematics.checks.limits.Limits.grouped`)."""
    pose = first.pose
    if count == 1:
        return first
    if pose is None:
        raise ValueError("run_finding: the first finding has no PoseFinding")
    when = "" if first.time_ms is None else f" from {first.time_ms} ms"
    run = Run(count, last_line, worst, pose.noun, f"{pose.subject}{when}")
    return dataclasses.replace(
        first,
        severity=first.severity if severity is None else severity,
        message=grouped_message(pose, count, (first.line, last_line), worst),
        hint=pose.hint if pose.hint is not None else first.hint,
        pose=None,
        run=run,
    )


def group_findings(diagnostics: Iterable[Diagnostic]) -> list[Diagnostic]:
    """``diagnostics`` with each run of consecutive per-pose findings of one code and subject
    made one finding (see the module's docstring); the others as they are.

    Each code and subject's findings must come in pose order (as a check reports them, or
    sorted by line); the result is not sorted. Only the groups being built are held besides
    the result: three findings each.
    """
    out: list[Diagnostic] = []
    open_: dict[tuple[str, str], _Open] = {}
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
            out.append(group.finding())
        open_[key] = _Open(d, pose)
    out.extend(group.finding() for group in open_.values())
    return out
