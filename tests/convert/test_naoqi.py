"""NAOqi export: the JSON's keys, evaluated as NAOqi's documentation describes its Bézier
curves, give back Webots' command stream at every control step; times are > 0; the script
sends exactly the JSON's arguments."""

from __future__ import annotations

import errno
import itertools
import json
import os
import runpy
import stat
import sys
import types
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import CORPUS, ROOT, corpus_params
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.kinematics import detect_robot
from motiontool.kinematics.builtin_robots import builtin
from motiontool.motionfmt import read_bytes
from motiontool.motionfmt.convert.base import ExportOptions
from motiontool.motionfmt.convert.held import held_stream
from motiontool.motionfmt.convert.naoqi import naoqi_names, write_naoqi
from motiontool.motionfmt.convert.naoqi_curve import curve_at
from motiontool.motionfmt.motion import Motion

NAO_FILES = sorted((ROOT / "motions" / "nao").glob("*.motion"))
ROUNDING = 1e-12  # rad: what floating-point evaluation of a straight line may leave
COUPLED = builtin("nao-v5").coupled_joints  # what convert --to naoqi passes (its robot's facts)
NAOQI_NAMES = naoqi_names(COUPLED)


def test_naoqi_names_come_from_the_robot_facts() -> None:
    """The hip the real NAO drives with one motor is read from nao-v5.json's
    coupled joints, not spelt again; the hands are NAOqi's one joint each."""
    assert NAOQI_NAMES["RHipYawPitch"] == "LHipYawPitch"
    assert NAOQI_NAMES["LPhalanx1"] == NAOQI_NAMES["LPhalanx8"] == "LHand"
    assert "LHipYawPitch" not in NAOQI_NAMES
    assert "RHipYawPitch" not in naoqi_names(())  # another robot: no coupling assumed


def _export(motion: Motion, lead_in_ms: int = 1000) -> tuple[dict[str, Any], Any]:
    options = ExportOptions(timestep_ms=20, lead_in_ms=lead_in_ms, coupled_joints=COUPLED)
    out = write_naoqi(motion, options)
    return json.loads(out.data), out


def _worst_from_json(motion: Motion, doc: dict[str, Any]) -> float:
    """The deviation recomputed from the JSON alone: its keys through the curve model, against
    the targets Webots' player holds at every step."""
    held = held_stream(motion, doc["timestep_ms"])
    t_s = (held.elapsed_ms + doc["lead_in_ms"]) / 1000.0
    curves = {
        name: curve_at(times, [(a, tuple(h1), tuple(h2)) for a, h1, h2 in keys], t_s)
        for name, times, keys in zip(doc["names"], doc["times"], doc["keys"], strict=True)
    }
    worst = 0.0
    for k, motor in enumerate(held.motors):
        want = held.targets[:, k]
        got = curves.get(NAOQI_NAMES.get(motor, motor))
        if got is None:
            assert np.isnan(want).all()  # never commanded: left out
            continue
        live = ~np.isnan(want)
        worst = max(worst, float(np.max(np.abs(got[live] - want[live]), initial=0.0)))
    return worst


def _coupled_joints_agree(motion: Motion) -> bool:
    """Whether the joints one motor drives on a real NAO (the fingers of a hand, the two
    HipYawPitch) hold the same targets: otherwise no export can play it there."""
    held = held_stream(motion, 20)
    by_name = {m: held.targets[:, k] for k, m in enumerate(held.motors)}
    for motor, target in by_name.items():
        leader = {"LHand": "LPhalanx1", "RHand": "RPhalanx1"}.get(NAOQI_NAMES.get(motor, ""))
        other = by_name.get(leader or NAOQI_NAMES.get(motor, motor))
        if other is not None and not np.allclose(target, other, atol=1e-3, equal_nan=True):
            return False
    return True


def _nao_params() -> list[object]:
    out: list[object] = list(NAO_FILES)
    for p in corpus_params():
        path = getattr(p, "values", [None])[0] if not isinstance(p, Path) else p
        out.append(p if path is None else path)
    return out


@pytest.mark.parametrize("path", _nao_params())
def test_keys_give_webots_stream_back(path: Path) -> None:
    motion = read_bytes(path.read_bytes(), str(path)).motion
    if detect_robot(motion.joints) not in ("nao", "nao-v5"):
        pytest.skip("not a Nao motion")
    if not np.isfinite(motion.values[motion.commanded]).all():
        pytest.skip("a nan/inf command cannot be sent")
    if not _coupled_joints_agree(motion):
        pytest.skip("fingers or hips one motor drives apart: refused (test below)")
    doc, out = _export(motion)
    assert out.deviation is not None and out.deviation.max_rad <= ROUNDING
    assert _worst_from_json(motion, doc) <= ROUNDING
    for times, keys in zip(doc["times"], doc["keys"], strict=True):
        assert times[0] > 0 and all(b > a for a, b in itertools.pairwise(times))
        assert len(keys) == len(times)
        for angle, h1, h2 in keys:
            assert isinstance(angle, float) and h1[0] == h2[0] == 3
            assert h1[1] <= 0 <= h2[1]  # each handle inside its segment


