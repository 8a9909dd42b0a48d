"""The left/right mirror map derived from model axes, and the unmirrored-copy note (MT309)."""

from __future__ import annotations

import hashlib
import shutil
from pathlib import Path

import numpy as np
import pytest
from conftest import CORPUS

from motiontool.errors import MotionToolError
from motiontool.kinematics.checks import RobotChecks, Wording
from motiontool.kinematics.checks.unmirrored import sibling_paths
from motiontool.kinematics.mirror import mirror_map, partner_name
from motiontool.kinematics.robots import JointSpec, RobotSpec, load_robot
from motiontool.motionfmt import loads
from motiontool.motionfmt.ops.mirror import mirror
from motiontool.motionfmt.validate import validate_paths

pytestmark = pytest.mark.usefixtures("corpus")

DANCING = CORPUS / "projects/robots/softbank/dancing_nao/motions"
NAO_MOTIONS = CORPUS / "projects/robots/softbank/nao/motions"
HAND_WAVE = CORPUS / "projects/robots/softbank/nao/controllers/nao_wave_hand/HandWave.motion"

#: Checked by hand against the Webots Nao PROTO's axes: a pitch axis (y) is its own mirror
#: image reversed, so the angle keeps its sign; roll (x) and yaw (z) axes lie in the mirror
#: plane, so the angle flips. HipYawPitch: L (0, .707, -.707), R (0, .707, .707), mirror
#: images reversed: keeps its sign (one motor drives both on the real robot).
NAO_EXPECTED = {
    "HeadYaw": ("HeadYaw", -1),
    "HeadPitch": ("HeadPitch", 1),
    "LShoulderPitch": ("RShoulderPitch", 1),
    "LShoulderRoll": ("RShoulderRoll", -1),
    "LElbowYaw": ("RElbowYaw", -1),
    "LElbowRoll": ("RElbowRoll", -1),
    "LWristYaw": ("RWristYaw", -1),
    "LHipYawPitch": ("RHipYawPitch", 1),
    "LHipRoll": ("RHipRoll", -1),
    "LHipPitch": ("RHipPitch", 1),
    "LKneePitch": ("RKneePitch", 1),
    "LAnklePitch": ("RAnklePitch", 1),
    "LAnkleRoll": ("RAnkleRoll", -1),
    "LPhalanx1": ("RPhalanx1", 1),
    "RShoulderRoll": ("LShoulderRoll", -1),
    "RHipYawPitch": ("LHipYawPitch", 1),
}


def test_nao_map_matches_the_hand_checked_table() -> None:
    derived = mirror_map(load_robot("nao")).as_dict()
    assert len(derived) == 40
    for joint, want in NAO_EXPECTED.items():
        assert derived[joint] == want, joint
    for joint, (partner, sign) in derived.items():  # an involution with one sign per pair
        assert derived[partner] == (joint, sign)
    # The arms' mirrored ranges are their partners' ranges: the PROTO's limits agree with the
    # derived signs (its hip roll and ankle ranges are not symmetric).
    spec = load_robot("nao")
    for joint in ("HeadYaw", "LShoulderPitch", "LShoulderRoll", "LElbowYaw", "LElbowRoll"):
        partner, sign = derived[joint]
        a, b = spec.joint(joint), spec.joint(partner)
        lo, hi = sorted((sign * a.lower, sign * a.upper))
        assert (lo, hi) == pytest.approx((b.lower, b.upper), abs=1e-6), joint


@pytest.mark.parametrize(
    ("name", "partner"),
    [
        ("LShoulderRoll", "RShoulderRoll"),
        ("RHipYawPitch", "LHipYawPitch"),
        ("l_hip_roll", "r_hip_roll"),
        ("leg_left_1_joint", "leg_right_1_joint"),
        ("arm_right_4_joint", "arm_left_4_joint"),
        ("knee_l", "knee_r"),
        ("HeadYaw", None),
        ("Lamp", None),
    ],
)
def test_partner_names(name: str, partner: str | None) -> None:
    assert partner_name(name) == partner


