"""Grouped findings (motionfmt/grouping.py): consecutive per-pose findings of one code and
subject become one, checked against a plain oracle on generated findings."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from motiontool.motionfmt.diagnostics import Diagnostic, PoseFinding, Severity
from motiontool.motionfmt.grouping import MAX_RUNS, group_findings

SUBJECTS = ("HeadYaw above its upper limit 2 rad", "HeadYaw below its lower limit -2 rad")


def finding(pose: int, code: str = "MT302", subject: str = SUBJECTS[0], excess: float = 0.1):
    """A per-pose finding at pose ``pose`` on line ``pose + 2`` (the header is line 1)."""
    return Diagnostic(
        code=code,
        severity=Severity.ERROR if code == "MT302" else Severity.WARNING,
        path="a.motion",
        line=pose + 2,
        column=11,
        message=f"{subject}: per-pose message at pose {pose}",
        hint="per-pose hint",
        joint="HeadYaw",
        time_ms=40 * pose,
        pose=PoseFinding(pose, subject, 2.0 + excess, "rad", excess),
    )


def test_a_run_of_consecutive_poses_is_one_finding_at_its_first() -> None:
    found = [finding(p, excess=0.5 if p == 6 else 0.1) for p in (3, 4, 5, 6, 7)]
    (group,) = group_findings(found)
    assert (group.line, group.column, group.time_ms, group.joint) == (5, 11, 120, "HeadYaw")
    assert group.message == (
        "HeadYaw above its upper limit 2 rad on 5 poses, lines 5\u20139, worst 2.5 rad at line 8"
    )
    assert group.run is not None and group.count == 5 and group.run.end_line == 9
    assert (group.run.worst.value, group.run.worst.line, group.run.worst.time_ms) == (2.5, 8, 240)
    assert group.hint == "per-pose hint"  # the check gave no hint of the group's own


def test_a_gap_another_subject_or_code_ends_a_run_a_finding_alone_is_kept() -> None:
    found = [
        finding(1),
        finding(2),
        finding(2, "MT303"),
        finding(3, subject=SUBJECTS[1]),
        finding(5),
        Diagnostic("MT203", Severity.WARNING, "a.motion", 4, 3, "no pose: never grouped"),
    ]
    out = sorted(group_findings(found), key=Diagnostic.sort_key)
    assert [(d.code, d.line, d.count) for d in out] == [
        ("MT302", 3, 2),
        ("MT203", 4, 1),
        ("MT303", 4, 1),
        ("MT302", 5, 1),
        ("MT302", 7, 1),
    ]
    assert out[2] is found[2] and out[3] is found[3] and out[4] is found[4]


def test_the_identity_names_the_subject_and_first_time_not_the_lines() -> None:
    (group,) = group_findings([finding(3), finding(4)])
    assert group.identity == "HeadYaw above its upper limit 2 rad from 120 ms"
    assert finding(3).identity == finding(3).message


def test_grouping_twice_changes_nothing() -> None:
    once = group_findings([finding(p) for p in range(4)])
    assert group_findings(once) == once


@st.composite
def per_pose_findings(draw: st.DrawFn) -> list[Diagnostic]:
    """Findings of two codes and two subjects at random poses, in pose order."""
    cells = draw(
        st.sets(
            st.tuples(
                st.integers(0, 60), st.sampled_from(("MT302", "MT304")), st.sampled_from(SUBJECTS)
            )
        )
    )
    excess = draw(st.lists(st.floats(0.001, 5), min_size=len(cells), max_size=len(cells)))
    return [
        finding(p, code, subject, e)
        for (p, code, subject), e in zip(sorted(cells), excess, strict=True)
    ]


@given(per_pose_findings())
def test_groups_are_the_maximal_runs_of_a_plain_oracle(found: list[Diagnostic]) -> None:
    out = group_findings(found)
    assert sum(d.count for d in out) == len(found)
    expected = []  # the oracle: per code and subject, maximal runs of consecutive poses
    for key in {(d.code, d.pose.subject) for d in found if d.pose}:
        members = [d for d in found if d.pose and (d.code, d.pose.subject) == key]
        poses = sorted(d.pose.pose for d in members)
        runs, start = [], poses[0]
        for a, b in zip(poses, [*poses[1:], None], strict=True):
            if b != a + 1:
                runs.append([d for d in members if start <= d.pose.pose <= a])
                start = b
        if len(runs) > MAX_RUNS:  # one finding for them all
            runs = [[d for run in runs for d in run]]
        for run in runs:
            worst = max(run, key=lambda d: d.pose.excess)  # the first of equal ones
            expected.append((key[0], run[0].line, run[-1].line, len(run), worst.line))
    got = [
        (
            d.code,
            d.line,
            d.run.end_line if d.run else d.line,
            d.count,
            d.run.worst.line if d.run else d.line,
        )
        for d in out
    ]
    assert sorted(got) == sorted(expected)


def test_more_than_max_runs_of_a_subject_are_one_finding_that_says_how_many() -> None:
    poses = [2 * k for k in range(MAX_RUNS + 1)] + [2 * MAX_RUNS + 1]  # 11 runs, the last of 2
    found = [finding(p, excess=0.7 if p == 6 else 0.1) for p in poses]
    (group,) = group_findings(found)
    assert group.run is not None and (group.count, group.run.runs) == (len(poses), MAX_RUNS + 1)
    assert group.message == (
        f"HeadYaw above its upper limit 2 rad on {len(poses)} poses in {MAX_RUNS + 1} runs, "
        f"lines 2\u2013{2 * MAX_RUNS + 3}, worst 2.7 rad at line 8"
    )
    assert len(group_findings(found[:-2])) == MAX_RUNS  # ten runs: each its own finding
