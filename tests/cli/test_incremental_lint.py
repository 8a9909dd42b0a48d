"""``motiontool server`` lints each version of a document from the last one (the reader goes on
from the edit, the robot checks kept): every version's findings and fixes are those of a fresh
lint of the same text, over random edits of a Nao motion."""

from __future__ import annotations

import random
from pathlib import Path
from typing import Any

import pytest
from conftest import calls_of
from edits import edit, motion

from motiontool.cli.config import Resolver
from motiontool.cli.lint_run import Overrides, lint_document
from motiontool.cli.validate import robot_checks
from motiontool.kinematics.checks import DEFAULT_PENETRATION_TOLERANCE_MM, RobotChecks
from motiontool.kinematics.robots import pick_robot
from motiontool.motionfmt.reread import Rereader
from motiontool.motionfmt.validate import FileReport


def _checks(*key: Any) -> RobotChecks:
    return robot_checks(*key, tolerance=DEFAULT_PENETRATION_TOLERANCE_MM, cache=None)


def _seen(report: FileReport) -> list[tuple[Any, ...]]:
    """What an editor gets of each finding: where, what, and its fixes."""
    return [
        (d.code, d.severity, d.line, d.column, d.end_column, d.message, d.hint, report.fix_of(d))
        for d in report.diagnostics
    ]


_NO_COMMAND = (b"*", b"nan", b"inf", b"-9999999.9")
"""Cells that are no command (or not a finite one): a file with one has its stream findings
found in full, not spliced (``_stream_steps.LastStream``)."""


def _commands_only(lines: list[bytes]) -> bool:
    return not any(c in _NO_COMMAND for line in lines[1:] for c in line.split(b",")[2:])


@pytest.mark.needs("kinematics")
@pytest.mark.parametrize(
    ("seed", "stars", "stream_limit"),
    [(0, 0.02, 1.0), (1, 0.02, 1.0), (2, 0.0, 1.0), (3, 0.0, 0.1)],
)
def test_every_version_lints_as_a_fresh_lint(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, seed: int, stars: float, stream_limit: float
) -> None:
    """With ``stars`` 0, the edits leave every cell a command: the velocity check's stream
    findings (MT304) are spliced from the last version's. Every step of such a stream too
    fast is on a segment MT303 reports (MT304 leaves it to it), so there is none to splice;
    ``stream_limit`` < 1 makes the stream's limit that share of the motor's maximum velocity,
    so that there are."""
    if stream_limit != 1.0:
        from motiontool.kinematics.checks.velocity import Velocity

        fast_steps = Velocity._fast_steps

        def slower(self: Velocity, times: Any, sent: Any, motor: Any, gaps: Any) -> Any:
            return fast_steps(self, times, sent, (motor[0] * stream_limit, *motor[1:]), gaps)

        monkeypatch.setattr(Velocity, "_fast_steps", slower)
    (tmp_path / "pyproject.toml").write_text('[tool.motiontool]\nrobot = "nao"\n')
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "walk.motion"
    rng = random.Random(seed)
    lines = motion(pick_robot("nao").joint_names[:20], 120, rng, stars=stars)
    kept: dict[tuple[Any, ...], RobotChecks] = {}
    reader = Rereader()
    stream_findings = 0

    def kept_checks(*key: Any) -> RobotChecks:
        return kept.setdefault(key, _checks(*key))

    for _version in range(40):
        data = b"\n".join(lines) + b"\n"
        got, _robot = lint_document(path, data, Resolver(), Overrides(), kept_checks, reader)
        want, _robot = lint_document(path, data, Resolver(), Overrides(), _checks)
        assert _seen(got) == _seen(want)
        stream_findings += sum(d.code == "MT304" for d in want.diagnostics)
        edited = edit(lines, rng)
        while not stars and not _commands_only(edited):  # another edit of the same version
            edited = edit(lines, rng)
        lines = edited
    assert reader.resumed > 10
    assert stream_findings or stream_limit == 1.0


@pytest.mark.needs("kinematics")
def test_a_value_edit_scans_only_the_configurations_it_changed(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """After a one-value edit, the collision check scans the keyframe and the two segment
    midpoints beside it, not the motion, and the velocity check reads the controller steps
    around a few poses; after a pose line inserted, the collision check scans the new
    keyframe and the midpoints beside it (those after it are found from the end)."""
    from motiontool.kinematics import collision
    from motiontool.kinematics.checks import velocity

    (tmp_path / "pyproject.toml").write_text('[tool.motiontool]\nrobot = "nao"\n')
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "walk.motion"
    lines = motion(pick_robot("nao").joint_names[:20], 300, random.Random(7), stars=0.0)
    checks = _checks("nao", None, None)
    reader = Rereader()
    first = b"\n".join(lines) + b"\n"
    lint_document(path, first, Resolver(), Overrides(), lambda *k: checks, reader)
    scans = calls_of(monkeypatch, collision, "scan_self_collisions")  # (spec, q)
    steps = calls_of(monkeypatch, velocity, "commands_at")  # (motion, elapsed)
    cells = lines[150].split(b",")
    cells[4] = b"0.25"
    lines[150] = b",".join(cells)
    data = b"\n".join(lines) + b"\n"
    got, _robot = lint_document(path, data, Resolver(), Overrides(), lambda *k: checks, reader)
    assert sum(len(args[1]) for args, _ in scans) == 3
    assert 0 < sum(len(args[1]) for args, _ in steps) <= 40  # of 601 (a step every 20 ms, 12 s)
    assert reader.resumed == 1
    want, _robot = lint_document(path, data, Resolver(), Overrides(), _checks)
    assert _seen(got) == _seen(want)

    scans.clear()
    cells = lines[100].split(b",")
    cells[0] = str(int(cells[0]) + 20).encode()  # halfway to the next pose
    cells[3] = b"0.125"
    lines.insert(101, b",".join(cells))
    data = b"\n".join(lines) + b"\n"
    got, _robot = lint_document(path, data, Resolver(), Overrides(), lambda *k: checks, reader)
    assert sum(len(args[1]) for args, _ in scans) == 3
    assert reader.resumed == 2
    want, _robot = lint_document(path, data, Resolver(), Overrides(), _checks)
    assert _seen(got) == _seen(want)