def _spec(path: Path, names: list[str], fmt: str = "mjcf") -> RobotSpec:
    joints = tuple(JointSpec(n, -1.0, 1.0, 1.0, 1.0) for n in names)
    digest = hashlib.sha256(path.read_bytes()).hexdigest()
    return RobotSpec(path.stem, path, digest, joints, 20, fmt)  # type: ignore[arg-type]


def test_signs_come_from_the_composed_axes_of_an_inline_mjcf(tmp_path: Path) -> None:
    # Left arm: body turned 90 deg about x, local axis y -> root axis z. Right arm: local axis
    # z reversed. (M a_L).a_R = (0,0,1).(0,0,-1) = -1: the angle keeps its sign. A centre
    # joint on a diagonal axis in the x-y plane cannot be mirrored.
    model = tmp_path / "toy.xml"
    model.write_text(
        """<mujoco><worldbody><body name="base">
        <body name="l" pos="0 0.1 0" quat="0.7071068 0.7071068 0 0">
          <joint name="LArm" axis="0 1 0"/></body>
        <body name="r" pos="0 -0.1 0"><joint name="RArm" axis="0 0 -1"/></body>
        <body name="c"><joint name="Twist" axis="1 0 0"/></body>
        </body></worldbody></mujoco>"""
    )
    m = mirror_map(_spec(model, ["LArm", "RArm", "Twist"])).as_dict()
    assert m == {"LArm": ("RArm", 1), "RArm": ("LArm", 1), "Twist": ("Twist", -1)}
    bad = tmp_path / "bad.xml"
    bad.write_text(
        '<mujoco><worldbody><body name="b"><joint name="Skew" axis="1 1 0"/></body>'
        "</worldbody></mujoco>"
    )
    with pytest.raises(MotionToolError, match=r"cannot be mirrored joint by joint.*Skew"):
        mirror_map(_spec(bad, ["Skew"]))


def test_signs_from_an_inline_urdf(tmp_path: Path) -> None:
    model = tmp_path / "toy.urdf"
    model.write_text(
        """<robot name="toy"><link name="base"/><link name="a"/><link name="b"/>
        <joint name="l_hip_roll" type="revolute"><parent link="base"/><child link="a"/>
          <origin xyz="0 0.1 0" rpy="0 0 3.141592653589793"/><axis xyz="1 0 0"/></joint>
        <joint name="r_hip_roll" type="revolute"><parent link="base"/><child link="b"/>
          <origin xyz="0 -0.1 0"/><axis xyz="1 0 0"/></joint></robot>"""
    )
    # The left frame is turned half a turn about z: its x axis points backwards, so the same
    # written axis is the mirror image reversed and the roll angle keeps its sign.
    m = mirror_map(_spec(model, ["l_hip_roll", "r_hip_roll"], "urdf"))
    assert m.as_dict() == {"l_hip_roll": ("r_hip_roll", 1), "r_hip_roll": ("l_hip_roll", 1)}


def test_mirror_of_handwave_differs_from_handwaveleft_in_shoulder_roll_only() -> None:
    nao = mirror_map(load_robot("nao")).as_dict()
    mirrored = mirror(loads(HAND_WAVE.read_bytes(), "HandWave.motion"), nao).document.motion
    left = loads((DANCING / "HandWaveLeft.motion").read_bytes(), "HandWaveLeft.motion").motion
    for joint in ("LShoulderPitch", "RShoulderPitch"):
        a, b = mirrored.values[:, mirrored.column(joint)], left.values[:, left.column(joint)]
        assert np.array_equal(a, b, equal_nan=True)
    roll_m = mirrored.values[:, mirrored.column("LShoulderRoll")]
    roll_l = left.values[:, left.column("LShoulderRoll")]
    assert (roll_m == -roll_l).all() and abs(roll_m).max() == 0.5


