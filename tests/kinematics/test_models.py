"""The built-in robot models, their generator, robot loading and the Pinocchio kinematics."""

from __future__ import annotations

import itertools
import json
import math
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from conftest import ROBOT_FACTS

import motiontool.kinematics as kin
from motiontool.errors import MotionToolError
from motiontool.kinematics import _modelgen
from motiontool.kinematics._modelgen.inertia import balanced
from motiontool.kinematics._pinocchio.hull import convex_hull, signed_distance
from motiontool.kinematics.builtin_robots import BUILTIN_ROBOTS
from motiontool.kinematics.robots import (
    AUTO,
    NONE,
    NoRobotDetectedError,
    UnknownRobotError,
    builtin_robots,
    detect_robot,
    load_robot,
    models_dir,
    pick_robot,
    resolve_robot,
    robot_choices,
)

ROBOTS_DATA = ROBOT_FACTS  # vendored in tests/data/robot_facts
#: Skips with a reason if the JSON is missing; fails instead under CI=true (conftest.py).
needs_data = pytest.mark.usefixtures("robot_facts")

ZERO_POSE_TORSO_HEIGHT_M = 0.3339
NAO_TOTAL_MASS_KG = 5.3106
#: The Hinge2Joint helper frames weigh this much in the models instead of 0 (kg).
VIRTUAL_MASS_KG = 1e-6
#: A right arm folded across the belly: forearm and hand inside the torso's sphere.
ARM_IN_TORSO = {"RShoulderPitch": 1.4, "RShoulderRoll": 0.3, "RElbowYaw": 0.0, "RElbowRoll": 1.5}


def _json(name: str) -> dict:
    return json.loads((ROBOTS_DATA / f"{name}.json").read_text(encoding="utf-8"))


def _mujoco():
    import mujoco

    return mujoco


# --------------------------------------------------------------------------- generator


@needs_data
def test_generator_reproduces_committed_models_byte_for_byte():
    generated = _modelgen.generate(ROBOTS_DATA)
    assert sorted(generated) == ["nao-v5.json", "nao.xml", "ur5e.xml"]
    for name, text in generated.items():
        assert (models_dir() / name).read_bytes() == text.encode("utf-8"), (
            f"{name} is stale: python -m motiontool.kinematics._modelgen {ROBOTS_DATA} "
            "kinematics/models"
        )


@needs_data
def test_generator_check_mode_reports_stale_files(tmp_path):
    assert _modelgen.main([str(ROBOTS_DATA), str(tmp_path), "--check"]) == 1
    assert list(tmp_path.iterdir()) == []
    assert _modelgen.main([str(ROBOTS_DATA), str(tmp_path)]) == 0
    assert _modelgen.main([str(ROBOTS_DATA), str(tmp_path), "--check"]) == 0


