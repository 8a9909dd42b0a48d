"""Robots that are not built in: a URDF or MJCF file, or a robot of example-robot-data
(``erd:<name>``), read through Pinocchio (:mod:`motiontool.kinematics._pinocchio`)."""

from __future__ import annotations

import difflib
import hashlib
import sys
from dataclasses import replace
from pathlib import Path
from typing import Literal

from motiontool.errors import MissingExtraError, MotionToolError
from motiontool.extras import require
from motiontool.kinematics.builtin_robots import DEFAULT_TIMESTEP_MS
from motiontool.kinematics.mjcf_table import velocity_actuators
from motiontool.kinematics.robot_spec import RobotSpec

__all__ = ["erd", "erd_robot_names", "erd_root", "from_pinocchio"]

#: example-robot-data robots by name (as its Python loaders name them): path of the URDF below
#: the ``robots`` folder, and whether the robot has a free-flying base.
_ERD_ROBOTS: dict[str, tuple[str, bool]] = {
    "a1": ("a1_description/urdf/a1.urdf", True),
    "anymal": ("anymal_b_simple_description/robots/anymal.urdf", True),
    "anymal_c": ("anymal_c_simple_description/urdf/anymal.urdf", True),
    "anymal_kinova": ("anymal_b_simple_description/robots/anymal-kinova.urdf", True),
    "asr_twodof": ("asr_twodof_description/urdf/TwoDofs.urdf", False),
    "b1": ("b1_description/urdf/b1.urdf", True),
    "b1_z1": ("b1_description/urdf/b1-z1.urdf", True),
    "baxter": ("baxter_description/urdf/baxter.urdf", False),
    "bolt": ("bolt_description/robots/bolt.urdf", True),
    "centauro": ("centauro_description/urdf/centauro.urdf", True),
    "double_pendulum": ("double_pendulum_description/urdf/double_pendulum.urdf", False),
    "double_pendulum_continuous": (
        "double_pendulum_description/urdf/double_pendulum_continuous.urdf",
        False,
    ),
    "double_pendulum_simple": (
        "double_pendulum_description/urdf/double_pendulum_simple.urdf",
        False,
    ),
    "finger_edu": ("finger_edu_description/robots/finger_edu.urdf", False),
    "g1": ("g1_description/urdf/g1_29dof_rev_1_0.urdf", True),
    "go1": ("go1_description/urdf/go1.urdf", True),
    "go2": ("go2_description/urdf/go2.urdf", True),
    "hector": ("hector_description/robots/quadrotor_base.urdf", True),
    "hyq": ("hyq_description/robots/hyq_no_sensors.urdf", True),
    "icub": ("icub_description/robots/icub.urdf", True),
    "icub_reduced": ("icub_description/robots/icub_reduced.urdf", True),
    "iris": ("iris_description/robots/iris_simple.urdf", True),
    "kinova": ("kinova_description/robots/kinova.urdf", False),
    "laikago": ("laikago_description/urdf/laikago.urdf", True),
    "panda": ("panda_description/urdf/panda.urdf", False),
    "romeo": ("romeo_description/urdf/romeo.urdf", True),
    "simple_humanoid": ("simple_humanoid_description/urdf/simple_humanoid.urdf", True),
    "simple_humanoid_classical": (
        "simple_humanoid_description/urdf/simple_humanoid_classical.urdf",
        True,
    ),
    "so100": ("so_arm_description/urdf/so100.urdf", False),
    "so101": ("so_arm_description/urdf/so101.urdf", False),
    "solo8": ("solo_description/robots/solo.urdf", True),
    "solo12": ("solo_description/robots/solo12.urdf", True),
    "talos": ("talos_data/robots/talos_reduced.urdf", True),
    "talos_arm": ("talos_data/robots/talos_left_arm.urdf", False),
    "talos_box": ("talos_data/robots/talos_reduced_box.urdf", True),
    "talos_full": ("talos_data/robots/talos_full_v2.urdf", True),
    "talos_full_box": ("talos_data/robots/talos_full_v2_box.urdf", True),
    "tiago": ("tiago_description/robots/tiago.urdf", False),
    "tiago_dual": ("tiago_description/robots/tiago_dual.urdf", False),
    "tiago_no_hand": ("tiago_description/robots/tiago_no_hand.urdf", False),
    "tiago_pro": ("tiago_pro_description/robots/tiago_pro.urdf", False),
    "ur3": ("ur_description/urdf/ur3_robot.urdf", False),
    "ur3_gripper": ("ur_description/urdf/ur3_gripper.urdf", False),
    "ur3_limited": ("ur_description/urdf/ur3_joint_limited_robot.urdf", False),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", False),
    "ur5_gripper": ("ur_description/urdf/ur5_gripper.urdf", False),
    "ur5_limited": ("ur_description/urdf/ur5_joint_limited_robot.urdf", False),
    "ur10": ("ur_description/urdf/ur10_robot.urdf", False),
    "ur10_limited": ("ur_description/urdf/ur10_joint_limited_robot.urdf", False),
    "xarm7": ("xarm_description/urdf/xarm7.urdf", False),
    "z1": ("z1_description/urdf/z1.urdf", False),
}


