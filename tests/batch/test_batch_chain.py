"""Chains in a batch from the command line: ``--after FILE`` (every motion played after FILE, as
a motions.toml ``after``; a motion's own ``after`` wins) and ``--start-pose FILE[:POSE]``; both
in the cache key, every chain element named in every report."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from pathlib import Path

import jsonschema
import pytest
from typer.testing import CliRunner

from motiontool.cli import schemas
from motiontool.cli.app import app

pytestmark = pytest.mark.needs("sim")

runner = CliRunner()

NOD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,A,0,0\n00:00:300,B,0.6,-0.3\n00:00:600,C,0,0\n"
SHAKE = b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,A,0\n00:00:200,B,-0.5\n00:00:400,C,0\n"
LOOK = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,Ahead,0,0\n00:00:200,Left,1.5,0\n"


def batch(*args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, ["batch", "-j", "1", *args])
    return result.exit_code, result.stdout, result.stderr


@pytest.fixture
def motions(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    folder = tmp_path / "motions"
    folder.mkdir()
    (folder / "nod.motion").write_bytes(NOD)
    (folder / "shake.motion").write_bytes(SHAKE)
    (folder / "look.motion").write_bytes(LOOK)
    monkeypatch.chdir(tmp_path)
    return folder


def _runs(path: str) -> dict[str, dict]:  # type: ignore[type-arg]
    doc = json.loads(Path(path).read_text(encoding="utf-8"))
    jsonschema.validate(doc, schemas.load("batch"), registry=schemas.registry())
    return {Path(r["spec"]["path"]).name: r for r in doc["runs"]}


def test_after_plays_every_motion_after_the_file_and_every_report_names_the_chain(
    motions: Path,
) -> None:
    (motions / "motions.toml").write_text('[shake]\nafter = "nod"\n', encoding="utf-8")
    reports = ["--json", "b.json", "--markdown", "b.md", "--junit", "b.xml"]
    code, out, err = batch(
        "motions/look.motion", "motions/shake.motion", "--after", "motions/nod.motion",
        "--no-cache", *reports,
    )  # fmt: skip
    assert code == 0, out + err
    runs = _runs("b.json")
    look, shake = runs["look.motion"], runs["shake.motion"]
    assert look["spec"]["chain"] == ["motions/nod.motion"]  # --after
    assert shake["spec"]["chain"] == [str(Path("motions/nod.motion"))]  # its own after wins
    assert [f["path"] for f in look["report"]["files"]] == [
        "motions/nod.motion",
        "motions/look.motion",
    ]
    nod_run, look_run = look["report"]["files"]
    assert look_run["start_s"] == pytest.approx(nod_run["start_s"] + nod_run["duration_s"])
    assert nod_run["duration_s"] >= 0.6 and look_run["duration_s"] >= 0.2
    assert ["chain", True] in look["spec"]["options"]
    chained = "motions/nod.motion + motions/look.motion"
    assert any(line.startswith(chained) for line in out.splitlines()), out
    assert f"`{chained}`" in Path("b.md").read_text(encoding="utf-8")
    names = {c.get("name") for c in ET.parse("b.xml").getroot().iter("testcase")}
    assert f"{chained} [nao]" in names


def test_a_motion_with_its_own_after_keeps_it(motions: Path) -> None:
    (motions / "motions.toml").write_text('[shake]\nafter = "look"\n', encoding="utf-8")
    code, out, err = batch(
        "motions/shake.motion", "motions/look.motion", "--after", "motions/nod.motion",
        "--no-cache", "--json", "b.json",
    )  # fmt: skip
    assert code == 0, out + err
    runs = _runs("b.json")
    assert runs["shake.motion"]["spec"]["chain"] == [str(Path("motions/look.motion"))]
    assert runs["look.motion"]["spec"]["chain"] == ["motions/nod.motion"]


def test_start_pose_starts_every_run_there(motions: Path) -> None:
    """HeadYaw starts at 1.5 rad (look.motion's pose Left) and the motions command 0 at once:
    the tracking error says where the run started."""
    code, out, err = batch(
        "motions/nod.motion", "motions/shake.motion", "--start-pose", "motions/look.motion:Left",
        "--no-cache", "--json", "b.json",
    )  # fmt: skip
    assert code == 0, out + err
    runs = _runs("b.json")
    for run in runs.values():
        options = dict(run["spec"]["options"])
        assert options["start_pose"] == "motions/look.motion:Left"
        assert options["start_pose_joints"] == [["HeadYaw", 1.5], ["HeadPitch", 0.0]]
        assert run["report"]["options"]["start_pose"] == "motions/look.motion:Left"
        yaw = next(j for j in run["report"]["joints"] if j["name"] == "HeadYaw")
        assert yaw["max_error"] > 1.0, yaw
    code, out, err = batch("motions/nod.motion", "--no-cache", "--json", "plain.json")
    yaw = next(
        j for j in _runs("plain.json")["nod.motion"]["report"]["joints"] if j["name"] == "HeadYaw"
    )
    assert yaw["max_error"] < 0.5


def test_after_and_start_pose_are_in_the_cache_key(motions: Path) -> None:
    args = ["motions/shake.motion", "--cache-dir", "cache", "--json", "b.json"]

    def cached(*more: str) -> bool:
        code, out, err = batch(*args, *more)
        assert code in (0, 1), out + err
        return bool(_runs("b.json")["shake.motion"]["cached"])

    after = ("--after", "motions/nod.motion")
    assert not cached(*after) and cached(*after)
    assert not cached()  # without the chain: another run
    (motions / "nod.motion").write_bytes(NOD.replace(b"0.6,-0.3", b"0.5,-0.3"))
    assert not cached(*after)  # the chain's content changed
    pose = ("--start-pose", "motions/look.motion:Left")
    assert not cached(*pose) and cached(*pose)
    (motions / "look.motion").write_bytes(LOOK.replace(b"1.5,0", b"1.4,0"))
    assert not cached(*pose)  # the pose's joints changed


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--after", "nowhere.motion"], "cannot read 'nowhere.motion'"),
        (["--after", "motions/bad.motion"], "motions/bad.motion:2:"),
        (["--start-pose", "motions/look.motion:Right"], "--start-pose motions/look.motion:Right:"),
    ],
)
def test_a_bad_chain_option_is_one_line_before_anything_runs(
    motions: Path, args: list[str], message: str
) -> None:
    (motions / "bad.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,P1,abc\n")
    code, out, err = batch("motions/nod.motion", *args, "--no-cache")
    assert (code, out) == (2, "")
    assert err.startswith("motiontool: error: ") and message in err and err.count("\n") == 1