def test_generator_takes_the_robot_facts_folder_as_an_argument(tmp_path, capsys):
    assert "<robots-dir>" in _modelgen.__doc__ and "/work/" not in _modelgen.__doc__
    with pytest.raises(SystemExit) as exc:  # an empty folder: no traceback, a usage error
        _modelgen.main([str(tmp_path), str(tmp_path / "models"), "--check"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "robots-dir output_dir" in err
    assert f"{tmp_path / 'nao.json'}: not found (robots-dir holds nao.json and ur5e.json)" in err


def test_triangle_inequality_correction_is_minimal():
    valid = {"ixx": 2.0, "iyy": 3.0, "izz": 4.0, "ixy": 0.0, "ixz": 0.0, "iyz": 0.0}
    assert balanced(valid) == ([2.0, 3.0, 4.0, 0.0, 0.0, 0.0], False)
    broken = {"ixx": 1.0, "iyy": 3.0, "izz": 5.0, "ixy": 0.0, "ixz": 0.0, "iyz": 0.0}
    full, corrected = balanced(broken)
    assert corrected
    assert full[:3] == pytest.approx([2.0, 3.0, 5.0], abs=1e-8)


# --------------------------------------------------------------------------- numbers vs JSON


#: The built-in robots with a model of their own (nao-v5 is nao's model with overrides).
OWN_MODEL = [r.name for r in BUILTIN_ROBOTS if r.overrides is None]


@needs_data
@pytest.mark.parametrize("robot", OWN_MODEL)
def test_every_motor_matches_the_json(robot):
    data = _json(robot)
    spec = load_robot(robot)
    expected = sorted(data["joints"], key=lambda j: j["tree_index"])
    assert spec.joint_names == tuple(j["name"] for j in expected)
    for joint in expected:
        got = spec.joint(joint["name"])
        assert (got.lower, got.upper) == (joint["minPosition"], joint["maxPosition"])
        assert got.max_velocity == joint["maxVelocity"]
        assert got.max_torque == joint["maxTorque"]
        assert (got.kind, got.unit) == ("hinge", "rad")


@pytest.mark.needs("sim")
@needs_data
@pytest.mark.parametrize("robot", OWN_MODEL)
def test_every_body_mass_matches_the_json(robot):
    mujoco = _mujoco()
    data = _json(robot)
    model = mujoco.MjModel.from_xml_path(str(models_dir() / f"{robot}.xml"))
    expected = {b["name"]: b["mass"] or 0.0 for b in data["bodies"]}
    for body in data["bodies"]:
        fsr = (body.get("rigidly_attached") or {}).get("force_sensor")
        if fsr:
            expected[fsr["device_name"]] = fsr["mass"]
    got = {model.body(i).name: float(model.body_mass[i]) for i in range(1, model.nbody)}
    assert sorted(got) == sorted(expected)
    for name, mass in expected.items():
        if mass == 0.0 and robot == "nao":
            assert got[name] == VIRTUAL_MASS_KG, name
        else:
            assert got[name] == pytest.approx(mass, rel=1e-12), name


@needs_data
def test_nao_v5_overrides_are_the_real_robot_limits():
    data = {j["name"]: j for j in _json("nao")["joints"]}
    v5 = load_robot("nao-v5")
    for joint in v5.joints:
        urdf = data[joint.name].get("ros_naoV50_urdf_limits")
        if urdf:
            assert (joint.lower, joint.upper) == (urdf["lower"], urdf["upper"])
            assert (joint.max_velocity, joint.max_torque) == (urdf["velocity"], urdf["effort"])
        else:  # fingers: the real robot's hand is one motor; Webots limits kept
            assert joint == load_robot("nao").joint(joint.name)


# --------------------------------------------------------------------------- MuJoCo / Pinocchio


@pytest.mark.needs("sim")
@pytest.mark.parametrize(("robot", "nq", "nv", "nu"), [("nao", 47, 46, 40), ("ur5e", 6, 6, 6)])
def test_mujoco_compiles_and_rests_without_contacts(robot, nq, nv, nu):
    mujoco = _mujoco()
    model = mujoco.MjModel.from_xml_path(str(models_dir() / f"{robot}.xml"))
    assert (model.nq, model.nv, model.nu) == (nq, nv, nu)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    assert data.ncon == 0
    assert all(w.number == 0 for w in data.warning)
    if robot == "nao":
        assert model.opt.jacobian == mujoco.mjtJacobian.mjJAC_DENSE
        assert model.body_mass.sum() == pytest.approx(NAO_TOTAL_MASS_KG, abs=5e-5)


@pytest.mark.needs("sim")
def test_mujoco_velocity_actuators_carry_the_limits():
    mujoco = _mujoco()
    model = mujoco.MjModel.from_xml_path(str(models_dir() / "nao.xml"))
    spec = load_robot("nao")
    for i in range(model.nu):
        joint = spec.joint(model.actuator(i).name)
        assert tuple(model.actuator_ctrlrange[i]) == (-joint.max_velocity, joint.max_velocity)
        assert tuple(model.actuator_forcerange[i]) == (-joint.max_torque, joint.max_torque)
        jid = model.actuator_trnid[i][0]
        assert model.joint(jid).name == joint.name
        assert tuple(model.jnt_range[jid]) == (joint.lower, joint.upper)
        assert tuple(model.jnt_actfrcrange[jid]) == (-joint.max_torque, joint.max_torque)


@pytest.mark.needs("sim")
def test_mujoco_zero_pose_torso_height():
    mujoco = _mujoco()
    model = mujoco.MjModel.from_xml_path(str(models_dir() / "nao.xml"))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    lowest = math.inf
    for foot in load_robot("nao").feet:
        g = model.geom(foot).id
        rot = data.geom_xmat[g].reshape(3, 3)
        for signs in itertools.product((-1, 1), repeat=3):
            corner = data.geom_xpos[g] + rot @ (np.array(signs) * model.geom_size[g])
            lowest = min(lowest, corner[2])
    height = data.body("torso").xpos[2] - lowest
    assert height == pytest.approx(ZERO_POSE_TORSO_HEIGHT_M, abs=1e-9)
    assert lowest == pytest.approx(0.0, abs=1e-9)  # spawned standing on z = 0


@pytest.mark.needs("kinematics", "sim")
@pytest.mark.parametrize(("robot", "nq", "nv"), [("nao", 47, 46), ("ur5e", 6, 6)])
def test_pinocchio_loads(robot, nq, nv):
    model, geoms = kin.build_model(load_robot(robot))
    assert (model.nq, model.nv) == (nq, nv)
    assert geoms.ngeoms > 0
    if robot == "nao":
        assert model.joints[1].shortname() == "JointModelFreeFlyer"
        total = sum(inertia.mass for inertia in model.inertias)
        assert total == pytest.approx(NAO_TOTAL_MASS_KG, abs=5e-5)


@pytest.mark.needs("kinematics", "sim")
def test_pinocchio_zero_pose_torso_height():
    soles = kin.sole_heights(load_robot("nao"), {})
    assert sorted(soles) == ["LFsr", "RFsr"]
    for z in soles.values():  # torso origin at z = 0
        assert -z == pytest.approx(ZERO_POSE_TORSO_HEIGHT_M, abs=1e-9)


@pytest.mark.needs("sim")
@pytest.mark.parametrize("robot", builtin_robots())
def test_mujoco_and_pinocchio_agree_on_forward_kinematics(robot):
    mujoco = _mujoco()
    spec = load_robot(robot)
    rng = np.random.default_rng(7)
    pose = {j.name: float(rng.uniform(j.lower, j.upper)) for j in spec.joints}
    model = mujoco.MjModel.from_xml_path(str(spec.model_path))
    data = mujoco.MjData(model)
    for name, value in pose.items():
        data.joint(name).qpos[0] = value
    if spec.floating_base:
        data.qpos[:3] = 0.0  # Pinocchio puts the root at the origin
    mujoco.mj_kinematics(model, data)
    positions = kin.body_positions(spec, pose)
    for i in range(1, model.nbody):
        name = model.body(i).name
        np.testing.assert_allclose(positions[name], data.xpos[i], atol=1e-12, err_msg=name)


# --------------------------------------------------------------------------- load_robot


def test_builtin_robots_and_their_timesteps():
    assert builtin_robots() == ["nao", "nao-v5", "ur5e"]
    nao, v5, ur5e = (load_robot(name) for name in builtin_robots())
    assert (nao.default_timestep_ms, v5.default_timestep_ms, ur5e.default_timestep_ms) == (
        20,
        20,
        8,
    )
    assert len(nao.joints) == 40 and "RPhalanx3" in nao and "LPhalanx8" in nao
    assert ur5e.joint_names == (
        "shoulder_pan_joint",
        "shoulder_lift_joint",
        "elbow_joint",
        "wrist_1_joint",
        "wrist_2_joint",
        "wrist_3_joint",
    )
    assert nao.floating_base and not ur5e.floating_base
    assert nao.model_path == v5.model_path
    assert len({nao.model_hash, v5.model_hash, ur5e.model_hash}) == 3
    assert load_robot("nao") is nao  # cached per process


def test_nao_v5_overrides():
    nao, v5 = load_robot("nao"), load_robot("nao-v5")
    assert v5.joint("LHipPitch").lower == v5.joint("RHipPitch").lower == -1.53589
    assert nao.joint("LHipPitch").lower == -1.77378
    assert v5.joint("RElbowRoll").lower == 0.0349066
    assert v5.joint("LElbowRoll").upper == -0.0349066
    assert (nao.joint("RElbowRoll").lower, nao.joint("LElbowRoll").upper) == (0.0, 0.0)
    assert v5.joint("HeadYaw").max_torque == 1.547
    assert ("LHipYawPitch", "RHipYawPitch") in v5.coupled_joints
    assert ("RPhalanx1", "RPhalanx8") in v5.coupled_joints
    assert nao.coupled_joints == () and nao.head_pitch_envelope == ()
    assert nao.head_pitch_limits(0.0) is None


def test_head_pitch_envelope_interpolates():
    v5 = load_robot("nao-v5")
    rows = v5.head_pitch_envelope
    assert len(rows) == 13 and list(rows) == sorted(rows)
    for yaw, low, high in rows:
        assert v5.head_pitch_limits(yaw) == pytest.approx((low, high))
    (y0, lo0, hi0), (y1, lo1, hi1) = rows[6], rows[7]
    mid = v5.head_pitch_limits((y0 + y1) / 2)
    assert mid == pytest.approx(((lo0 + lo1) / 2, (hi0 + hi1) / 2))
    assert v5.head_pitch_limits(-10.0) == pytest.approx(rows[0][1:])
    assert v5.head_pitch_limits(10.0) == pytest.approx(rows[-1][1:])


@pytest.mark.needs("erd", "kinematics")
def test_load_robot_from_example_robot_data():
    spec = load_robot("erd:ur5")
    assert spec.name == "erd:ur5" and spec.model_format == "urdf"
    assert spec.joint_names[0] == "shoulder_pan_joint" and len(spec.joints) == 6
    assert all(math.isfinite(j.lower) and j.max_velocity > 0 for j in spec.joints)


URDF = """\
<robot name="tiny">
  <link name="base"/>
  <link name="arm">
    <inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/>
    </inertial>
    <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
  </link>
  <link name="slider">
    <inertial><mass value="0.5"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/>
    </inertial>
  </link>
  <link name="wheel">
    <inertial><mass value="0.1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/>
    </inertial>
  </link>
  <joint name="hinge" type="revolute">
    <parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1.5" upper="1.25" velocity="3" effort="7"/>
  </joint>
  <joint name="rail" type="prismatic">
    <parent link="arm"/><child link="slider"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="0.2" velocity="0.5" effort="40"/>
  </joint>
  <joint name="spin" type="continuous">
    <parent link="slider"/><child link="wheel"/><axis xyz="0 1 0"/>
  </joint>
</robot>
"""


@pytest.mark.needs("kinematics", "sim")
def test_load_robot_from_a_urdf_file(tmp_path):
    path = tmp_path / "tiny.urdf"
    path.write_text(URDF, encoding="utf-8")
    spec = load_robot(str(path))
    assert spec.name == "tiny" and spec.model_format == "urdf" and not spec.floating_base
    hinge, rail, spin = spec.joints
    assert hinge == kin.JointSpec("hinge", -1.5, 1.25, 3.0, 7.0, "hinge", "rad")
    assert rail == kin.JointSpec("rail", 0.0, 0.2, 0.5, 40.0, "slide", "m")
    assert (spin.lower, spin.upper, spin.max_velocity) == (-math.inf, math.inf, math.inf)
    assert kin.self_collisions(spec, {"hinge": 1.0, "spin": 0.5}) == []


MJCF = """\
<mujoco model="pendulum">
  <compiler angle="degree"/>
  <worldbody>
    <body name="link" pos="0 0 1">
      <joint name="swing" type="hinge" axis="0 1 0" range="-90 45" actuatorfrcrange="-2 2"/>
      <geom type="capsule" size="0.02 0.2" mass="1"/>
    </body>
  </worldbody>
  <actuator><velocity joint="swing" ctrlrange="-4 4"/></actuator>
</mujoco>
"""


@pytest.mark.needs("kinematics", "sim")
def test_load_robot_from_an_mjcf_file(tmp_path):
    path = tmp_path / "pendulum.xml"
    path.write_text(MJCF, encoding="utf-8")
    spec = load_robot(str(path))
    (swing,) = spec.joints  # MJCF angles default to degrees; limits come back in rad
    assert swing == kin.JointSpec("swing", -math.pi / 2, math.pi / 4, 4.0, 2.0, "hinge", "rad")
    assert spec.default_timestep_ms == 32  # Webots' WorldInfo default
    shipped = load_robot(str(models_dir() / "nao.xml"))  # through Pinocchio this time
    assert shipped.joints == load_robot("nao").joints


@pytest.mark.parametrize(
    ("spec", "message"),
    [
        (
            "nao5",
            "unknown robot 'nao5'; did you mean 'nao'? choose nao, nao-v5, ur5e, a .urdf/.xml"
            " path, or erd:<name>",
        ),
        (
            "pepper",
            "unknown robot 'pepper'; choose nao, nao-v5, ur5e, a .urdf/.xml path, or erd:<name>",
        ),
        ("missing.urdf", "robot model file 'missing.urdf' not found"),
    ],
)
def test_load_robot_errors(spec, message):
    with pytest.raises(MotionToolError) as info:
        load_robot(spec)
    assert str(info.value) == message


@pytest.mark.needs("kinematics")
def test_load_robot_errors_on_unknown_erd_and_broken_files(tmp_path):
    if kin.erd_robot_names():
        with pytest.raises(MotionToolError, match=r"did you mean 'erd:ur5'\?"):
            load_robot("erd:ur55")
    broken = tmp_path / "broken.urdf"
    broken.write_text("<robot name='x'><joint name='j' type='revolute'/></robot>", "utf-8")
    with pytest.raises(MotionToolError, match="cannot load robot model"):
        load_robot(str(broken))


@pytest.mark.needs("kinematics")
def test_unknown_joint_names_the_closest_motor():
    with pytest.raises(
        MotionToolError, match=r"unknown joint 'HeadYw' for robot nao; did you mean 'HeadYaw'\?"
    ):
        load_robot("nao").joint("HeadYw")
    with pytest.raises(MotionToolError, match="did you mean 'HeadYaw'"):
        kin.self_collisions(load_robot("nao"), {"HeadYw": 0.1})


# --------------------------------------------------------------------------- detect_robot


def test_detect_robot():
    nao = load_robot("nao").joint_names
    assert detect_robot(nao) == "nao"
    assert detect_robot(["HeadYaw", "RPhalanx3", "LKneePitch"]) == "nao"
    assert detect_robot(load_robot("ur5e").joint_names[:3]) == "ur5e"
    assert detect_robot(["HeadYaw", "elbow_joint"]) is None  # a tie: the file does not say
    assert detect_robot(["LHand"]) is None
    assert detect_robot([]) is None


def test_detect_robot_survives_a_typo_but_not_a_foreign_file():
    # One misspelt name must not lose the robot (and with it every robot check).
    assert detect_robot(["RShoulderPitch", "RShoulderRoll", "RElbowYaw", "RElbowRol"]) == "nao"
    assert detect_robot(["HeadYaw", "HeadYw"]) == "nao"  # half is enough
    assert detect_robot(["HeadYaw", "HeadYw", "Tail"]) is None  # less than half is not
    assert detect_robot(["shoulder_pan_joint", "elbow_jiont"]) == "ur5e"
    # A Darwin-OP motion has nothing of the Nao's.
    assert detect_robot(["ShoulderR", "ArmUpperR", "ArmLowerR", "PelvYR"]) is None


# --------------------------------------------------------------------------- resolve_robot


def test_robot_choices_is_the_one_list() -> None:
    assert robot_choices() == "nao, nao-v5, ur5e, a .urdf/.xml path, or erd:<name>"
    assert robot_choices(AUTO, NONE) == (
        "auto, none, nao, nao-v5, ur5e, a .urdf/.xml path, or erd:<name>"
    )


def test_resolve_robot_auto_named_and_several_motions() -> None:
    assert resolve_robot(AUTO, ["HeadYaw", "HeadYw"]) is load_robot("nao")
    assert resolve_robot("nao-v5", ["elbow_joint"]).name == "nao-v5"  # named: joints unused
    # Several motions: the joints of all of them, a name given twice counting once.
    both = ["HeadYaw", "Tail", "HeadYaw", "HeadPitch"]
    assert resolve_robot(AUTO, both).name == "nao"


def test_resolve_robot_errors_are_typed_and_carry_their_facts() -> None:
    with pytest.raises(UnknownRobotError) as unknown:
        resolve_robot("aut")
    assert unknown.value.choices == ("auto", "nao", "nao-v5", "ur5e")
    assert unknown.value.suggestion == "auto"
    assert str(unknown.value) == (
        "unknown robot 'aut'; did you mean 'auto'? choose auto, nao, nao-v5, ur5e, a .urdf/.xml"
        " path, or erd:<name>"
    )
    with pytest.raises(UnknownRobotError, match="choose auto, nao"):
        resolve_robot(NONE)  # where a robot is needed, none is no choice
    with pytest.raises(NoRobotDetectedError) as none_fits:
        resolve_robot(AUTO, ["HeadYaw", "HeadYw", "Tail"])
    err = none_fits.value
    assert isinstance(err, MotionToolError)
    assert (err.best, err.covered, err.missing, err.suggestion) == ("nao", 1, (1, 2), "HeadYaw")
    assert str(err) == (
        "no robot fits the motion: no built-in robot has half of its joints or more: nao has 1"
        " of 3, not 'HeadYw', 'Tail' (did you mean 'HeadYaw'?); name the robot explicitly (nao,"
        " nao-v5, ur5e, a .urdf/.xml path, or erd:<name>)"
    )
    assert "--" not in str(err)  # the library names no CLI flag
    tie = NoRobotDetectedError(["HeadYaw", "elbow_joint"])
    assert (tie.best, tie.tied) == ("nao", ("ur5e",))
    assert NoRobotDetectedError(["leg0"]).best is None


def test_pick_robot_is_optional() -> None:
    assert pick_robot(NONE, ["HeadYaw"]) is None
    assert pick_robot(AUTO, ["leg0"]) is None  # no robot fits: no robot, no error
    assert pick_robot(AUTO, ["HeadYaw"]) is load_robot("nao")
    with pytest.raises(UnknownRobotError) as info:
        pick_robot("nine")
    assert info.value.choices == ("auto", "none", "nao", "nao-v5", "ur5e")
    assert info.value.suggestion == "none"


# --------------------------------------------------------------------------- collisions, balance


@pytest.mark.needs("kinematics", "sim")
def test_no_self_collision_at_zero_pose():
    assert kin.self_collisions(load_robot("nao"), {}) == []
    assert kin.self_collisions(load_robot("ur5e"), {}) == []


@pytest.mark.needs("kinematics", "sim")
def test_arm_pushed_into_the_torso_collides():
    nao = load_robot("nao")
    pairs = kin.self_collisions(nao, ARM_IN_TORSO)
    assert ("r_forearm", "torso") in pairs and ("r_hand", "torso") in pairs
    depths = kin.self_collision_depths(nao, ARM_IN_TORSO)
    assert list(depths) == pairs and depths[("r_hand", "torso")] > 0.03
    deep = kin.self_collisions(nao, ARM_IN_TORSO, penetration_tolerance_m=0.03)
    assert ("r_hand", "torso") in deep and len(deep) < len(pairs)
    assert kin.self_collisions(load_robot("nao-v5"), ARM_IN_TORSO) == pairs


@pytest.mark.needs("kinematics", "sim")
def test_folded_ur5e_collides_with_itself():
    assert ("forearm_link", "shoulder_link") in kin.self_collisions(
        load_robot("ur5e"), {"elbow_joint": 3.0}
    )


@pytest.mark.needs("kinematics")
def test_self_collision_rejects_non_finite_positions():
    with pytest.raises(MotionToolError, match="not a position"):
        kin.self_collisions(load_robot("nao"), {"HeadYaw": math.nan})


@pytest.mark.needs("kinematics", "sim")
def test_zero_pose_is_statically_stable():
    com_xy, polygon, margin_mm = kin.com_and_support(load_robot("nao"), {})
    assert com_xy.shape == (2,) and polygon.shape == (6, 2)
    assert com_xy[1] == pytest.approx(0.0, abs=1e-9)
    # front edge of the FSR boxes: 0.02 + 0.0735 m ahead of the ankles
    assert margin_mm == pytest.approx((0.0935 - com_xy[0]) * 1000, abs=0.01)


@pytest.mark.needs("kinematics", "sim")
def test_standing_on_one_foot_moves_the_support():
    pose = {"LHipPitch": -0.6, "LKneePitch": 1.2, "LAnklePitch": -0.6}
    balance = kin.com_and_support(load_robot("nao"), pose)
    assert (balance.support_polygon[:, 1] < 0).all()  # only the right foot
    assert balance.margin_mm < 0  # centre of mass still between the feet


@pytest.mark.needs("kinematics")
def test_balance_needs_feet():
    with pytest.raises(MotionToolError, match="has no feet"):
        kin.com_and_support(load_robot("ur5e"), {})


def test_signed_distance_against_a_square():
    hull = convex_hull([(0, 0), (1, 0), (1, 1), (0, 1), (0.5, 0.5), (1, 0.5)])
    assert hull == [(0, 0), (1, 0), (1, 1), (0, 1)]
    assert signed_distance((0.5, 0.25), hull) == pytest.approx(0.25)
    assert signed_distance((2.0, 0.5), hull) == pytest.approx(-1.0)
    assert signed_distance((0.0, 0.0), [(3.0, 4.0)]) == pytest.approx(-5.0)
    assert signed_distance((0.5, 1.0), [(0.0, 0.0), (1.0, 0.0)]) == pytest.approx(-1.0)


# --------------------------------------------------------------------------- package hygiene


def test_builtin_lookup_imports_neither_pinocchio_nor_mujoco():
    code = textwrap.dedent(
        """
        import sys
        import motiontool.kinematics.robots as robots
        robots.load_robot("nao")
        robots.load_robot("nao-v5")
        robots.detect_robot(["HeadYaw"])
        heavy = sorted({"pinocchio", "mujoco", "coal"} & set(sys.modules))
        print(",".join(heavy))
        """
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=60
    )
    assert out.stdout.strip() == ""


def test_all_is_honest():
    exported = set(kin.__all__)
    assert all(hasattr(kin, name) for name in exported)
    public = {
        name
        for name, value in vars(kin).items()
        if not name.startswith("_") and not isinstance(value, type(sys))
    }
    assert public == exported


def test_the_robot_table_is_the_one_place_a_robot_is_named() -> None:
    """Every built-in robot: loaded, described, listed by ``motiontool robots``, accepted by
    ``--robot`` and its did-you-mean; the ranking rule finds it for its own joints."""
    from motiontool.cli.robots import list_robots
    from motiontool.kinematics.builtin_robots import describe

    listing = list_robots()
    for robot in BUILTIN_ROBOTS:
        spec = load_robot(robot.name)
        assert spec.name == robot.name and describe(robot.name) in listing
        assert robot.name in robot_choices()
        assert UnknownRobotError(robot.name + "x").suggestion == robot.name
        same = [
            r.name for r in BUILTIN_ROBOTS if load_robot(r.name).joint_names == spec.joint_names
        ]
        assert detect_robot(spec.joint_names) == same[0]  # the first of robots with its motors


def test_detect_robot_and_its_error_rank_by_one_rule() -> None:
    from motiontool.kinematics.robots import rank_robots

    for joints in (
        ["HeadYaw", "HeadYw", "Tail"],
        ["HeadYaw", "elbow_joint"],
        ["leg0"],
        ["HeadYaw", "HeadYaw", "Tail"],  # a name twice counts once
        ["HeadYaw", "HeadPitch", "Tail"],
    ):
        ranking = rank_robots(joints)
        assert (detect_robot(joints) is not None) == ranking.fits
        if not ranking.fits:
            err = NoRobotDetectedError(joints)
            assert (err.best, err.covered, err.missing, err.tied) == (
                ranking.best, ranking.covered, ranking.missing, ranking.tied,
            )  # fmt: skip
    assert rank_robots(["HeadYaw", "HeadYaw", "Tail"]).covered == 1


def test_a_builtin_robot_has_the_motors_of_its_model() -> None:
    # What the ranking reads, without an overrides file: one changes limits, never motors.
    from motiontool.kinematics.mjcf_table import parse_mjcf_table

    for robot in BUILTIN_ROBOTS:
        model = parse_mjcf_table(models_dir() / robot.model)
        assert load_robot(robot.name).joint_names == model.joint_names, robot.name
