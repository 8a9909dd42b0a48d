"""URScript for the real UR5e rounds the corners of Webots' straight lines with parabolic blends
at 40 rad/s²: the script, parsed back, needs no more than that at any step (the arm at rest
before and after the stream), passes each keyframe |dv| * tb / 8 from it, as the report and the
header say, and sends Webots' own numbers outside the blends. Where blends cannot fit, one line
at the keyframe; --max-error bounds the deviation; --no-blend sends the corners as they are."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.kinematics.real_ur5e import MAX_ACCELERATION_RAD_S2
from motiontool.kinematics.robots import load_robot
from motiontool.motionfmt import read_bytes, sample
from motiontool.motionfmt.convert.blend import CornersDoNotFit, plan_blends

UR = load_robot("ur5e")
ARM = sorted((ROOT / "motions" / "ur5e").glob("*.motion"))
STEP_S = 0.008
_SERVOJ = re.compile(r"^  servoj\(\[([^\]]*)\]", re.MULTILINE)


def _convert(*args: str) -> tuple[int, str]:
    result = CliRunner().invoke(app, ["convert", *args])
    return result.exit_code, result.stderr


def _motion(tmp_path: Path, rows: str, name: str = "arm.motion") -> Path:
    path = tmp_path / name
    path.write_text("#WEBOTS_MOTION,V1.0," + ",".join(UR.joint_names) + "\n" + rows)
    return path


def _servoj(script: str) -> np.ndarray:
    """The servoj targets of a script, (S, 6) rad, as written."""
    return np.array([[float(x) for x in m.split(",")] for m in _SERVOJ.findall(script)])


def _oracle(times_ms: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each keyframe's velocity change (P, 6) rad/s, from rest before the first and to rest
    after the last, and its blend time (P,) s at 40 rad/s²: the textbook's, a loop."""
    velocity = [np.zeros(6)]
    for k in range(len(times_ms) - 1):
        velocity.append((q[k + 1] - q[k]) / ((times_ms[k + 1] - times_ms[k]) / 1000))
    velocity.append(np.zeros(6))
    dv = np.array([velocity[k + 1] - velocity[k] for k in range(len(times_ms))])
    return dv, np.abs(dv).max(axis=1) / MAX_ACCELERATION_RAD_S2


@pytest.mark.parametrize("path", ARM, ids=lambda p: p.name)
def test_the_shipped_motions_convert_blended_within_the_real_arm(
    path: Path, tmp_path: Path
) -> None:
    out = tmp_path / "a.script"
    code, err = _convert(str(path), str(out))
    assert code == 0, err
    motion = read_bytes(path.read_bytes(), str(path)).motion
    order = [motion.column(j) for j in UR.joint_names]
    q = motion.values[:, order]
    dv, tb = _oracle(motion.times_ms, q)
    script = out.read_text()
    sent = _servoj(script)
    # The arm stands at the first pose before the stream and at the last one after it.
    rest = np.concatenate((sent[:1], sent, sent[-1:]))
    accel = np.abs(np.diff(rest, 2, axis=0)) / STEP_S**2
    assert accel.max() <= MAX_ACCELERATION_RAD_S2 * (1 + 1e-9)
    assert accel.max() > 0.9 * MAX_ACCELERATION_RAD_S2  # the blends use what the arm has
    # Webots' stream, from the first step; the blend at the first pose starts before it.
    webots = sample(motion, 8).targets[:, order]
    before = math.ceil(tb[0] / 2 / STEP_S)
    assert np.array_equal(sent[0], q[0]) and np.array_equal(sent[-1], q[-1])
    stream = sent[before : before + webots.shape[0]]
    # At every keyframe (on a step in these files) the blend passes dv * tb / 8 from it.
    rows = motion.times_ms // 8
    assert (motion.times_ms % 8 == 0).all()
    deviation = stream[rows] - q
    np.testing.assert_allclose(deviation, dv * tb[:, None] / 8, rtol=0, atol=1e-12)
    # Outside the blends, Webots' own numbers, bit for bit.
    t = np.arange(webots.shape[0]) * STEP_S
    at = motion.times_ms / 1000
    inside = (np.abs(t[:, None] - at[None, :]) < tb[None, :] / 2 + 1e-12).any(axis=1)
    assert np.array_equal(stream[~inside].view(np.int64), webots[~inside].view(np.int64))
    assert inside.sum() < webots.shape[0] / 2
    # The largest deviation is said in the report and in the header, with its keyframe.
    worst = np.abs(deviation)
    pose, joint = np.unravel_index(int(np.argmax(worst)), worst.shape)
    figure = f"{worst[pose, joint]:.6g}"
    line = motion.pose_names[pose]
    assert (
        f"worst deviation from the motion: {figure} rad ({UR.joint_names[joint]} at {path}:" in err
    )
    assert f"pose {pose} '{line}' ({motion.times_ms[pose]} ms))" in err
    assert "checked against robot ur5e (real arm): clean" in err
    assert f"# largest deviation from the motion: {figure} rad" in script
    assert "# its corners rounded with parabolic blends at 40 rad/s^2" in script


