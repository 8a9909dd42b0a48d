"""The diff, resample, retime and plot commands: golden outputs, never touching the input."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import corpus_params
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.kinematics import detect_robot, load_robot
from motiontool.motionfmt import read_bytes, read_file, read_motion

runner = CliRunner()

HEAD = (
    b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n"
    b"00:00:000,Pose1,0,0\n00:00:040,Pose2,0.20,*\n00:00:080,Pose3,0.4,0.1\n00:00:160,Pose4,0.4,+0.1\n"
)
# The same motion: columns swapped, times in ms, keyframes re-spaced on the same lines.
RESPELLED = (
    b"#WEBOTS_MOTION,V1.0,HeadPitch,HeadYaw\n"
    b"0,A,0,0\n40,B,*,0.2\n80,C,0.1,0.4\n120,D,0.1,0.4\n160,E,0.1,0.4\n"
)
CHANGED = (
    b"#WEBOTS_MOTION,V1.0,HeadYaw,LShoulderPitch\n"
    b"00:00:000,Pose1,0,0\n00:00:040,Pose2,0.25,*\n00:00:080,Pose3,0.4,1\n00:00:200,Pose4,0.4,1\n"
)
FAST = (
    b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n"
    b"00:00:000,Pose1,0,0\n00:00:040,Pose2,0.5,-0.2\n00:00:080,Pose3,1.2,-0.4\n"
)
NAO = load_robot("nao").model_hash[:12]


@pytest.fixture
def here(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    for name, data in [
        ("head.motion", HEAD),
        ("respelled.motion", RESPELLED),
        ("changed.motion", CHANGED),
        ("fast.motion", FAST),
    ]:
        (tmp_path / name).write_bytes(data)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def invoke(*args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, list(args))
    return result.exit_code, result.stdout, result.stderr


# --------------------------------------------------------------------------- diff


def test_diff_same_motion_spelt_differently(here: Path) -> None:
    code, out, _ = invoke("diff", "head.motion", "respelled.motion")
    assert code == 0
    assert out == (
        "same: head.motion and respelled.motion command the same motion "
        "(every joint within 0.0001 rad, compared every 1 ms)\n"
        "joint columns re-ordered (the robot is commanded the same)\n"
        "poses: 4 -> 5\n"
    )


def test_diff_of_a_file_with_itself_is_one_line(here: Path) -> None:
    assert invoke("diff", "head.motion", "head.motion") == (
        0,
        "same: head.motion and head.motion command the same motion "
        "(every joint within 0.0001 rad, compared every 1 ms)\n",
        "",
    )


def test_diff_different_both_ways(here: Path) -> None:
    code, out, _ = invoke("diff", "head.motion", "changed.motion")
    assert code == 1
    assert out == (
        "different: head.motion -> changed.motion (tolerance 0.0001 rad, compared every 1 ms)\n"
        "joints added: LShoulderPitch\n"
        "joints removed: HeadPitch\n"
        "duration: 160 ms -> 200 ms (+40 ms)\n"
        "joints commanded differently (largest |Δq| first):\n"
        "  HeadYaw  |Δq| 0.05 rad at 40 ms (old 0.2 rad, new 0.25 rad)\n"
    )
    code, out, _ = invoke("diff", "changed.motion", "head.motion")
    assert code == 1
    assert out.splitlines()[1:] == [
        "joints added: HeadPitch",
        "joints removed: LShoulderPitch",
        "duration: 200 ms -> 160 ms (-40 ms)",
        "joints commanded differently (largest |Δq| first):",
        "  HeadYaw  |Δq| 0.05 rad at 40 ms (old 0.25 rad, new 0.2 rad)",
    ]
    assert invoke("diff", "head.motion", "changed.motion", "--tolerance", "0.1")[0] == 1  # joints


def test_diff_json_and_timestep(here: Path) -> None:
    code, out, _ = invoke("diff", "head.motion", "changed.motion", "-f", "json", "-t", "20")
    assert code == 1
    doc = json.loads(out)
    assert doc["schema"] == "motiontool.diff" and doc["stamps"]["motiontool"]
    assert doc["same"] is False and doc["timestep_ms"] == 20
    assert doc["joints_added"] == ["LShoulderPitch"] and doc["joints_removed"] == ["HeadPitch"]
    assert doc["changed"] == ["HeadYaw"]
    (yaw,) = doc["joints"]
    assert yaw["at_ms"] == 40 and yaw["max_delta"] == pytest.approx(0.05)


def test_diff_errors_exit_2(here: Path) -> None:
    (here / "bad.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,A\n0,p,abc\n")
    code, _, err = invoke("diff", "head.motion", "bad.motion")
    assert code == 2 and err.startswith("motiontool: error: bad.motion:2:5:")
    code, _, err = invoke("diff", "head.motion", "missing.motion")
    assert code == 2 and "cannot read 'missing.motion'" in err


@pytest.mark.needs("plot")
def test_diff_plot(here: Path) -> None:
    code, _, _ = invoke("diff", "head.motion", "changed.motion", "--plot", "d.png")
    assert code == 1
    png = (here / "d.png").read_bytes()
    assert png.startswith(b"\x89PNG\r\n\x1a\n")
    code, _, err = invoke("diff", "head.motion", "changed.motion", "--plot", "head.motion")
    assert code == 2 and "--plot 'head.motion' is the input file; write the PNG" in err
    assert (here / "head.motion").read_bytes() == HEAD


@pytest.mark.needs("plot")
def test_diff_plot_of_motions_playing_for_hours(here: Path) -> None:
    """10 hours at 1 ms are 36 million steps: the plot draws the steps that shape the lines
    (held_pair), not all of them, so it is drawn rather than refused."""
    (here / "a.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,P1,0\n600:00:000,P2,0.5\n")
    (here / "b.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,P1,0\n600:00:000,P2,0.4\n")
    code, _, err = invoke("diff", "a.motion", "b.motion", "--plot", "long.png")
    assert code == 1, err
    assert (here / "long.png").read_bytes().startswith(b"\x89PNG\r\n\x1a\n")


# --------------------------------------------------------------------------- resample


def test_resample_lossless_golden(here: Path) -> None:
    code, out, _ = invoke("resample", "head.motion", "--step", "20", "-o", "h20.motion")
    assert code == 0
    assert out == (
        "resampled head.motion -> h20.motion: 4 -> 9 poses\n"
        "grid: every 20 ms; it holds every original pose time, so the result is lossless "
        "(5 poses inserted on their segments)\n"
        "largest deviation from the original command stream: 5.55112e-17 rad "
        "(floating-point rounding only), compared every 1 ms\n"
    )
    assert (here / "h20.motion").read_bytes() == (
        b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n"
        b"00:00:000,Pose1,0,0\n"
        b"00:00:020,Pose20ms,0.1,*\n"
        b"00:00:040,Pose2,0.20,*\n"
        b"00:00:060,Pose60ms,0.30000000000000004,*\n"
        b"00:00:080,Pose3,0.4,0.1\n"
        b"00:00:100,Pose100ms,0.4,0.1\n"
        b"00:00:120,Pose120ms,0.4,0.1\n"
        b"00:00:140,Pose140ms,0.4,0.1\n"
        b"00:00:160,Pose4,0.4,+0.1\n"
    )
    assert invoke("diff", "head.motion", "h20.motion")[0] == 0


def test_resample_off_grid_reports_its_deviation(here: Path) -> None:
    code, out, _ = invoke("resample", "head.motion", "--step", "30", "-o", "h30.motion")
    assert code == 0
    assert out == (
        "resampled head.motion -> h30.motion: 4 -> 7 poses\n"
        "grid: every 30 ms; 2 original poses off the grid dropped, 5 poses inserted: NOT lossless\n"
        "largest deviation from the original command stream: 0.1 rad at 81 ms (HeadPitch), "
        "compared every 1 ms\n"
    )


def test_resample_max_error_golden(here: Path) -> None:
    code, out, _ = invoke("resample", "respelled.motion", "--max-error", "0", "-o", "small.motion")
    assert code == 0
    assert out == (
        "resampled respelled.motion -> small.motion: 5 -> 4 poses\n"
        "removed 1 of 5 keyframes (1 exactly collinear), keeping every joint within 0 rad\n"
        "largest deviation from the original command stream: 0 rad "
        "(floating-point rounding only), compared every 1 ms\n"
    )
    assert (here / "small.motion").read_bytes() == (
        b"#WEBOTS_MOTION,V1.0,HeadPitch,HeadYaw\n0,A,0,0\n40,B,*,0.2\n80,C,0.1,0.4\n160,E,0.1,0.4\n"
    )


def test_resample_json(here: Path) -> None:
    code, out, _ = invoke(
        "resample",
        "head.motion",
        "--step",
        "20",
        "--max-error",
        "0.01",
        "-o",
        "x.motion",
        "-f",
        "json",
    )
    assert code == 0
    doc = json.loads(out)
    assert doc["schema"] == "motiontool.resample" and doc["grid_has_keyframes"] is True
    assert doc["poses"] == {"old": 4, "new": 4} and doc["removed"] == 5


# --------------------------------------------------------------------------- retime


def test_retime_speed_and_duration_golden(here: Path) -> None:
    code, out, _ = invoke("retime", "head.motion", "--speed", "0.5", "-o", "slow.motion")
    assert code == 0
    assert out == (
        "retimed head.motion -> slow.motion: speed x0.5\n"
        "pose times rounded to whole ms: at most 0 ms from exact scaling\n"
        "duration: 160 ms -> 320 ms (+160 ms, +100.0%)\n"
    )
    assert (here / "slow.motion").read_bytes() == HEAD.replace(b"00:00:160", b"00:00:320").replace(
        b"00:00:080", b"00:00:160"
    ).replace(b"00:00:040", b"00:00:080")
    code, out, _ = invoke("retime", "head.motion", "--duration", "100", "-o", "d.motion")
    assert code == 0
    assert out.splitlines()[-1] == "duration: 160 ms -> 100 ms (-60 ms, -37.5%)"
    assert read_motion("d.motion").times_ms.tolist() == [0, 25, 50, 100]


def test_retime_refuses_times_past_int_max(here: Path) -> None:
    code, out, err = invoke("retime", "head.motion", "--speed", "1e-9", "-o", "x.motion")
    assert (code, out) == (2, "")
    assert err.startswith("motiontool: error: retiming ") and err.count("\n") == 1
    assert "the last pose at 160000000000 ms, past the longest time" in err
    assert "2147483647 ms" in err
    assert not (here / "x.motion").exists() and (here / "head.motion").read_bytes() == HEAD
    # A duration past it is out of --duration's range: refused as the option is read.
    code, out, err = invoke("retime", "head.motion", "--duration", "99999999999", "-o", "x.motion")
    assert (code, out) == (2, "") and "not in the range 0<=x<=2147483647" in err
    assert not (here / "x.motion").exists()
    # The limit itself is a time Webots reads: written, and it validates.
    assert invoke("retime", "head.motion", "--duration", "2147483647", "-o", "x.motion")[0] == 0
    assert invoke("validate", "--robot", "none", "x.motion")[0] == 0


def test_a_move_too_long_for_any_time_is_one_error_and_validate_still_reports_it(
    here: Path,
) -> None:
    """A move of 1e306 rad needs more ms than a float can count: retime --fit-limits refuses it
    in one line (it raised OverflowError from math.ceil), and validate reports the file, its
    MT303 without a stretch fix until the clamp has brought the value within the limit."""
    (here / "far.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n40,B,1e306\n")
    code, out, err = invoke("retime", "far.motion", "--fit-limits", "-o", "x.motion")
    assert (code, out) == (2, "")
    assert err.startswith("motiontool: error: fitting the velocity limits") and err.count("\n") == 1
    assert not (here / "x.motion").exists()
    code, out, _err = invoke("validate", "--robot", "nao", "-f", "json", "far.motion")
    assert code == 1
    assert {d["code"] for f in json.loads(out)["files"] for d in f["diagnostics"]} >= {"MT303"}
    assert invoke("validate", "--robot", "nao", "--fix", "--unsafe-fixes", "far.motion")[0] == 0
    assert (here / "far.motion").read_bytes().endswith(b",B,2.08567\n")


def test_retime_library_raises_time_overflow_for_every_caller() -> None:
    from motiontool.errors import MotionToolError
    from motiontool.motionfmt.retime import (
        MAX_TIME_MS,
        TimeOverflowError,
        fit_duration,
        fit_limits,
        scale_times,
    )

    assert MAX_TIME_MS == 2**31 - 1 and issubclass(TimeOverflowError, MotionToolError)
    with pytest.raises(TimeOverflowError) as caught:
        scale_times([0, 160], 1e-9)
    assert caught.value.last_ms == 160_000_000_000
    with pytest.raises(TimeOverflowError):
        fit_duration([0, 160], MAX_TIME_MS + 1)
    assert fit_duration([0, 160], MAX_TIME_MS).times_ms == (0, MAX_TIME_MS)
    with pytest.raises(TimeOverflowError, match="fitting the velocity limits"):
        fit_limits([0, 40], ["HeadYaw"], [[0.0], [1.0]], {"HeadYaw": 1e-9})


def test_retime_fit_limits_golden_and_idempotent(here: Path) -> None:
    code, out, _ = invoke("retime", "fast.motion", "--fit-limits", "-o", "safe.motion")
    assert code == 0
    assert out == (
        "retimed fast.motion -> safe.motion: fit to nao's limits\n"
        f"robot: nao (model {NAO}); velocity within 90% of maxVelocity\n"
        "stretched 2 of 2 segments:\n"
        "  0 ms to 40 ms (poses 1 to 2): 40 ms -> 80 ms, HeadYaw (velocity)\n"
        "  40 ms to 80 ms (poses 2 to 3): 40 ms -> 100 ms, HeadYaw (velocity)\n"
        "duration: 80 ms -> 180 ms (+100 ms, +125.0%)\n"
        "velocity check (20 ms controller step): no warning\n"
    )
    # Whole 20 ms steps (68 and 95 ms would do at whole ms): pose times on the step stay on it.
    assert (here / "safe.motion").read_bytes() == (
        b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n"
        b"00:00:000,Pose1,0,0\n00:00:080,Pose2,0.5,-0.2\n00:00:180,Pose3,1.2,-0.4\n"
    )
    code, out, _ = invoke("retime", "safe.motion", "--fit-limits", "-o", "again.motion")
    assert code == 0 and "stretched 0 of 2 segments\n" in out
    assert (here / "again.motion").read_bytes() == (here / "safe.motion").read_bytes()
    # validate (at the robot's step without -t) finds nothing: within the limits, and the
    # stretched times on the Nao's 20 ms step (whole ms had given two MT209 warnings).
    code, out, _ = invoke("validate", "--checks", "velocity", "safe.motion")
    assert code == 0 and out.endswith("0 errors, 0 warnings, 0 notes\n"), out
    # At -t 8 (a step the file's 40 ms segments are whole numbers of), whole 8 ms steps.
    code, out, _ = invoke("retime", "fast.motion", "--fit-limits", "-t", "8", "-o", "s8.motion")
    assert code == 0 and "40 ms -> 72 ms" in out and "40 ms -> 96 ms" in out


def test_retime_accel_and_json(here: Path) -> None:
    code, out, _ = invoke(
        "retime",
        "fast.motion",
        "--fit-limits",
        "--accel",
        "100",
        "--margin",
        "1",
        "-o",
        "a.motion",
        "-f",
        "json",
    )
    assert code == 0
    doc = json.loads(out)
    assert doc["schema"] == "motiontool.retime" and doc["stamps"]["model_sha256"].startswith(NAO)
    assert doc["times_ms"] == [0, 120, 240]  # on the 20 ms step (whole ms: 0, 101, 220)
    assert [s["reason"] for s in doc["stretches"]] == ["acceleration", "acceleration"]
    assert doc["remaining_velocity_findings"] == []


def test_retime_usage_errors(here: Path) -> None:
    code, _, err = invoke("retime", "head.motion", "-o", "x.motion")
    assert code == 2 and "exactly one of --speed, --duration or --fit-limits" in err
    code, _, err = invoke(
        "retime", "head.motion", "--speed", "2", "--duration", "9", "-o", "x.motion"
    )
    assert code == 2 and "(got --speed and --duration)" in err
    code, _, err = invoke("retime", "head.motion", "--speed", "2", "--accel", "9", "-o", "x.motion")
    assert code == 2 and "--accel applies to --fit-limits only" in err
    code, _, err = invoke(
        "retime", "head.motion", "--fit-limits", "--margin", "0", "-o", "x.motion"
    )
    assert code == 2 and "margin must be in (0, 1]" in err
    (here / "hex.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,leg0\n0,p,0\n100,q,1\n")
    code, _, err = invoke("retime", "hex.motion", "--fit-limits", "-o", "x.motion")
    assert code == 2 and "name one with --robot" in err
    assert not (here / "x.motion").exists()


# --------------------------------------------------------------------------- writing


@pytest.mark.parametrize(
    "command",
    [
        ["resample", "head.motion", "--step", "20"],
        ["resample", "head.motion", "--max-error", "0.01"],
        ["retime", "head.motion", "--speed", "0.5"],
        ["retime", "head.motion", "--duration", "1000"],
        ["retime", "head.motion", "--fit-limits"],
    ],
)
def test_input_is_never_modified_without_in_place(here: Path, command: list[str]) -> None:
    source = here / "head.motion"
    before = source.stat().st_mtime_ns
    code, _, err = invoke(*command)
    assert code == 2 and "-o FILE, -o - for stdout, or --in-place" in err
    for same in ("head.motion", "./head.motion", str(source), str(here / "." / "head.motion")):
        code, _, err = invoke(*command, "-o", same)
        assert code == 2 and "is the input file" in err and "; add --in-place" in err
    code, _, err = invoke(*command, "-o", "other.motion", "--in-place")
    assert code == 2 and "give one of them" in err
    assert invoke(*command, "-o", "out.motion")[0] == 0
    assert source.read_bytes() == HEAD and source.stat().st_mtime_ns == before
    code, out, err = invoke(*command, "-o", "-")
    assert (
        code == 0 and out.startswith("#WEBOTS_MOTION") and err.startswith(("resampled", "retimed"))
    )
    assert out.encode() == (here / "out.motion").read_bytes()
    assert source.read_bytes() == HEAD
    assert invoke(*command, "--in-place")[0] == 0
    assert source.read_bytes() == (here / "out.motion").read_bytes()
    assert not list(here.glob(".*.tmp"))  # atomic writes leave no temporary file


# --------------------------------------------------------------------------- plot


@pytest.mark.needs("plot")
def test_plot_is_deterministic_and_reports(here: Path) -> None:
    code, out, err = invoke("plot", "fast.motion", "-o", "a.png")
    assert code == 0
    assert (out, err) == (
        "",
        f"motiontool: wrote a.png (PNG: 2 joints in 1 group; robot nao (model {NAO}); "
        "0 keyframe values outside the limits, 2 segments above maxVelocity)\n",
    )
    assert invoke("plot", "fast.motion", "-o", "b.png")[0] == 0
    a, b = (here / "a.png").read_bytes(), (here / "b.png").read_bytes()
    assert a.startswith(b"\x89PNG\r\n\x1a\n") and a == b
    code, _, err = invoke("plot", "head.motion", "-o", "c.png", "--robot", "none")
    assert code == 0 and err == (
        "motiontool: wrote c.png (PNG: 2 joints in 1 group; no robot: no limits; "
        "no robot limits drawn)\n"
    )
    code, _, err = invoke("plot", "head.motion", "-o", "head.motion")
    assert code == 2 and "is the input file" in err
    assert (here / "head.motion").read_bytes() == HEAD


@pytest.mark.needs("plot")
@pytest.mark.parametrize(
    ("raw", "shown"),
    [
        (b"Bad\xff\xfeName", b"Bad\\xff\\xfeName"),  # not UTF-8: kept as surrogates
        (b"a$\\frac$", None),  # drawn as typed, not as mathtext
    ],
)
def test_plot_and_diff_plot_draw_a_name_as_its_escaped_text(
    tmp_path: Path, raw: bytes, shown: bytes | None
) -> None:
    """A joint name matplotlib cannot draw as it is (a TypeError on the surrogate of an
    undecodable byte, a ParseSyntaxException on '$\\frac$' read as mathtext) is drawn as its
    text, escaped: the very PNG of a file whose joint is named that text."""
    pngs = []
    for name, label in [("raw", raw), ("shown", shown)]:
        if label is None:
            continue
        (tmp_path / name).mkdir()
        old, new = tmp_path / name / "a.motion", tmp_path / name / "b.motion"
        old.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw,%s\n0,P1,0,0\n1000,P2,0.5,0.3\n" % label)
        new.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw,%s\n0,P1,0,0\n1000,P2,0.5,0.4\n" % label)
        code, _, err = invoke("plot", str(old), "-o", str(tmp_path / name / "p.png"))
        assert code == 0, err
        plot = str(tmp_path / name / "d.png")
        code, _, err = invoke("diff", str(old), str(new), "--plot", plot, "-f", "json")
        assert code == 1, err
        pngs.append([(tmp_path / name / png).read_bytes() for png in ("p.png", "d.png")])
    assert all(png.startswith(b"\x89PNG") for png in pngs[0])
    assert shown is None or pngs[0] == pngs[1]


def test_limb_groups_for_the_nao() -> None:
    from motiontool.cli._plotting import limb_groups, panels_for

    nao = load_robot("nao")
    joints = [
        "RKneePitch",
        "HeadYaw",
        "LPhalanx2",
        "LShoulderPitch",
        "LPhalanx1",
        "Custom",
        "LElbowRoll",
    ]
    assert limb_groups(joints, "nao", nao.joint_names) == [
        ("head", ["HeadYaw"]),
        ("left arm", ["LShoulderPitch", "LElbowRoll"]),
        ("right leg", ["RKneePitch"]),
        ("hands", ["LPhalanx1", "LPhalanx2"]),
        ("other", ["Custom"]),
    ]
    assert limb_groups(joints, None) == [("joints", list(joints))]
    (hand,) = panels_for(["LPhalanx1", "LPhalanx2"])
    assert (hand.title, hand.joints) == ("LPhalanx1 to LPhalanx2", ["LPhalanx1", "LPhalanx2"])


def test_plot_draws_a_held_span_over_star_but_not_over_a_nan_command() -> None:
    from motiontool.cli._held_lines import held_lines

    motion = read_bytes(b"#WEBOTS_MOTION,V1.0,A,B\n0,P1,0,0\n100,P2,nan,*\n").motion
    (_, ya), (xb, yb) = held_lines(motion, 50)
    assert np.isnan(ya).all()  # A sends its NaN: nothing held to draw
    assert xb.tolist() == [0.0, 0.1] and yb.tolist() == [0.0, 0.0]  # B holds 0 from 0 s on


@pytest.mark.needs("plot")
def test_help_and_non_plot_commands_do_not_import_matplotlib(here: Path) -> None:
    code = (
        "import sys\nfrom motiontool.cli.app import app\n"
        "for argv in (['--help'], ['validate', 'head.motion'], ['diff', 'head.motion', 'respelled.motion'],"
        " ['resample', 'head.motion', '--step', '20', '-o', 'r.motion'],"
        " ['retime', 'head.motion', '--speed', '2', '-o', 's.motion']):\n"
        "    try:\n        app(argv, prog_name='motiontool')\n    except SystemExit:\n        pass\n"
        "print(sorted(m for m in sys.modules if m.split('.')[0] == 'matplotlib'))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=here
    ).stdout
    assert out.strip().splitlines()[-1] == "[]"


# --------------------------------------------------------------------------- corpus


@pytest.mark.parametrize("path", corpus_params())
def test_corpus_resample_retime_diff(path: Path, tmp_path: Path) -> None:
    source = str(path)
    before = read_file(source)
    motion = read_motion(source)
    step = int(np.gcd.reduce(motion.times_ms)) or 1
    out = tmp_path / "grid.motion"
    code, text, _ = invoke("resample", source, "--step", str(step), "-o", str(out))
    assert code == 0 and "lossless" in text
    assert invoke("diff", source, str(out), "--tolerance", "1e-12")[0] == 0
    assert invoke("diff", source, str(out), "-t", "20", "--tolerance", "1e-12")[0] == 0
    slow, back = tmp_path / "slow.motion", tmp_path / "back.motion"
    assert invoke("retime", source, "--speed", "0.5", "-o", str(slow))[0] == 0
    assert invoke("retime", str(slow), "--speed", "2", "-o", str(back))[0] == 0
    assert read_motion(str(back)).times_ms.tolist() == motion.times_ms.tolist()
    if detect_robot(motion.joints) is not None:
        safe, again = tmp_path / "safe.motion", tmp_path / "again.motion"
        assert invoke("retime", source, "--fit-limits", "-o", str(safe))[0] == 0
        assert invoke("retime", str(safe), "--fit-limits", "-o", str(again))[0] == 0
        assert again.read_bytes() == safe.read_bytes()
        code, report, _ = invoke("validate", "--checks", "velocity", "-f", "json", str(safe))
        codes = {d["code"] for f in json.loads(report)["files"] for d in f["diagnostics"]}
        assert not codes & {"MT303", "MT304"}
    assert read_file(source) == before


@pytest.mark.needs("plot")
def test_plot_draws_every_fast_segment_of_a_joint_as_one_artist() -> None:
    """A file of random values has millions of segments above maxVelocity: one line each took
    the plot of the 26 MB benchmark file past 20 GB; one broken line per joint draws them in
    27 s and 1 GB."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    from motiontool.cli._plotting import JointLimits, _mark_too_fast

    t = np.arange(600) * 0.04  # 1,800 points: a line drawn whole (cli/_plotting.py _SPANS)
    v = np.where(np.arange(600) % 2, 1.0, -1.0)  # every segment 50 rad/s
    fig, ax = plt.subplots()
    try:
        n = _mark_too_fast(ax, t, v, JointLimits(-2.0, 2.0, 5.0, "rad"))
        assert n == 599 and len(ax.lines) == 1
        x, y = ax.lines[0].get_data()
        assert np.isnan(x[2::3]).all() and list(x[:2]) == [0.0, 0.04] and list(y[:2]) == [-1, 1]
    finally:
        plt.close(fig)