def erd_robot_names() -> list[str]:
    """Names accepted after ``erd:`` (example-robot-data robots this installation has)."""
    root = erd_root()
    if root is None:
        return []
    return sorted(n for n, (sub, _ff) in _ERD_ROBOTS.items() if (root / sub).is_file())


def erd_root() -> Path | None:
    """example-robot-data's ``robots`` folder (pip/cmeel, conda or robotpkg layouts)."""
    from importlib import metadata

    candidates = []
    try:
        dist = metadata.distribution("example-robot-data")
        candidates.append(
            Path(str(dist.locate_file("cmeel.prefix/share/example-robot-data/robots")))
        )
    except metadata.PackageNotFoundError:
        pass
    candidates.append(Path(sys.prefix) / "share" / "example-robot-data" / "robots")
    candidates.extend(
        Path(p).parent.parent.parent / "share" / "example-robot-data" / "robots"
        for p in sys.path
        if p
    )
    for candidate in candidates:
        if candidate.is_dir():
            return candidate
    return None


def erd(name: str) -> RobotSpec:
    root = erd_root()
    if root is None:
        raise MissingExtraError(
            "example_robot_data", "erd", f"robot 'erd:{name}'", "example-robot-data"
        )
    available = erd_robot_names()
    if name not in available:
        close = difflib.get_close_matches(name, available, n=1)
        hint = f"did you mean 'erd:{close[0]}'? " if close else ""
        raise MotionToolError(
            f"unknown example-robot-data robot '{name}'; {hint}choose one of "
            + ", ".join(available)
        )
    subpath, floating = _ERD_ROBOTS[name]
    return from_pinocchio(f"erd:{name}", root / subpath, "urdf", floating_base=floating)


def from_pinocchio(
    name: str, path: Path, fmt: Literal["mjcf", "urdf"], *, floating_base: bool | None
) -> RobotSpec:
    from motiontool.kinematics import _pinocchio

    require("pinocchio", "kinematics", f"robot '{name}' (a {fmt.upper()} model)")
    raw = path.read_bytes()
    joints, floating = _pinocchio.joint_table(path, fmt, floating_base)
    if fmt == "mjcf":
        # Pinocchio reads no velocity limit from MJCF; take motiontool's convention (a
        # <velocity> actuator's ctrlrange) where the file follows it.
        import xml.etree.ElementTree as ET

        velocity = velocity_actuators(ET.fromstring(raw))
        joints = tuple(
            replace(j, max_velocity=velocity[j.name]) if j.name in velocity else j for j in joints
        )
    return RobotSpec(
        name=name,
        model_path=path.resolve(),
        model_hash=hashlib.sha256(raw).hexdigest(),
        joints=joints,
        default_timestep_ms=DEFAULT_TIMESTEP_MS,
        model_format=fmt,
        floating_base=floating,
    )
