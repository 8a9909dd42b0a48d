"""``retime --fit-limits`` (with or without ``--accel``) on a file with a nan/inf command: one
error at the cell (MT113), never a traceback; the robot's stretch fix plans nothing for it."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import DATA
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.kinematics.robot_fixes import stretch_fixes
from motiontool.kinematics.robots import load_robot
from motiontool.motionfmt import read_bytes

NAN_INF = DATA / "valid" / "nan_inf.motion"


@pytest.mark.parametrize("accel", [[], ["--accel", "50"]], ids=["velocity", "acceleration"])
def test_fit_limits_refuses_a_non_finite_command_at_its_cell(
    tmp_path: Path, accel: list[str]
) -> None:
    out = tmp_path / "out.motion"
    args = ["retime", str(NAN_INF), "--fit-limits", "--robot", "nao", *accel, "-o", str(out)]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 2 and not out.exists()
    assert result.stderr == (
        f"motiontool: error: {NAN_INF}:3:17: HeadYaw = nan is not a finite number (MT113): write"
        " a number, or '*' for no command, before fitting it to the robot's limits\n"
    )


def test_the_stretch_fix_plans_nothing_for_a_non_finite_motion() -> None:
    data = NAN_INF.read_bytes()
    result = read_bytes(data, "nan_inf.motion")
    assert stretch_fixes(data, "nan_inf.motion", result, load_robot("nao")) == []