def test_a_first_pose_at_zero_gets_the_lead_in() -> None:
    motion = read_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0.5\n100,B,0\n", "m").motion
    doc, _ = _export(motion, lead_in_ms=700)
    assert doc["times"] == [[0.7, 0.8]]
    assert doc["keys"][0][0] == [0.5, [3, -0.7 / 3, 0.0], [3, (0.8 - 0.7) / 3, -0.5 / 3]]


def test_a_star_stretch_is_held_then_jumps_as_webots_plays_it() -> None:
    # HeadYaw: 0 at 0 ms, '*' at 100 ms: nothing is sent until after 200 ms (the motor holds
    # 0), then the segment 200 -> 300 ms is played from its first step (220 ms: 0.8).
    data = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n0,A,0,0\n100,B,*,0.2\n200,C,1,0.2\n300,D,0,0\n"
    motion = read_bytes(data, "m").motion
    doc, out = _export(motion)
    assert doc["names"] == ["HeadYaw", "HeadPitch"]
    assert doc["times"][0] == [1.0, 1.2, 1.22, 1.3]
    assert [k[0] for k in doc["keys"][0]] == [0.0, 0.0, 0.8, 0.0]
    assert out.deviation.max_rad <= ROUNDING


def test_handles_off_the_line_are_measured_not_hidden() -> None:
    # Choregraphe's flat handles ([3, +-dt/3, 0]): a smooth curve, not Webots' straight lines.
    motion = read_bytes(NAO_FILES[0].read_bytes(), "m").motion
    doc, _ = _export(motion)
    doc["keys"] = [[[a, [3, h1[1], 0.0], [3, h2[1], 0.0]] for a, h1, h2 in j] for j in doc["keys"]]
    assert _worst_from_json(motion, doc) > 0.01


def _send(script: Path, monkeypatch: pytest.MonkeyPatch, *args: str) -> list[tuple[str, Any]]:
    """Run the companion script with a stand-in ``qi``: the calls it makes."""
    calls: list[tuple[str, tuple[Any, ...]]] = []

    class Service:
        def __getattr__(self, name: str) -> Any:
            return lambda *args: calls.append((name, args))

    class Session:
        def connect(self, url: str) -> None:
            calls.append(("connect", (url,)))

        def service(self, name: str) -> Service:
            assert name == "ALMotion"
            return Service()

    monkeypatch.setitem(sys.modules, "qi", types.SimpleNamespace(Session=Session))
    monkeypatch.setattr(sys, "argv", [script.name, "--ip", "10.0.0.5", *args])
    runpy.run_path(str(script), run_name="__main__")
    return calls


