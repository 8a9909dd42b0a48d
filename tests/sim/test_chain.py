"""Chains and start states: ``play A B --chain`` plays the motions in one run,
each from the state the one before left (joints and the base: the physics goes on), an element
looped on its own (``--loop NAME=N``), the report naming every element with its time in the run
and what it did; ``--start-pose FILE[:POSE]`` starts from a pose instead of the zero stance."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import pytest
from typer.testing import CliRunner

from motiontool.cli import schemas
from motiontool.cli.app import app

pytestmark = pytest.mark.needs("sim")

runner = CliRunner()

NOD = b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,A,0\n00:00:300,B,0.5\n00:00:600,C,0\n"
RAISE = b"#WEBOTS_MOTION,V1.0,RShoulderPitch\n00:00:000,Down,0\n00:00:500,Up,-1\n"
# Knees bent, hips and ankles to keep the torso over the feet: the robot stands lower.
CROUCH = (
    b"#WEBOTS_MOTION,V1.0,LHipPitch,RHipPitch,LKneePitch,RKneePitch,LAnklePitch,RAnklePitch\n"
    b"00:00:000,Zero,0,0,0,0,0,0\n"
    b"00:00:500,Crouch,-0.8,-0.8,1.6,1.6,-0.8,-0.8\n"
    b"00:01:000,Half,-0.5,-0.5,1.0,1.0,-0.5,-0.5\n"
)


@pytest.fixture
def motions(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    for name, data in (("nod", NOD), ("raise", RAISE), ("crouch", CROUCH)):
        (tmp_path / f"{name}.motion").write_bytes(data)
    return tmp_path


def _play(*args: str, code: int = 0) -> dict[str, object]:
    result = runner.invoke(app, ["play", "--headless", "--json", "out.json", *args])
    assert result.exit_code == code, result.output
    doc: dict[str, object] = json.loads(Path("out.json").read_text(encoding="utf-8"))
    jsonschema.validate(doc, schemas.load("play"))
    return doc


def test_a_chain_loops_one_element_and_names_every_element(motions: Path) -> None:
    alone = _play("nod.motion", "--loop", "3", "--hold", "0")
    doc = _play("nod.motion", "raise.motion", "--chain", "--loop", "nod=3", "--hold", "0")
    files = doc["files"]
    assert isinstance(files, list)
    nod, up = files
    assert (nod["path"], nod["loops"], up["path"], up["loops"]) == (
        "nod.motion",
        3,
        "raise.motion",
        1,
    )
    assert nod["steps"] == alone["files"][0]["steps"]  # type: ignore[index]
    assert up["start_s"] == nod["duration_s"]  # raise starts where nod's third cycle ends
    assert doc["options"]["chain"] is True  # type: ignore[index]
    # Each element's base motion, from the frame it starts at to the frame it ends at: the
    # elements follow each other without a gap, so they add up to the run's.
    base = doc["base"]
    assert isinstance(base, dict)
    assert nod["dx_m"] + up["dx_m"] == pytest.approx(base["dx_m"], abs=1e-9)
    assert nod["yaw_change_deg"] + up["yaw_change_deg"] == pytest.approx(
        base["yaw_change_deg"], abs=1e-6
    )
    assert up["distance_m"] >= 0.0
    text = runner.invoke(
        app, ["play", "--headless", "nod.motion", "raise.motion", "--chain", "--loop", "nod=3"]
    ).stdout
    assert "chain: 2 elements" in text
    assert "  1. nod.motion x3: 0.00-1.86 s" in text
    assert "  2. raise.motion: 1.86-2.38 s" in text


def test_the_state_goes_on_from_one_element_to_the_next(motions: Path) -> None:
    # Crouching, then a nod that commands only the head: the legs hold where the crouch left
    # them (half bent), so the robot stays lower than after a nod alone.
    alone = _play("nod.motion")
    chain = _play("crouch.motion", "nod.motion", "--chain")
    assert chain["base"]["final_height_m"] < alone["base"]["final_height_m"] - 0.01  # type: ignore[index]


def test_loop_n_keeps_its_meaning_and_an_element_loop_needs_a_chain(motions: Path) -> None:
    doc = _play("nod.motion", "raise.motion", "--loop", "2")
    assert [f["loops"] for f in doc["files"]] == [2, 2]  # type: ignore[union-attr, index]
    for args, message in (
        (
            ["nod.motion", "--loop", "nod=3"],
            "motiontool: error: --loop nod=3 loops one element of a chain: pass --chain\n",
        ),
        (
            ["nod.motion", "raise.motion", "--chain", "--loop", "wave=3"],
            "motiontool: error: --loop wave=3: no element 'wave' in the chain "
            "(nod.motion, raise.motion)\n",
        ),
        (
            ["nod.motion", "--chain", "--loop", "nod=0"],
            "motiontool: error: --loop nod=0: not in the range 1<=x<=1000000\n",
        ),
    ):
        result = runner.invoke(app, ["play", "--headless", *args])
        assert (result.exit_code, result.stderr) == (2, message)


def test_start_pose_starts_from_a_pose_of_a_motion_file(motions: Path) -> None:
    standing = _play("nod.motion")
    crouched = _play("nod.motion", "--start-pose", "crouch.motion:Crouch")
    half = _play("nod.motion", "--start-pose", "crouch.motion")  # the last pose: Half
    stand_h = standing["base"]["final_height_m"]  # type: ignore[index]
    crouch_h = crouched["base"]["final_height_m"]  # type: ignore[index]
    half_h = half["base"]["final_height_m"]  # type: ignore[index]
    assert crouch_h < half_h - 0.005 < stand_h - 0.01
    assert crouched["options"]["start_pose"] == "crouch.motion:Crouch"  # type: ignore[index]
    result = runner.invoke(
        app, ["play", "--headless", "nod.motion", "--start-pose", "crouch.motion:Sit"]
    )
    assert (result.exit_code, result.stderr) == (
        2,
        "motiontool: error: --start-pose crouch.motion:Sit: no pose 'Sit' (poses: Zero, "
        "Crouch, Half)\n",
    )


def test_a_sidecar_after_makes_the_run_a_chain(motions: Path) -> None:
    (motions / "walk_Start.motion").write_bytes(CROUCH)
    (motions / "walk_Loop.motion").write_bytes(NOD)
    (motions / "walk_Stop.motion").write_bytes(RAISE)
    (motions / "motions.toml").write_text(
        '[walk_Loop]\nafter = "walk_Start"\nexpect = ["upright"]\n\n'
        '[walk_Stop]\nafter = "walk_Loop"\n\n[nod]\nafter = "gone"\n',
        encoding="utf-8",
    )
    doc = _play("walk_Stop.motion")
    assert [f["path"] for f in doc["files"]] == [  # type: ignore[union-attr, index]
        "walk_Start.motion",
        "walk_Loop.motion",
        "walk_Stop.motion",
    ]
    assert doc["options"]["chain"] is True  # type: ignore[index]
    loop = _play("walk_Loop.motion", "--chain", "--loop", "walk_Loop=2")
    assert [(f["path"], f["loops"]) for f in loop["files"]] == [  # type: ignore[union-attr, index]
        ("walk_Start.motion", 1),
        ("walk_Loop.motion", 2),
    ]
    assert [e["text"] for e in loop["expectations"]] == ["upright"]  # type: ignore[union-attr, index]
    alone = _play("walk_Loop.motion", "--no-sidecar")
    assert len(alone["files"]) == 1  # type: ignore[arg-type]
    result = runner.invoke(app, ["play", "--headless", "nod.motion"])
    assert (result.exit_code, result.stderr) == (
        2,
        "motiontool: error: motions.toml:9: after 'gone' in [nod]: no such motion (gone.motion)\n",
    )


def test_a_start_pose_for_another_robot_is_refused(motions: Path) -> None:
    (motions / "arm.motion").write_bytes(
        b"#WEBOTS_MOTION,V1.0,shoulder_pan_joint,elbow_joint\n00:00:000,Home,0.5,1.0\n"
    )
    result = runner.invoke(
        app, ["play", "--headless", "nod.motion", "--start-pose", "arm.motion:Home"]
    )
    assert (result.exit_code, result.stderr) == (
        2,
        "motiontool: error: start pose arm.motion:Home: none of its joints (shoulder_pan_joint,"
        " elbow_joint) is a motor of nao\n",
    )