def test_sorting_deviation_and_its_keyframe_line(tmp_path: Path) -> None:
    sorting = ROOT / "motions" / "ur5e" / "sorting.motion"
    code, err = _convert(str(sorting), str(tmp_path / "s.script"))
    assert code == 0, err
    # home's corner: shoulder_lift from 1.556 rad/s to 0.476 rad/s within 40 rad/s²
    assert (
        f"worst deviation from the motion: 0.0273416 rad (shoulder_lift_joint at {sorting}:3:26, "
        "pose 1 'home' (1272 ms))"
    ) in err


def test_a_motion_that_starts_and_ends_still_adds_no_step(tmp_path: Path) -> None:
    src = _motion(
        tmp_path, "0,A,0,0,0,0,0,0\n200,B,0,0,0,0,0,0\n600,C,0,0.4,0,0,0,0\n1000,D,0,0.4,0,0,0,0\n"
    )
    out = tmp_path / "a.script"
    code, err = _convert(str(src), str(out))
    assert code == 0, err
    sent = _servoj(out.read_text())
    assert sent.shape[0] == 1000 // 8 + 1  # Webots' steps, none added
    assert "corners blended at 40 rad/s² (the real arm's): 2 keyframes" in err


def test_blends_that_cannot_fit_are_refused_in_one_line_and_retime_fits_them(
    tmp_path: Path,
) -> None:
    # A 40 ms stop between two moves at 2.5 rad/s: each corner needs a 62.5 ms blend.
    src = _motion(
        tmp_path,
        "0,A,0,0,0,0,0,0\n1000,B,2.5,0,0,0,0,0\n1040,C,2.5,0,0,0,0,0\n2040,D,0,0,0,0,0,0\n",
    )
    out = tmp_path / "a.script"
    code, err = _convert(str(src), str(out))
    assert code == 1 and not out.exists()
    assert err.count("\n") == 1
    assert err.startswith(
        f"{src}:3:1: not written: the corner at pose 1 'B' (1000 ms) needs 62.5 rad/s² to be "
        "rounded (shoulder_pan_joint turns most; its blend and pose 2's share the 40 ms between "
        "them), beyond the real arm's 40 rad/s²; slow the motion down (motiontool retime "
        "--speed 0.79 IN -o OUT fits every corner)"
    )
    slow = tmp_path / "slow.motion"
    result = CliRunner().invoke(app, ["retime", str(src), "--speed", "0.79", "-o", str(slow)])
    assert result.exit_code == 0, result.stderr
    code, err = _convert(str(slow), str(out))
    assert code == 0, err


def test_max_error_holds_the_deviation(tmp_path: Path) -> None:
    jog = ROOT / "motions" / "ur5e" / "jog.motion"
    out = tmp_path / "j.script"
    code, err = _convert(str(jog), str(out), "--max-error", "0.005")
    assert code == 1 and not out.exists()
    assert err.startswith(
        "not written: --max-error 0.005 rad: the corners blended at 40 rad/s² pass 0.00762386 "
        f"rad from the motion (elbow_joint at {jog}:2:21, pose 0 'start' (0 ms))"
    )
    code, err = _convert(str(jog), str(out), "--max-error", "0.008")
    assert code == 0, err
    code, err = _convert(str(jog), str(out), "--max-error", "0.005", "--limits", "webots")
    assert code == 0, err  # nothing blended: Webots' stream as it is


def test_no_blend_and_max_error_are_servoj_options(tmp_path: Path) -> None:
    jog = ROOT / "motions" / "ur5e" / "jog.motion"
    for option in (["--no-blend"], ["--max-error", "0.01"]):
        code, err = _convert(str(jog), str(tmp_path / "a.script"), "--keyframes", *option)
        assert code == 2 and f"{option[0]} is about servoj's blended corners" in err
    code, err = _convert(str(jog), str(tmp_path / "a.csv"), "--no-blend")
    assert code == 2 and "--no-blend applies to urscript, not to motion -> csv" in err


def test_a_held_joint_is_still_and_blends_fit_at_touching() -> None:
    times = np.array([0, 100, 200, 300], dtype=np.int64)
    q = np.array([[0.0, 0], [0.2, 0], [0.2, 0.1], [0.2, 0.1]])
    sent = np.ones_like(q, dtype=bool)
    sent[1, 1] = False  # joint 1 has '*' at pose 1: nothing sent from 0 to 200 ms
    blends = plan_blends(("a", "b"), times, q, sent, 40.0)
    assert blends.dv.tolist() == [[2.0, 0.0], [-2.0, 0.0], [0.0, 0.0], [0.0, 0.0]]
    # Up 0.1 rad and back at 2 rad/s: at 60 rad/s² the blends (1/30 s, 1/15 s, 1/30 s) just
    # touch in each 50 ms segment: they fit; in 49 ms they need 0.3 / (2 * 0.049²) rad/s².
    q = np.array([[0.0], [0.1], [0.0]])
    sent = np.ones((3, 1), dtype=bool)
    fits = plan_blends(("a",), np.array([0, 50, 100]), q, sent, 60.0)
    np.testing.assert_allclose(fits.tb_s, [1 / 30, 1 / 15, 1 / 30])
    with pytest.raises(CornersDoNotFit, match=r"pose 1: .* needs 62\.47 rad/s²") as e:
        plan_blends(("a",), np.array([0, 49, 98]), q, sent, 60.0)
    assert e.value.worst_rad_s2 == pytest.approx(0.3 / (2 * 0.049**2))
    assert e.value.speed() <= math.sqrt(60 / e.value.worst_rad_s2)