def test_the_script_sends_the_json(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    target = tmp_path / "wave.naoqi.json"
    result = CliRunner().invoke(
        app, ["convert", str(ROOT / "motions" / "nao" / "wave_right.motion"), str(target)]
    )
    assert result.exit_code == 0, result.stderr
    assert "worst deviation from Webots' command stream: " in result.stderr
    assert "(the script that sends it)" in result.stderr
    calls = _send(tmp_path / "wave_send.py", monkeypatch)
    doc = json.loads(target.read_text())
    assert calls[0] == ("connect", ("tcp://10.0.0.5:9559",))
    assert calls[-1] == ("angleInterpolationBezier", (doc["names"], doc["times"], doc["keys"]))


def test_a_hand_the_real_robot_cannot_do_is_refused(tmp_path: Path) -> None:
    # salute.motion moves RPhalanx7/8 apart from RPhalanx1: one motor drives them on a NAO.
    result = CliRunner().invoke(
        app,
        [
            "convert",
            str(ROOT / "motions" / "nao" / "salute.motion"),
            str(tmp_path / "s.naoqi.json"),
        ],
    )
    assert result.exit_code == 1
    assert "warning MT306" in result.stderr and "not written" in result.stderr
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("name", ["SideStepLeft", "SideStepRight"])
def test_webots_side_steps_export_as_validate_passes_them(name: str, tmp_path: Path) -> None:
    # Their LAnkleRoll sits at its lower limit -0.397761 rad; the Bezier model evaluates the
    # flat segment there one float step below it. validate finds nothing: neither may the
    # export's check of what it sends.
    src = CORPUS / "projects/robots/softbank/dancing_nao/motions" / f"{name}.motion"
    target = tmp_path / f"{name}.naoqi.json"
    assert CliRunner().invoke(app, ["validate", "--robot", "nao-v5", str(src)]).exit_code == 0
    result = CliRunner().invoke(app, ["convert", str(src), str(target)])
    assert result.exit_code == 0, result.stderr
    assert "checked against robot nao-v5: clean" in result.stderr
    doc = json.loads(target.read_text())
    ankle = doc["keys"][doc["names"].index("LAnkleRoll")]
    assert min(key[0] for key in ankle) == -0.397761


WAVE = ROOT / "motions" / "nao" / "wave_right.motion"


def _convert(*args: str | Path) -> Any:
    return CliRunner().invoke(app, ["convert", *map(str, args)])


def test_send_script_puts_the_script_where_it_is_named(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target, script = tmp_path / "out" / "wave.naoqi.json", tmp_path / "bin" / "play_wave.py"
    result = _convert(WAVE, target, "--send-script", script)
    assert result.exit_code == 0, result.stderr
    assert f"motiontool: wrote {script} (the script that sends it)" in result.stderr
    assert sorted(p.name for p in target.parent.iterdir()) == ["wave.naoqi.json"]
    monkeypatch.chdir(tmp_path / "out")  # the script finds the JSON from its own folder
    calls = _send(script, monkeypatch)
    doc = json.loads(target.read_text())
    assert calls[-1] == ("angleInterpolationBezier", (doc["names"], doc["times"], doc["keys"]))


def test_no_script_beside_a_device(tmp_path: Path) -> None:
    # Beside /dev/null it wrote /dev/null_send.py (as root). A node made here, not the machine's.
    null = tmp_path / "null"
    try:
        os.mknod(null, stat.S_IFCHR | 0o666, os.makedev(1, 3))
    except PermissionError:
        pytest.skip("mknod needs root (CI runs as root)")
    result = _convert(WAVE, null, "--to", "naoqi")
    assert result.exit_code == 0, result.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["null"]
    assert (
        f"motiontool: no script written: '{null}' is not a regular file "
        "(give --send-script PATH for one)" in result.stderr
    )


def test_to_stdout_the_json_alone(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    result = _convert(WAVE, "-", "--to", "naoqi")
    assert result.exit_code == 0, result.stderr
    assert json.loads(result.stdout)["call"] == "ALMotion.angleInterpolationBezier"
    assert "motiontool: no script written: OUT is standard output" in result.stderr
    assert list(tmp_path.iterdir()) == []
    script = tmp_path / "send.py"  # named: it needs --json, the JSON having no file
    result = _convert(WAVE, "-", "--to", "naoqi", "--send-script", script)
    assert result.exit_code == 0, result.stderr
    (tmp_path / "w.naoqi.json").write_text(result.stdout)
    calls = _send(script, monkeypatch, "--json", str(tmp_path / "w.naoqi.json"))
    assert calls[-1][0] == "angleInterpolationBezier"


def test_a_script_that_cannot_be_written_leaves_no_json(tmp_path: Path) -> None:
    (tmp_path / "wave_send.py").mkdir()
    result = _convert(WAVE, tmp_path / "wave.naoqi.json")
    assert result.exit_code == 2
    assert result.stderr.endswith("wave_send.py': Is a directory\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["wave_send.py"]


def test_a_json_that_cannot_be_renamed_takes_its_script_away(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # The last step of the pair fails (a full disk, a lost mount): the script already in place
    # is removed, so neither file is there.
    replace = os.replace

    def failing(src: Any, dst: Any) -> None:
        if str(dst).endswith(".naoqi.json"):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        replace(src, dst)

    monkeypatch.setattr(os, "replace", failing)
    result = _convert(WAVE, tmp_path / "wave.naoqi.json")
    assert result.exit_code == 2
    assert result.stderr.endswith("wave.naoqi.json': No space left on device\n")
    assert list(tmp_path.iterdir()) == []


def test_send_script_is_for_naoqi_only(tmp_path: Path) -> None:
    result = _convert(WAVE, tmp_path / "w.csv", "--send-script", tmp_path / "s.py")
    assert result.exit_code == 2
    assert "--send-script applies to naoqi, not to motion -> csv" in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_a_full_disk_under_the_script_leaves_no_json(tmp_path: Path) -> None:
    # The script goes to a full device (1, 7: /dev/full): the JSON is not left alone.
    full = tmp_path / "full"
    try:
        os.mknod(full, stat.S_IFCHR | 0o666, os.makedev(1, 7))
    except PermissionError:
        pytest.skip("mknod needs root (CI runs as root)")
    result = _convert(WAVE, tmp_path / "wave.naoqi.json", "--send-script", full)
    assert result.exit_code == 2
    assert result.stderr == f"motiontool: error: cannot write '{full}': No space left on device\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["full"]
