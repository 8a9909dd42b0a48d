"""``motiontool server`` lints each version of a document from the last one (the reader goes on
from the edit, the robot checks kept): every version's findings and fixes are those of a fresh
lint of the same text, over random edits of a Nao motion."""

from __future__ import annotations

import random
from pathlib import Path
from typing import Any

import pytest
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


@pytest.mark.needs("kinematics")
@pytest.mark.parametrize("seed", range(3))
def test_every_version_lints_as_a_fresh_lint(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, seed: int
) -> None:
    (tmp_path / "pyproject.toml").write_text('[tool.motiontool]\nrobot = "nao"\n')
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "walk.motion"
    rng = random.Random(seed)
    lines = motion(pick_robot("nao").joint_names[:20], 120, rng)
    kept: dict[tuple[Any, ...], RobotChecks] = {}
    reader = Rereader()

    def kept_checks(*key: Any) -> RobotChecks:
        return kept.setdefault(key, _checks(*key))

    for _version in range(40):
        data = b"\n".join(lines) + b"\n"
        got, _robot = lint_document(path, data, Resolver(), Overrides(), kept_checks, reader)
        want, _robot = lint_document(path, data, Resolver(), Overrides(), _checks)
        assert _seen(got) == _seen(want)
        lines = edit(lines, rng)
    assert reader.resumed > 10


@pytest.mark.needs("kinematics")
def test_a_value_edit_scans_only_the_configurations_it_changed(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """After a one-value edit, the collision check scans the keyframe and the two segment
    midpoints beside it, not the motion; after a pose line inserted, the new keyframe and the
    midpoints beside it (those after it are found from the end of the motion)."""
    from motiontool.kinematics import collision

    (tmp_path / "pyproject.toml").write_text('[tool.motiontool]\nrobot = "nao"\n')
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "walk.motion"
    lines = motion(pick_robot("nao").joint_names[:20], 300, random.Random(7))
    checks = _checks("nao", None, None)
    reader = Rereader()
    first = b"\n".join(lines) + b"\n"
    lint_document(path, first, Resolver(), Overrides(), lambda *k: checks, reader)
    scanned: list[int] = []
    scan = collision.scan_self_collisions

    def counted(spec: Any, q: Any, **options: Any) -> list[collision.Contact]:
        scanned.append(len(q))
        return scan(spec, q, **options)

    monkeypatch.setattr(collision, "scan_self_collisions", counted)
    cells = lines[150].split(b",")
    cells[4] = b"0.25"
    lines[150] = b",".join(cells)
    data = b"\n".join(lines) + b"\n"
    got, _robot = lint_document(path, data, Resolver(), Overrides(), lambda *k: checks, reader)
    assert sum(scanned) == 3
    assert reader.resumed == 1
    want, _robot = lint_document(path, data, Resolver(), Overrides(), _checks)
    assert _seen(got) == _seen(want)

    scanned.clear()
    cells = lines[100].split(b",")
    cells[0] = str(int(cells[0]) + 20).encode()  # halfway to the next pose
    cells[3] = b"0.125"
    lines.insert(101, b",".join(cells))
    data = b"\n".join(lines) + b"\n"
    got, _robot = lint_document(path, data, Resolver(), Overrides(), lambda *k: checks, reader)
    assert sum(scanned) == 3
    assert reader.resumed == 2
    want, _robot = lint_document(path, data, Resolver(), Overrides(), _checks)
    assert _seen(got) == _seen(want)
