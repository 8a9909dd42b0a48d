"""Findings made on demand (motiontool.motionfmt.findings): in file order, the same as a stable
sort of them all, made again at each reading, and made only as far as a report has read."""

from __future__ import annotations

from typing import Any

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from motiontool.kinematics.checks.limits import Limits
from motiontool.kinematics.robots import load_robot
from motiontool.motionfmt.diagnostics import Diagnostic, Severity
from motiontool.motionfmt.findings import Findings, in_order
from motiontool.motionfmt.reader import read_bytes
from motiontool.motionfmt.validate import validate_bytes

_CODES = ("MT302", "MT303", "MT307")


def _finding(line: int, column: int, code: str, tag: int) -> Diagnostic:
    severity = Severity.ERROR if code == "MT302" else Severity.WARNING
    return Diagnostic(code, severity, "a.motion", line, column, f"finding {tag}")


_places = st.lists(
    st.tuples(st.integers(1, 6), st.integers(1, 4), st.sampled_from(_CODES)), max_size=30
)


@given(st.lists(_places, min_size=1, max_size=4))
def test_merged_parts_read_as_a_stable_sort_of_them_all(parts: list[list[tuple]]) -> None:
    tag = iter(range(10**6))
    lists = [[_finding(*place, next(tag)) for place in part] for part in parts]
    merged = Findings.merge(lists)
    expected = sorted((d for part in lists for d in part), key=Diagnostic.sort_key)
    assert [d.message for d in merged] == [d.message for d in expected]
    assert [d.message for d in merged] == [d.message for d in expected]  # again, the same
    assert merged.count(Severity.ERROR) == sum(d.severity is Severity.ERROR for d in expected)
    assert len(merged) == len(expected) and merged == expected


def test_in_order_makes_each_finding_when_it_is_read() -> None:
    poses = np.array([3, 1, 2, 1])
    columns = np.array([0, 5, -1, 2])
    made: list[int] = []

    def make(i: int) -> Diagnostic:
        made.append(i)
        return _finding(int(poses[i]) + 2, int(columns[i]) + 2, "MT302", i)

    found = in_order(poses, columns, make)
    assert made == []  # nothing is made before it is read
    reading = iter(found)
    assert next(reading).message == "finding 3"  # pose 1, column 2
    assert made == [3]
    assert [d.message for d in reading] == ["finding 1", "finding 2", "finding 0"]
    assert made == [3, 1, 2, 0]
    assert found.count(Severity.ERROR) == 4 and made == [3, 1, 2, 0]  # counted in that pass


def _random_file(poses: int) -> bytes:
    rng = np.random.default_rng(1)
    joints = ["HeadYaw", "HeadPitch", "LShoulderRoll", "RShoulderRoll"]
    lines = ["#WEBOTS_MOTION,V1.0," + ",".join(joints)]
    for p in range(poses):
        cells = ",".join(f"{v:.4f}" for v in rng.uniform(-2, 2, len(joints)))
        lines.append(f"00:{p // 25:02d}:{p % 25 * 40:03d},Pose{p + 1},{cells}")
    return ("\n".join(lines) + "\n").encode()


class _Counted(Limits):
    """The Nao's limit check, counting the per-pose findings it makes."""

    def __init__(self) -> None:
        super().__init__(load_robot("nao"))
        self.made = 0

    def _beyond(self, *args: Any) -> Diagnostic:
        self.made += 1
        return super()._beyond(*args)


def test_a_report_reads_the_first_finding_of_a_large_file_without_making_the_others() -> None:
    """The limit check keeps its findings as arrays: reading the first one makes one."""
    data = _random_file(1_000)
    limits = _Counted()
    report = validate_bytes(data, "random.motion", checks=[limits], group=False)
    assert limits.made == 0
    first = next(iter(report.diagnostics))
    assert first.code == "MT302" and limits.made == 1
    total = len(report.diagnostics)
    assert total > 500 and limits.made == 1 + total  # one pass counted them, a finding each


def test_a_subject_that_comes_and_goes_in_many_runs_is_one_finding() -> None:
    """Random values cross the limits hundreds of times: grouped, each joint and side is one
    finding (more than MAX_RUNS runs), which says how many poses and runs."""
    from motiontool.motionfmt.grouping import MAX_RUNS, group_findings

    result = read_bytes(_random_file(1_000), "random.motion")
    limits = Limits(load_robot("nao"))
    grouped = list(limits.grouped(result))
    assert len(grouped) <= 8  # 4 joints, 2 sides
    per_pose = list(limits(result))
    for d in grouped:
        assert d.run is not None and d.run.runs > MAX_RUNS
        assert f"in {d.run.runs:,} runs" in d.message
    assert sum(d.count for d in grouped) == len(per_pose)
    assert sorted(group_findings(per_pose), key=Diagnostic.sort_key) == grouped


def test_findings_made_on_demand_are_those_made_at_once() -> None:
    """Per pose and grouped, the limit check's findings are the ones its per-pose findings
    give, sorted (what validate reported when it held them all)."""
    result = read_bytes(_random_file(300), "random.motion")
    limits = Limits(load_robot("nao"))
    per_pose = list(limits(result))
    assert per_pose == sorted(per_pose, key=Diagnostic.sort_key) and len(per_pose) > 300
    from motiontool.motionfmt.grouping import group_findings

    grouped = sorted(group_findings(per_pose), key=Diagnostic.sort_key)
    assert list(limits.grouped(result)) == grouped


def test_the_text_and_json_reports_write_findings_as_they_are_made() -> None:
    from motiontool.cli.validate_report import render, render_pieces
    from motiontool.motionfmt.validate import ValidationReport

    data = _random_file(1_000)
    limits = _Counted()
    report = ValidationReport(files=[validate_bytes(data, "r.motion", checks=[limits])])
    text = render_pieces(report, "text")
    assert next(text).startswith("r.motion:2:") and limits.made == 1
    whole = "".join(text)
    assert limits.made > 1000 and whole.endswith("\n") and "error" in whole.splitlines()[-1]
    assert limits.made == 1907  # the text report's pass counted them: the summary needs no other
    limits.made = 0
    report = ValidationReport(files=[validate_bytes(data, "r.motion", checks=[limits])])
    pieces = render_pieces(report, "json")
    head = next(pieces)  # the files come first: nothing is made before them
    assert head.rstrip().endswith('"files":') and limits.made == 0
    next(pieces), next(pieces), next(pieces)
    assert 1 <= limits.made <= 2  # the first finding written, the next one made
    tail = "".join(pieces)
    assert limits.made == 1907  # one pass: the summary after the files needs no other
    assert '"errors": 1907' in tail and render(report, "json").startswith(head)
