"""Choregraphe in and out: a real timeline (Aldebaran's Hello, vendored with its licence) and
Python exports read as a motion within the maximum error, the deviation printed; motions
written as Choregraphe's Python and read back within it; bad input refused in one line with
its position, nothing written."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from conftest import DATA, ROOT
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.kinematics.builtin_robots import builtin
from motiontool.motionfmt import read_bytes
from motiontool.motionfmt.convert.base import ExportOptions, ImportOptions
from motiontool.motionfmt.convert.choregraphe import auto_handles
from motiontool.motionfmt.convert.choregraphe_py import read_choregraphe_py, write_choregraphe_py
from motiontool.motionfmt.convert.choregraphe_xml import read_timeline
from motiontool.motionfmt.convert.held import held_stream
from motiontool.motionfmt.motion import Motion

runner = CliRunner()
CHOREGRAPHE = DATA / "choregraphe"
HELLO = CHOREGRAPHE / "hello" / "behavior.xar"
WELCOMING = CHOREGRAPHE / "welcoming" / "Welcoming.py"
NAO_MOTIONS = sorted((ROOT / "motions" / "nao").glob("*.motion"))
COUPLED = builtin("nao-v5").coupled_joints
MAX_ERROR = 1e-3  # rad
ROUNDING = 1e-9  # rad: floating-point evaluation of the curves and the lines


def _run(*args: str | Path) -> tuple[int, str]:
    result = runner.invoke(app, ["convert", *map(str, args)])
    return result.exit_code, result.stderr


def _motion(path: Path) -> Motion:
    return read_bytes(path.read_bytes(), str(path)).motion


def test_the_vendored_files_are_those_the_manifest_lists() -> None:
    header, *rows = (CHOREGRAPHE / "MANIFEST.tsv").read_text(encoding="utf-8").splitlines()
    listed = [dict(zip(header.split("\t"), row.split("\t"), strict=True)) for row in rows]
    for row in listed:
        assert (CHOREGRAPHE / row["path"]).stat().st_size == int(row["bytes"])
        assert row["license"] and row["repository"] and len(row["commit"]) == 40
    files = {p.relative_to(CHOREGRAPHE).as_posix() for p in CHOREGRAPHE.rglob("*") if p.is_file()}
    assert files == {r["path"] for r in listed} | {"MANIFEST.tsv", "NOTICE"}
    assert "BSD-style" in (CHOREGRAPHE / "NOTICE").read_text(encoding="utf-8")
    assert "GNU GENERAL PUBLIC LICENSE" in (WELCOMING.parent / "LICENSE.md").read_text()


def test_a_python_export_from_the_wild_converts_and_validates(tmp_path: Path) -> None:
    """Welcoming.py, a Choregraphe Python export as a team keeps it (Python 2, the proxy call
    at its end): read within the maximum error with the deviation printed, and the motion
    written passes validate for the NAO."""
    out = tmp_path / "welcoming.motion"
    code, err = _run(WELCOMING, out)
    assert code == 0, err
    assert (
        "read 75 keys of 14 joint curves (a Choregraphe Python export calling "
        "angleInterpolationBezier); its first key, at 0.64 s, is the motion's 0 ms\n" in err
    )
    worst = float(re.search(r"worst deviation from the curves: (\S+) rad", err).group(1))  # type: ignore[union-attr]
    assert 0 < worst <= MAX_ERROR
    assert "checked against robot nao: clean" in err
    result = runner.invoke(app, ["validate", "--robot", "nao-v5", str(out)])
    assert result.exit_code == 0, result.output
    assert "0 errors, 0 warnings" in result.output


def test_choregraphes_own_handles_are_the_automatic_ones() -> None:
    """Welcoming.py is Aldebaran's Hello exported by Choregraphe, with the Bezier handles it
    computed for keys that had none; the timeline read with our automatic handles gives the
    same curves to the export's five decimals. The hands differ: the export gives them as
    the timeline's number taken as degrees (0.853478 -> 0.01490), the timeline reader as a
    fraction (open 0.85), so they are left out."""
    options = ImportOptions(timestep_ms=20, max_error_rad=0.0)
    exported = read_choregraphe_py(WELCOMING.read_bytes(), str(WELCOMING), options).motion
    timeline = read_timeline(HELLO.read_bytes(), str(HELLO), options).motion
    assert exported.joints == timeline.joints
    a, b = held_stream(exported, 20), held_stream(timeline, 20)
    assert np.array_equal(a.elapsed_ms, b.elapsed_ms)
    arms = [j for j, m in enumerate(a.motors) if "Phalanx" not in m]
    assert len(arms) == 12
    assert np.max(np.abs(a.targets[:, arms] - b.targets[:, arms])) < 1e-5  # rad


def test_the_hello_timeline_reads_within_the_maximum_error() -> None:
    """Aldebaran's Hello: 14 curves of 75 keys in degrees at 25 fps. The motion passes through
    every key (Choregraphe's curves do) within the maximum error, and its worst deviation from
    the curves at every control step is within it too."""
    imported = read_timeline(HELLO.read_bytes(), str(HELLO), ImportOptions(timestep_ms=20))
    s, motion = imported.sampled, imported.motion
    assert s is not None
    assert (s.keys, s.curves, s.what) == (75, 14, "a Choregraphe timeline at 25 fps")
    text = HELLO.read_text(encoding="utf-8")
    first = min(int(f) for f in re.findall(r'<Key frame="(\d+)"', text))
    assert s.start_s == pytest.approx(first / 25)  # the earliest key of any joint: 0 ms
    assert 0 < s.deviation.max_rad <= MAX_ERROR
    assert motion.n_poses < s.samples  # reduced
    # HeadYaw's keys (frame, degrees), as the file has them
    block = text[text.index('actuator="HeadYaw"') :].split("</ActuatorCurve>")[0]
    keys = [(int(f), float(v)) for f, v in re.findall(r'frame="(\d+)" value="([-\d.]+)"', block)]
    assert len(keys) == 6
    column = motion.joints.index("HeadYaw")
    for frame, degrees in keys:
        t_ms = (frame / 25 - s.start_s) * 1000
        got = np.interp(t_ms, motion.times_ms, motion.values[:, column])
        assert abs(got - math.radians(degrees)) <= MAX_ERROR + ROUNDING
    assert "LPhalanx8" in motion.joints and "LHand" not in motion.joints


def test_convert_prints_the_deviation_and_writes_a_valid_motion(tmp_path: Path) -> None:
    out = tmp_path / "hello.motion"
    code, err = _run(HELLO, out, "--max-error", "0.002")
    assert code == 0, err
    lines = err.splitlines()
    assert lines[1].startswith("read 75 keys of 14 joint curves (a Choregraphe timeline at 25 fps)")
    assert "sampled every 20 ms" in err and "reduced within 0.002 rad" in err
    worst = next(line for line in lines if line.startswith("worst deviation from the curves"))
    assert float(worst.split(": ")[1].split(" rad")[0]) <= 0.002
    result = read_bytes(out.read_bytes(), str(out))
    assert not [d for d in result.diagnostics if d.severity.name == "ERROR"]


def _one_motor_each(motion: Motion) -> bool:
    """Whether the joints a real NAO moves with one motor (a hand's phalanges, the two
    HipYawPitch) agree, as convert's robot checks require before a NAOqi export."""
    groups = [[f"{s}Phalanx{i}" for i in range(1, 9)] for s in "LR"]
    groups.append([leader for pair in COUPLED for leader in pair])
    for group in groups:
        present = [motion.joints.index(j) for j in group if j in motion.joints]
        if present and not (motion.values[:, present] == motion.values[:, present[:1]]).all():
            return False
    return True


@pytest.mark.parametrize("path", NAO_MOTIONS, ids=lambda p: p.name)
def test_a_motion_goes_through_choregraphe_python_and_back(path: Path) -> None:
    """motion -> Choregraphe Python (NAOqi's keys, times + lead-in) -> motion: Webots plays the
    result within the maximum error of the original at every control step."""
    original = _motion(path)
    if not _one_motor_each(original):
        pytest.skip("fingers or hips one motor drives apart: convert refuses it (robot checks)")
    exported = write_choregraphe_py(
        original, ExportOptions(timestep_ms=20, coupled_joints=COUPLED, source=path.name)
    )
    assert exported.deviation is not None and exported.deviation.max_rad <= ROUNDING
    back = read_choregraphe_py(exported.data, "x.py", ImportOptions(timestep_ms=20)).motion
    a, b = held_stream(original, 20), held_stream(back, 20)
    common = [m for m in a.motors if m in b.motors]
    assert len(common) == len(a.motors)  # the hands and the coupled hip come back
    assert np.array_equal(a.elapsed_ms, b.elapsed_ms)
    ia = [a.motors.index(m) for m in common]
    ib = [b.motors.index(m) for m in common]
    err = np.abs(a.targets[:, ia] - b.targets[:, ib])
    assert np.nanmax(err) <= MAX_ERROR + ROUNDING


def test_the_cli_round_trip_through_a_python_file(tmp_path: Path) -> None:
    wave = ROOT / "motions" / "nao" / "wave_left.motion"
    code, err = _run(wave, tmp_path / "wave.py")
    assert code == 0, err
    text = (tmp_path / "wave.py").read_text(encoding="utf-8")
    assert "motion.angleInterpolationBezier(names, times, keys)" in text
    compile(text, "wave.py", "exec")  # valid Python (never run here)
    code, err = _run(tmp_path / "wave.py", tmp_path / "back.motion")
    assert code == 0, err
    assert "its first key, at 1 s, is the motion's 0 ms" in err  # the lead-in comes off


CHOREGRAPHE_STYLE = """# Choregraphe bezier export in Python.
from naoqi import ALProxy
names = list()
times = list()
keys = list()

names.append("HeadPitch")
times.append([0.4, 0.8, 1.2])
keys.append([[-0.2, [3, -0.133333, 0], [3, 0.133333, 0]], [0.3, [3, -0.133333, -0.1], \\
[3, 0.133333, 0.1]], [0.5, [3, -0.133333, 0], [3, 0, 0]]])

names.append("LHand")
times.append([0.8])
keys.append([[0.75, [3, -0.266667, 0], [3, 0, 0]]])

try:
  motion = ALProxy("ALMotion", "127.0.0.1", 9559)
  motion.angleInterpolationBezier(names, times, keys)
except BaseException, err:
  print err
"""


def test_a_python2_export_is_read_without_running_it() -> None:
    """Choregraphe's own exports are Python 2 (no Python 3 parser takes them whole): the
    appends are read as literals; the keys are on the curve; LHand opens all eight phalanges."""
    imported = read_choregraphe_py(
        CHOREGRAPHE_STYLE.encode(), "e.py", ImportOptions(timestep_ms=20)
    )
    s, motion = imported.sampled, imported.motion
    assert s is not None and s.what.endswith("calling angleInterpolationBezier")
    assert s.start_s == pytest.approx(0.4) and s.keys == 4 and not s.notes
    pitch = motion.values[:, motion.joints.index("HeadPitch")]
    for t_ms, angle in ((0, -0.2), (400, 0.3), (800, 0.5)):
        assert np.interp(t_ms, motion.times_ms, pitch) == pytest.approx(angle, abs=MAX_ERROR)
    hand = motion.values[:, motion.joints.index("LPhalanx5")]
    assert np.all(hand == 0.75)  # one key: held from the start


def test_plain_angles_get_choregraphes_automatic_handles() -> None:
    """The simplified export (plain angles, for angleInterpolation): flat at a turning point
    and at the ends, no overshoot between monotonic keys."""
    src = (
        "names = list(); times = list(); keys = list()\n"
        'names.append("HeadYaw")\ntimes.append([1, 2, 3, 4])\nkeys.append([0, 1, 1.2, -1])\n'
        "motion.angleInterpolation(names, keys, times, True)\n"
    )
    imported = read_choregraphe_py(src.encode(), "s.py", ImportOptions(timestep_ms=10))
    assert imported.sampled is not None and imported.sampled.notes
    q = imported.motion.values[:, 0]
    assert q.max() <= 1.2 + MAX_ERROR and q.min() >= -1 - MAX_ERROR
    times, angles = [1.0, 2.0, 3.0, 4.0], [0.0, 1.0, 1.2, -1.0]
    assert auto_handles(times, angles, 2)[1][1] == 0.0  # 1.2 is a turning point
    assert auto_handles(times, angles, 0)[0] == (0.0, 0.0)
    before, after = auto_handles(times, angles, 1)
    assert 0 < after[1] <= 0.2 and before[1] < 0  # towards 1.2, shortened to not pass it


def test_linear_and_constant_tangents(tmp_path: Path) -> None:
    xar = (
        '<ChoregrapheProject><Box><Timeline fps="10"><ActuatorList>'
        '<ActuatorCurve actuator="HeadYaw" unit="1">'
        '<Key frame="10" value="0"><Tangent side="right" interpType="linear" '
        'abscissaParam="0" ordinateParam="0"/></Key>'
        '<Key frame="20" value="1"><Tangent side="left" interpType="linear" abscissaParam="0" '
        'ordinateParam="0"/><Tangent side="right" interpType="constant" abscissaParam="0" '
        'ordinateParam="0"/></Key><Key frame="30" value="2"/>'
        "</ActuatorCurve></ActuatorList></Timeline></Box></ChoregrapheProject>"
    )
    imported = read_timeline(xar.encode(), "t.xar", ImportOptions(timestep_ms=20, max_error_rad=0))
    m = imported.motion
    q = m.values[:, 0]
    at = dict(zip(m.times_ms.tolist(), q.tolist(), strict=True))
    assert at[0] == pytest.approx(0.0, abs=ROUNDING)
    assert at[1000] == pytest.approx(1.0, abs=ROUNDING)
    assert np.interp(500, m.times_ms, q) == pytest.approx(0.5, abs=ROUNDING)  # a line
    assert np.interp(1980, m.times_ms, q) == pytest.approx(1.0, abs=ROUNDING)  # held
    assert at[2000] == 2.0


def test_convert_from_lists_only_the_formats_it_can_read() -> None:
    result = runner.invoke(app, ["convert", "--help"], terminal_width=400)
    text = " ".join(result.output.split())
    assert (
        "Input format (motion, csv, npz, choregraphe, choregraphe-py, ros-trajectory, rosbag, "
        "rosbag-db3, rosbag1)" in text
    )
    assert "Output format (motion, csv, npz, naoqi, choregraphe-py, urscript," in text


BAD = [
    ("x.xar", b'<a><Timeline fps="25">\n<Key frame="1" value="1">\n</a>', r"x.xar:3:3: not well"),
    ("x.xar", b'<!DOCTYPE a [<!ENTITY e "x">]><a>&e;</a>', r"x.xar:1:\d+: an entity declaration"),
    (
        "x.xar",
        b'<Timeline fps="25"><ActuatorCurve actuator="HeadYaw"><Key frame="2.5" value="1"/>'
        b"</ActuatorCurve></Timeline>",
        r"x.xar:1:\d+: Key: frame='2.5': expected a whole frame number",
    ),
    ("x.py", b'names.append("HeadYaw"\ntimes.append([1])\n', r"x.py:1:13: Python syntax: names"),
    (
        "x.py",
        b'names.append("HeadYaw")\ntimes.append([1, 2])\nkeys.append([0.1])\n',
        r"x.py:3:13: keys of HeadYaw: 1 keys for its 2 times \(line 2\)",
    ),
    (
        "x.py",
        b'names.append("HeadYaw")\ntimes.append([1])\nkeys.append([[0.1, [3, 0], [3, 0, 0]]])\n',
        r"x.py:3:13: keys of HeadYaw: key 1 is .*: expected an angle, or \[angle",
    ),
    ("x.py", b'names.append("HeadYaw")\nkeys.append([0.1])\n', r"x.py:1:14: names.append without"),
    ("x.py", b"names.append(__import__('os'))\n", r"x.py:1:14: expected a literal"),
]


@pytest.mark.parametrize(("name", "data", "pattern"), BAD, ids=[b[2][:30] for b in BAD])
def test_bad_input_is_one_line_with_its_position(
    tmp_path: Path, name: str, data: bytes, pattern: str
) -> None:
    source, out = tmp_path / name, tmp_path / "out.motion"
    source.write_bytes(data)
    code, err = _run(source, out)
    assert code == 2
    assert err.count("\n") == 1 and "Traceback" not in err
    assert re.match(rf"motiontool: error: {re.escape(str(tmp_path))}/{pattern}", err), err
    assert not out.exists()
