"""URScript is checked against the real UR5e by default: 180 °/s on every joint (the Webots
model allows 360 °/s on the wrists), the joint accelerations the servoj stream needs,
movej's rest-to-rest trapezoids with ``--keyframes``, and servoj's t against the
controller's 2 ms cycle; ``--limits webots`` checks against the model instead."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.kinematics.real_ur5e import (
    MAX_ACCELERATION_RAD_S2,
    MAX_VELOCITY_RAD_S,
    _trapezoid,
    movej_findings,
    servoj_findings,
)
from motiontool.kinematics.robots import load_robot
from motiontool.motionfmt.convert.base import RobotStream

UR = load_robot("ur5e")
JOG = ROOT / "motions" / "ur5e" / "jog.motion"


def _motion(tmp_path: Path, rows: str) -> Path:
    path = tmp_path / "arm.motion"
    path.write_text("#WEBOTS_MOTION,V1.0," + ",".join(UR.joint_names) + "\n" + rows)
    return path


def _convert(*args: str) -> tuple[int, str]:
    result = CliRunner().invoke(app, ["convert", *args])
    return result.exit_code, result.stderr


def test_the_shipped_jog_sent_unblended_needs_more_acceleration_than_the_real_arm(
    tmp_path: Path,
) -> None:
    out = tmp_path / "jog.script"
    code, err = _convert(str(JOG), str(out), "--no-blend")
    assert code == 1 and not out.exists()
    assert "fails robot ur5e (real arm)'s limits" in err
    line = "urscript export: elbow_joint needs 195.242 rad/s² at 1272 ms, beyond the real arm's"
    assert f"{line} 40 rad/s²" in err
    code, err = _convert(str(JOG), str(out), "--limits", "webots")
    assert code == 0 and "checked against robot ur5e: clean" in err
    assert "corners blended" not in err  # the Webots model has no acceleration limit


def test_a_wrist_at_4_rad_s_passes_webots_but_not_the_real_arm(tmp_path: Path) -> None:
    src = _motion(tmp_path, "0,A,0,0,0,0,0,0\n500,B,0,0,0,2,0,0\n")
    code, err = _convert(str(src), str(tmp_path / "a.script"), "--keyframes")
    assert code == 1, err
    assert "MT303" in err and "wrist_1_joint" in err and "3.14159 rad/s" in err
    code, err = _convert(str(src), str(tmp_path / "a.script"), "--keyframes", "--limits", "webots")
    assert code == 0, err


def test_movej_trapezoid_rest_to_rest(tmp_path: Path) -> None:
    # 1 rad in 350 ms: 2.86 rad/s on average (within 180 °/s), but rest to rest at most
    # pi rad/s the ramps leave 31.7 ms: 99 rad/s².
    src = _motion(tmp_path, "0,A,0,0,0,0,0,0\n350,B,1,0,0,0,0,0\n")
    code, err = _convert(str(src), str(tmp_path / "a.script"), "--keyframes")
    assert code == 1
    assert (
        "urscript export: shoulder_pan_joint moves 1 rad in movej from 0 ms to 350 ms (rest to "
        "rest): its trapezoid needs a peak of 3.14159 rad/s and 99.1348 rad/s², beyond the real "
        "arm's 3.14159 rad/s and 40 rad/s²"
    ) in err
    ok = _motion(tmp_path, "0,A,0,0,0,0,0,0\n400,B,1,0,0,0,0,0\n")  # 38.5 rad/s²
    code, err = _convert(str(ok), str(tmp_path / "b.script"), "--keyframes")
    assert code == 0 and "checked against robot ur5e (real arm): clean" in err
    assert "# robot check: ur5e (real arm)" in (tmp_path / "b.script").read_text()


@pytest.mark.parametrize(("distance", "seconds"), [(0.1, 1.0), (1.0, 0.4), (1.0, 0.35), (3.0, 1.0)])
def test_the_trapezoid_covers_the_distance_in_the_time(distance: float, seconds: float) -> None:
    peak, acc = _trapezoid(distance, seconds)
    assert peak <= MAX_VELOCITY_RAD_S * (1 + 1e-12)
    ramp = peak / acc
    assert ramp <= seconds / 2 + 1e-12
    assert peak * (seconds - ramp) == pytest.approx(distance)  # area under the trapezoid


def test_faster_than_180_deg_s_even_at_constant_speed() -> None:
    stream = RobotStream(UR.joint_names, np.array([0, 100]), np.array([[0.0] * 6, [0.5] * 6]))
    found = movej_findings(stream, "x")
    assert len(found) == 6 and "needs 5 rad/s even at constant speed" in found[0]


def test_servoj_acceleration_is_the_second_difference_across_chunks() -> None:
    t = np.arange(0, 80, 8)
    q = np.zeros((t.size, 6))
    q[5:, 1] = np.cumsum([0.5, 0.5, 0.5, 0.25, 0.25]) * 0.008  # rest to 0.5 rad/s in 8 ms,
    # then down to 0.25 rad/s and to rest after the last row (31.25 rad/s² each: within)
    chunks = [(t[:5], q[:5]), (t[5:], q[5:])]  # the corner lies across the chunk boundary
    stream = RobotStream(UR.joint_names, t[:0], q[:0], lambda: iter(chunks))
    found = servoj_findings(stream, 8, "x")
    assert found == [
        "x: shoulder_lift_joint needs 62.5 rad/s² at 32 ms, beyond the real arm's 40 rad/s²"
    ]
    assert math.isclose(0.5 / 0.008, 62.5) and MAX_ACCELERATION_RAD_S2 < 62.5


def test_servoj_starts_and_ends_at_rest() -> None:
    # The arm stands at the first target (after the movej) and at the last one (stopj): a
    # stream that starts or ends moving needs the step from rest, which no row pair shows.
    t = np.arange(0, 40, 8)
    q = np.zeros((t.size, 6))
    q[:, 0] = np.arange(t.size) * 0.008 * 0.4  # 0.4 rad/s from the first row to the last
    stream = RobotStream(UR.joint_names, t, q)
    assert servoj_findings(stream, 8, "x") == [
        "x: shoulder_pan_joint needs 50 rad/s² at 0 ms, beyond the real arm's 40 rad/s²"
    ]
    q[:, 0] = np.arange(t.size) * 0.008 * 0.3  # 37.5 rad/s² at either end: within
    assert servoj_findings(RobotStream(UR.joint_names, t, q), 8, "x") == []


def test_servoj_t_under_the_controller_cycle(tmp_path: Path) -> None:
    src = _motion(tmp_path, "0,A,0,0,0,0,0,0\n100,B,0,0,0,0,0,0\n")
    code, err = _convert(str(src), str(tmp_path / "a.script"), "--timestep", "1")
    assert code == 1
    assert "urscript export: servoj t = 1 ms is shorter than the controller's 2 ms cycle" in err
    code, err = _convert(str(src), str(tmp_path / "a.script"), "--timestep", "2")
    assert code == 0, err


def test_real_limits_are_known_for_the_ur5e_only(tmp_path: Path) -> None:
    src = _motion(tmp_path, "0,A,0,0,0,0,0,0\n100,B,0,0,0,0,0,0\n")
    code, err = _convert(str(src), str(tmp_path / "a.script"), "--robot", "nao", "--limits", "real")
    assert code == 2 and "--limits real: the real arm's limits are known for ur5e" in err
    code, err = _convert(str(src), str(tmp_path / "a.csv"), "--limits", "real")
    assert code == 2 and "--limits applies to urscript, not to motion -> csv" in err
