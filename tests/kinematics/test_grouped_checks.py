"""The limits and velocity checks' ``grouped`` findings (MT302, MT303 grouped from arrays, issue
17 item 4) are exactly what ``group_findings`` makes of their per-pose findings: every field,
on random motions (with ``*``, ``inf`` and a joint named twice), the Webots corpus and
``motions/``; and they are built without a finding per pose."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from conftest import CORPUS, ROOT

from motiontool.kinematics import load_robot
from motiontool.kinematics.checks import Limits, RobotChecks, Velocity
from motiontool.motionfmt import read_bytes, validate_bytes
from motiontool.motionfmt.diagnostics import Diagnostic
from motiontool.motionfmt.grouping import group_findings

NAO_JOINTS = ["HeadYaw", "HeadPitch", "LShoulderPitch", "LShoulderRoll", "RElbowRoll"]


def random_motion(poses: int, seed: int, *, twice: bool = False) -> bytes:
    """Random Nao values in [-2, 2] rad (runs of poses past the limits), some '*' and 'inf'
    cells; ``twice``: the last joint named twice (MT205)."""
    rng = np.random.default_rng(seed)
    joints = NAO_JOINTS + (["RElbowRoll"] if twice else [])
    lines = ["#WEBOTS_MOTION,V1.0," + ",".join(joints)]
    for p in range(poses):
        cells = [f"{v:.4f}" for v in rng.uniform(-2.0, 2.0, len(joints))]
        if rng.random() < 0.1:
            cells[int(rng.integers(len(joints)))] = "*"
        if rng.random() < 0.02:
            cells[int(rng.integers(len(joints)))] = "inf"
        t = 40 * p
        lines.append(
            f"{t // 60000:02d}:{t // 1000 % 60:02d}:{t % 1000:03d},Pose{p},{','.join(cells)}"
        )
    return ("\n".join(lines) + "\n").encode()


def every_field(findings: list[Diagnostic]) -> list[tuple[object, ...]]:
    """The findings in report order, each with every field (those ``==`` skips included)."""
    ordered = sorted(findings, key=Diagnostic.sort_key)
    return [tuple(getattr(d, f.name) for f in dataclasses.fields(d)) for d in ordered]


def files() -> list[Path]:
    return sorted(CORPUS.glob("*.motion")) + sorted((ROOT / "motions").rglob("*.motion"))


@pytest.mark.parametrize("check_class", [Limits, Velocity])
def test_grouped_is_group_findings_of_the_per_pose_findings(check_class: type) -> None:
    check = check_class(load_robot("nao"))
    motions = [random_motion(400, seed, twice=seed % 2 == 1) for seed in range(4)]
    motions += [path.read_bytes() for path in files()]
    grouped_somewhere = False
    for i, data in enumerate(motions):
        result = read_bytes(data, f"m{i}.motion")
        if not result.accepted or not result.times_ms:
            continue
        expected = group_findings(check(result))
        got = group_findings(check.grouped(result))
        assert every_field(got) == every_field(expected), f"motion {i}"
        grouped_somewhere |= any(d.run is not None for d in got)
    assert grouped_somewhere


def test_grouped_builds_a_finding_per_run_not_per_pose(monkeypatch: pytest.MonkeyPatch) -> None:
    calls = {"limits": 0, "velocity": 0}
    beyond, segment = Limits._beyond, Velocity._segment

    def counted_beyond(self: Limits, *args: object) -> Diagnostic:
        calls["limits"] += 1
        return beyond(self, *args)  # type: ignore[arg-type]

    def counted_segment(*args: object) -> Diagnostic:
        calls["velocity"] += 1
        return segment(*args)  # type: ignore[arg-type]

    monkeypatch.setattr(Limits, "_beyond", counted_beyond)
    monkeypatch.setattr(Velocity, "_segment", staticmethod(counted_segment))
    result = read_bytes(random_motion(400, 7), "r.motion")
    spec = load_robot("nao")
    for name, check, code in (
        ("limits", Limits(spec), "MT302"),
        ("velocity", Velocity(spec), "MT303"),
    ):
        per_pose = sum(d.code == code for d in check(result))
        calls[name] = 0
        runs = sum(d.code == code for d in check.grouped(result))
        assert calls[name] == runs < per_pose, name


def test_validate_groups_through_the_checks_grouped_method() -> None:
    """``validate_bytes(group=True)`` gives the same report as grouping every per-pose finding,
    and ``group=False`` the per-pose findings."""
    data = random_motion(300, 3, twice=True)
    checks = RobotChecks("nao", ["limits", "velocity"])
    grouped = validate_bytes(data, "r.motion", checks=[checks], group=True).diagnostics
    flat = validate_bytes(data, "r.motion", checks=[checks], group=False).diagnostics
    assert every_field(grouped) == every_field(group_findings(flat))
    assert all(d.run is None for d in flat) and any(d.run is not None for d in grouped)
