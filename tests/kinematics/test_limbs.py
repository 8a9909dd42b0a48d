"""The one joint grouping of plots, recordings and reports (``motiontool.kinematics.limbs``)."""

from __future__ import annotations

from motiontool.kinematics import load_robot
from motiontool.kinematics.limbs import NAO_LIMBS, limb_of


def test_every_nao_motor_has_a_nao_limb() -> None:
    limbs = {limb_of(j) for j in load_robot("nao").joint_names}
    assert limbs == set(NAO_LIMBS)
    assert limb_of("LWristYaw") == "LArm" and limb_of("RPhalanx8") == "RHand"
    assert limb_of("LHand") == "LHand"  # the older Nao hand motor


def test_a_serial_arm_is_arm_and_wrist_not_one_group() -> None:
    ur5e = load_robot("ur5e").joint_names
    assert [limb_of(j) for j in ur5e] == ["arm", "arm", "arm", "wrist", "wrist", "wrist"]
    assert limb_of("panda_finger_joint1") == "gripper"
    assert limb_of("panda_joint3", "arm") == "arm"  # a name that does not say: the fallback
    assert limb_of("panda_joint3") == "other"
