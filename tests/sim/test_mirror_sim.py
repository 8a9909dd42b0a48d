"""Mirrored walks go the other way in simulation (issue #12: within 10 % of the original)."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CORPUS

from motiontool.kinematics.mirror import mirror_map
from motiontool.kinematics.robots import load_robot
from motiontool.motionfmt import loads
from motiontool.motionfmt.ops.mirror import mirror
from motiontool.sim import PlayReport, play

pytestmark = [pytest.mark.slow, pytest.mark.needs("sim"), pytest.mark.usefixtures("corpus")]

SIDE_STEP = CORPUS / "projects/robots/softbank/dancing_nao/motions/SideStepLeft.motion"
TURN = CORPUS / "projects/robots/softbank/nao/motions/TurnLeft60.motion"


def _original_and_mirrored(path: Path, tmp_path: Path) -> tuple[PlayReport, PlayReport]:
    nao = mirror_map(load_robot("nao")).as_dict()
    mirrored = tmp_path / f"{path.stem}.mirrored.motion"
    mirrored.write_bytes(mirror(loads(path.read_bytes(), path.name), nao).document.to_bytes())
    return play([path], robot="nao"), play([mirrored], robot="nao")


def test_mirrored_side_step_left_steps_right(tmp_path: Path) -> None:
    original, mirrored = _original_and_mirrored(SIDE_STEP, tmp_path)
    assert original.base is not None and mirrored.base is not None
    assert not mirrored.base.fell
    assert original.base.dy_m > 0.04  # left
    assert mirrored.base.dy_m < 0  # right
    assert abs(mirrored.base.dy_m) == pytest.approx(abs(original.base.dy_m), rel=0.10)


def test_mirrored_turn_left_turns_right(tmp_path: Path) -> None:
    original, mirrored = _original_and_mirrored(TURN, tmp_path)
    assert original.base is not None and mirrored.base is not None
    yaw, yaw_m = original.base.yaw_change_deg, mirrored.base.yaw_change_deg
    assert yaw is not None and yaw_m is not None
    assert not mirrored.base.fell
    assert yaw > 50.0 and yaw_m < 0
    assert abs(yaw_m) == pytest.approx(abs(yaw), rel=0.10)
