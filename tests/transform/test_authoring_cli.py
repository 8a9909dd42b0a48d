"""The mirror, concat, trim and scale commands: reports, -o / --in-place, refusals."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from conftest import CORPUS
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.kinematics.robots import load_robot
from motiontool.motionfmt import loads

runner = CliRunner()
NAO = load_robot("nao").model_hash[:12]
HAND_WAVE = CORPUS / "projects/robots/softbank/nao/controllers/nao_wave_hand/HandWave.motion"
HAND_WAVE_LEFT = CORPUS / "projects/robots/softbank/dancing_nao/motions/HandWaveLeft.motion"

HEAD = (
    b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n"
    b"00:00:000,A,0,0\n00:00:100,B,0.20,*\n00:00:200,C,0.4,0.1\n00:00:400,D,-0.4,+0.1\n"
)
ARMS = (
    b"#WEBOTS_MOTION,V1.0,LShoulderRoll,RShoulderRoll\n00:00:000,A,0.2,-0.1\n00:00:500,B,1.0,-0.3\n"
)
OTHER = b"#WEBOTS_MOTION,V1.0,HeadPitch,HeadYaw\n0,E,0.1,1.2\n300,F,0.2,1.2\n"


@pytest.fixture
def here(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    for name, data in [("head.motion", HEAD), ("arms.motion", ARMS), ("other.motion", OTHER)]:
        (tmp_path / name).write_bytes(data)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def invoke(*args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, list(args))
    return result.exit_code, result.stdout, result.stderr


@pytest.mark.parametrize(
    "argv",
    [
        ["mirror", "head.motion"],
        ["trim", "head.motion", "--from", "10"],
        ["scale", "head.motion", "-k", "0.5"],
        ["concat", "head.motion", "other.motion"],
    ],
)
def test_every_authoring_command_needs_a_destination_and_never_overwrites_an_input(
    here: Path, argv: list[str]
) -> None:
    code, _, err = invoke(*argv)
    assert code == 2 and err.startswith("motiontool: error: say where to write the result: -o")
    code, _, err = invoke(*argv, "-o", "head.motion")
    assert code == 2 and "-o 'head.motion' is the input file" in err
    assert (here / "head.motion").read_bytes() == HEAD
    if argv[0] == "concat":
        code, _, err = invoke(*argv, "-o", "other.motion")
        assert code == 2 and "-o 'other.motion' is the input file" in err
        assert (here / "other.motion").read_bytes() == OTHER
    code, out, err = invoke(*argv, "-o", "-")
    assert code == 0, err
    assert out.startswith("#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n")  # the motion on stdout
    assert "-> stdout" in err  # the report on stderr
    code, _, err = invoke(*argv, "--in-place")
    assert code == 0, err
    assert (here / "head.motion").read_bytes() != HEAD
    assert not list(here.glob("*.tmp*")) and not list(here.glob(".*"))  # atomic: no leftovers


def test_mirror_report_and_show_map(here: Path) -> None:
    code, out, _ = invoke("mirror", "arms.motion", "-o", "m.motion")
    assert (code, out) == (
        0,
        f"mirrored arms.motion -> m.motion: robot nao (model {NAO})\n"
        "swapped: LShoulderRoll <-> RShoulderRoll\n"
        "negated (roll/yaw axes: their mirror turns the other way): LShoulderRoll, "
        "RShoulderRoll\n"
        "limits: every mirrored value within the partner's limits\n",
    )
    assert (here / "m.motion").read_bytes() == (
        b"#WEBOTS_MOTION,V1.0,LShoulderRoll,RShoulderRoll\n"
        b"00:00:000,A,0.1,-0.2\n00:00:500,B,0.3,-1.0\n"
    )
    code, out, _ = invoke("mirror", "--show-map", "--robot", "nao")
    assert code == 0
    assert "  LHipYawPitch -> RHipYawPitch: keeps its sign ((M a).b = -1)" in out.splitlines()
    assert "  HeadYaw -> HeadYaw: negated ((M a).b = +1)" in out.splitlines()
    code, _, err = invoke("mirror", "--show-map")
    assert code == 2 and "needs --robot NAME" in err


def test_mirror_twice_through_the_cli_gives_the_input_back(here: Path) -> None:
    assert invoke("mirror", "head.motion", "-o", "m.motion")[0] == 0
    assert invoke("mirror", "m.motion", "-o", "mm.motion", "-f", "json")[0] == 0
    assert (here / "mm.motion").read_bytes() == HEAD


def test_mirror_of_handwave_against_handwaveleft_shows_the_webots_bug(here: Path) -> None:
    shutil.copy(HAND_WAVE, here)
    shutil.copy(HAND_WAVE_LEFT, here)
    assert invoke("mirror", "HandWave.motion", "-o", "mirrored.motion")[0] == 0
    code, out, _ = invoke("diff", "mirrored.motion", "HandWaveLeft.motion")
    assert code == 1
    assert out.splitlines() == [
        "different: mirrored.motion -> HandWaveLeft.motion (tolerance 0.0001 rad, compared "
        "every 1 ms)",
        "joints added: RShoulderRoll",
        "joint columns re-ordered (the robot is commanded the same)",
        "joints commanded differently (largest |Δq| first):",
        "  LShoulderRoll  |Δq| 1 rad at 440 ms (old 0.5 rad, new -0.5 rad)",
        "2 other joints within 0.0001 rad",
    ]


def test_concat_report_and_json(here: Path) -> None:
    code, out, _ = invoke("concat", "head.motion", "other.motion", "-o", "c.motion")
    assert code == 0
    assert out.splitlines() == [
        "joined head.motion + other.motion -> c.motion: 6 poses, 920 ms",
        f"robot: nao (model {NAO}); transitions within 90% of maxVelocity",
        # HeadYaw -0.4 -> 1.2 rad: 1.6 / (0.9 x 8.26797 rad/s) = 215.02 ms -> 11 steps of
        # the Nao's 20 ms (216 ms at whole ms: every later pose time off the step, MT209)
        "transition into other.motion: 220 ms from 400 ms (fitted, limited by HeadYaw)",
        "columns put in the first file's order: other.motion",
        "velocity check (20 ms controller step): no warning in the transitions",
    ]
    joined = loads((here / "c.motion").read_bytes()).motion
    assert joined.times_ms.tolist() == [0, 100, 200, 400, 620, 920]
    assert invoke("validate", "c.motion", "--robot", "nao")[0] == 0  # no MT209
    code, out, _ = invoke("concat", "head.motion", "other.motion", "-t", "8", "-o", "c8.motion")
    assert code == 0 and "transition into other.motion: 216 ms from 400 ms" in out  # 27 x 8
    assert joined.joints == ("HeadYaw", "HeadPitch")
    code, out, _ = invoke(
        "concat",
        "head.motion",
        "other.motion",
        "--transition",
        "20",
        "-o",
        "d.motion",
        "-f",
        "json",
    )
    doc = json.loads(out)
    assert code == 1  # 1.6 rad in 20 ms: validate's velocity check finds the transition
    assert doc["transitions"][0]["duration_ms"] == 20 and not doc["transitions"][0]["fitted"]
    assert doc["transition_velocity_findings"][0]["code"] == "MT303"
    code, _, err = invoke("concat", "head.motion", "arms.motion", "-o", "e.motion")
    assert code == 2
    assert err == (
        "motiontool: error: arms.motion does not have the joints of head.motion: it lacks "
        "HeadYaw, HeadPitch and has LShoulderRoll, RShoulderRoll that the first does not; "
        "concat needs the same joints in every motion (add the missing columns, e.g. as '*')\n"
    )


def test_trim_times_and_errors(here: Path) -> None:
    code, out, _ = invoke(
        "trim", "head.motion", "--from", "0:050", "--to", "00:00:300", "-o", "t.motion"
    )
    assert code == 0
    assert out == (
        "trimmed head.motion -> t.motion: kept 50 ms to 300 ms\n"
        "poses: 2 of 4 kept, 2 boundary poses inserted (Webots' interpolation there, exact)\n"
        "times shifted 50 ms earlier (the result starts at 0 ms); duration 250 ms\n"
    )
    assert (here / "t.motion").read_bytes() == (
        b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n"
        b"00:00:000,Pose0ms,0.1,*\n00:00:050,B,0.20,*\n00:00:150,C,0.4,0.1\n"
        b"00:00:250,Pose250ms,0,0.1\n"
    )
    code, _, err = invoke("trim", "head.motion", "--from", "1.5s", "-o", "u.motion")
    assert code == 2 and err == (
        "motiontool: error: --from expects a time in ms (1500), s:ms (1:500) or m:s:ms "
        "(00:01:500), got '1.5s'\n"
    )
    code, _, err = invoke("trim", "head.motion", "--from", "500", "-o", "u.motion")
    assert code == 2 and "nothing to keep between 500 ms and 400 ms" in err


def test_scale_reports_clipping_with_units(here: Path) -> None:
    code, out, _ = invoke("scale", "arms.motion", "-k", "2", "--about", "zero", "-o", "s.motion")
    assert code == 0
    assert out.splitlines() == [
        "scaled arms.motion -> s.motion: amplitude x2 about the zero pose (0 rad)",
        "changed 4 cells",
        "clipped 1 cells to nao's limits:",
        "  LShoulderRoll: 1 cells, worst 0.67355 rad above its upper limit 1.32645 rad at 500 ms",
        "velocity check: no warning more than the input's",
    ]
    code, _, err = invoke("scale", "arms.motion", "-k", "2", "--about", "Nope", "-o", "s.motion")
    assert code == 2 and "no pose named 'Nope' in arms.motion" in err


def test_mirror_limit_findings_are_grouped_as_validate_groups_them(here: Path) -> None:
    """A mirrored file whose values fall past the partner's limits at many poses gets one
    finding per joint and bound (with how many poses it stands for), not one per value: a
    26 MB file of random values got 1.1 million lines and 1.8 GB before."""
    import numpy as np

    joints = [j.name for j in load_robot("nao").joints]
    rng = np.random.default_rng(7)
    rows = [
        ",".join([f"{40 * k}", f"P{k}", *(f"{v:.4f}" for v in rng.uniform(-2, 2, len(joints)))])
        for k in range(300)
    ]
    (here / "noisy.motion").write_text(
        "#WEBOTS_MOTION,V1.0," + ",".join(joints) + "\n" + "\n".join(rows) + "\n"
    )
    code, out, _ = invoke("mirror", "noisy.motion", "-o", "m.motion", "--robot", "nao")
    assert code == 1
    listed = [line for line in out.splitlines() if ": MT302: " in line]
    assert listed and any(" poses in " in line for line in listed)
    code, out, _ = invoke(
        "mirror", "noisy.motion", "-o", "m2.motion", "--robot", "nao", "-f", "json"
    )
    found = json.loads(out)["limit_findings"]
    assert len(found) == len(listed) and sum(f["count"] for f in found) > 10 * len(found)
    heading = next(
        line
        for line in invoke("mirror", "noisy.motion", "-o", "m3.motion")[1].splitlines()
        if line.startswith("limits:")
    )
    assert heading.startswith(f"limits: {sum(f['count'] for f in found)} mirrored values")
