"""A ``nan`` / ``inf`` cell is a command Webots sends to the motor: ``play`` refuses it with a
one-line error at the cell instead of feeding it to the physics."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.motionfmt import Motion, MotionSyntaxError, MotionToolError
from motiontool.sim import command_matrix, command_stream, play

NAN_FILE = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n0,P1,0,0\n500,P2,0.2,nan\n"


def test_play_refuses_a_nan_cell_at_its_line_and_column(tmp_path: Path) -> None:
    path = tmp_path / "nan.motion"
    path.write_bytes(NAN_FILE)
    with pytest.raises(MotionSyntaxError) as info:
        play([path], robot="nao")
    assert (info.value.line, info.value.column) == (3, 12)
    assert str(info.value).startswith(f"{path}:3:12: HeadPitch = nan is not a finite number")


@pytest.mark.needs("sim")
def test_cli_play_of_a_nan_cell_is_one_line_and_exit_2(tmp_path: Path) -> None:
    path = tmp_path / "nan.motion"
    path.write_bytes(NAN_FILE)
    result = CliRunner().invoke(app, ["play", str(path), "--headless"])
    assert result.exit_code == 2
    assert result.stderr.startswith(f"motiontool: error: {path}:3:12: HeadPitch = nan")
    assert result.stderr.count("\n") == 1


def test_command_matrix_fails_on_a_commanded_nan_and_keeps_star_held() -> None:
    values = np.array([[0.5], [np.nan]])
    star = Motion(("A",), ("P", "Q"), np.array([0, 40]), values)  # no mask: NaN is '*'
    targets, commanded, _l, _i = command_matrix(command_stream([star], ["A"], 20, np.zeros(1)))
    assert commanded[:, 0].tolist() == [True, False, False]
    assert targets[:, 0].tolist() == [0.5, 0.5, 0.5]
    nan = Motion(("A",), ("P", "Q"), np.array([0, 40]), values, np.array([[True], [True]]))
    with pytest.raises(MotionToolError, match="non-finite target"):
        command_matrix(command_stream([nan], ["A"], 20, np.zeros(1)))