# --------------------------------------------------------------------------- MT309


def _mt309(*paths: Path) -> dict[str, list[str]]:
    report = validate_paths([str(p) for p in paths], checks=[RobotChecks("nao", ["limits"])])
    return {
        Path(f.path).name: [d.message for d in f.diagnostics if d.code == "MT309"]
        for f in report.files
    }


def test_siblings_are_the_other_side_then_no_side(tmp_path: Path) -> None:
    for name in ("WaveLeft", "WaveRight", "Wave", "wave_left"):
        (tmp_path / f"{name}.motion").write_bytes(b"")
    assert sibling_paths(tmp_path / "WaveLeft.motion") == [
        tmp_path / "WaveRight.motion",
        tmp_path / "Wave.motion",
    ]
    assert sibling_paths(tmp_path / "wave_left.motion") == []  # no wave_right, no wave_


def test_webots_handhigh_pair_are_unmirrored_copies_of_each_other() -> None:
    found = _mt309(DANCING / "HandHighLeft.motion", DANCING / "HandHighRight.motion")
    assert found["HandHighLeft.motion"] == [
        "looks like an unmirrored copy of HandHighRight.motion: LShoulderRoll (= RShoulderRoll"
        " of HandHighRight.motion) without the sign flip a left/right mirror needs (nao's joint"
        " axes)"
    ]
    assert len(found["HandHighRight.motion"]) == 1


def test_mt309_hint_uses_the_callers_words_only_when_given() -> None:
    left = str(DANCING / "HandHighLeft.motion")

    def hint(**words: str) -> str | None:
        wording = Wording(**words)
        report = validate_paths([left], checks=[RobotChecks("nao", ["limits"], wording=wording)])
        (note,) = [d for d in report.diagnostics if d.code == "MT309"]
        return note.hint

    assert hint() == (
        "the left/right mirror of HandHighRight.motion is the true one; if the motion is meant"
        " to be asymmetric, leave MT309 out"
    )
    assert hint(
        ignore_option="--ignore", mirror_command="motiontool mirror {source} -o {target}"
    ) == (
        "'motiontool mirror HandHighRight.motion -o HandHighLeft.motion' writes the true mirror;"
        " if the motion is meant to be asymmetric, --ignore MT309"
    )


def test_handwaveleft_beside_handwave_gets_the_note(tmp_path: Path) -> None:
    shutil.copy(HAND_WAVE, tmp_path)
    shutil.copy(DANCING / "HandWaveLeft.motion", tmp_path)
    found = _mt309(tmp_path)
    assert found["HandWave.motion"] == []  # no side word: it looks for no sibling
    assert len(found["HandWaveLeft.motion"]) == 1
    assert "copy of HandWave.motion: LShoulderRoll" in found["HandWaveLeft.motion"][0]


def test_a_true_mirror_and_real_left_right_pairs_get_no_note(tmp_path: Path) -> None:
    nao = mirror_map(load_robot("nao")).as_dict()
    right = loads((DANCING / "HandHighRight.motion").read_bytes(), "HandHighRight.motion")
    (tmp_path / "HandHighRight.motion").write_bytes(right.to_bytes())
    (tmp_path / "HandHighLeft.motion").write_bytes(mirror(right, nao).document.to_bytes())
    assert _mt309(tmp_path) == {"HandHighLeft.motion": [], "HandHighRight.motion": []}
    pairs = _mt309(
        DANCING / "SideStepLeft.motion",
        DANCING / "SideStepRight.motion",
        DANCING / "TurnLeft40.motion",
        DANCING / "TurnRight40.motion",
        NAO_MOTIONS / "TurnLeft60.motion",
        NAO_MOTIONS / "TurnRight60.motion",
    )
    assert all(v == [] for v in pairs.values()), pairs
