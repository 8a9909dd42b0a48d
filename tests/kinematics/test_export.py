"""Model export: MJCF byte for byte (nao-v5 with its limits written in), URDF that Pinocchio
reads back as the same robot."""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from conftest import import_extra

from motiontool.errors import MotionToolError
from motiontool.kinematics import load_robot, models_dir
from motiontool.kinematics.builtin_robots import BUILTIN_ROBOTS, BuiltinRobot
from motiontool.kinematics.collision import scan_self_collisions
from motiontool.kinematics.erd import from_pinocchio
from motiontool.kinematics.export import mjcf_bytes, urdf_bytes
from motiontool.kinematics.robot_spec import RobotSpec

pin = import_extra("pinocchio", "kinematics")


@pytest.mark.parametrize("robot", [r for r in BUILTIN_ROBOTS if r.overrides is None], ids=str)
def test_builtin_mjcf_is_the_model_file(robot: BuiltinRobot) -> None:
    assert mjcf_bytes(load_robot(robot.name)) == (models_dir() / robot.model).read_bytes()


@pytest.mark.needs("sim")
def test_nao_v5_mjcf_carries_the_real_robots_limits(tmp_path: Path) -> None:
    path = tmp_path / "nao-v5.xml"
    path.write_bytes(mjcf_bytes(load_robot("nao-v5")))
    reread = load_robot(str(path))  # through Pinocchio's MJCF reader
    assert reread.joints == load_robot("nao-v5").joints
    assert reread.joints != load_robot("nao").joints
    text = path.read_text()
    assert "LHipYawPitch = RHipYawPitch" in text
    import mujoco

    model = mujoco.MjModel.from_xml_path(str(path))
    elbow = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, "RElbowRoll")
    assert model.jnt_range[elbow].tolist() == pytest.approx([0.0349066, 1.54462])


def test_urdf_robot_has_no_mjcf() -> None:
    with pytest.raises(MotionToolError, match="comes from a URDF file"):
        mjcf_bytes(load_robot("erd:ur5"))
    spec = load_robot("erd:ur5")
    assert urdf_bytes(spec) == spec.model_path.read_bytes()


def test_no_mjcf_message_names_the_callers_option_only_when_given(tmp_path: Path) -> None:
    path = tmp_path / "arm.urdf"
    path.write_bytes(urdf_bytes(load_robot("ur5e")))
    spec = load_robot(str(path))
    with pytest.raises(MotionToolError, match=r"export it as URDF \(urdf_bytes\), or") as plain:
        mjcf_bytes(spec)
    assert "--" not in str(plain.value)
    # The CLI words the remedy with its own flag (cli/options.py error_line).
    from motiontool.cli.options import error_line

    assert "export it with --urdf, or let MuJoCo convert it" in error_line(plain.value)


@pytest.mark.parametrize(("robot", "floating"), [("nao", True), ("nao-v5", True), ("ur5e", False)])
def test_urdf_reads_back_as_the_same_robot(tmp_path: Path, robot: str, floating: bool) -> None:
    spec = load_robot(robot)
    path = tmp_path / f"{robot}.urdf"
    path.write_bytes(urdf_bytes(spec))
    if floating:
        assert "free-flyer root joint" in path.read_text()
    back = from_pinocchio(robot, path, "urdf", floating_base=floating)
    # Joint limits, velocities and torques.
    assert {j.name: j for j in back.joints} == {j.name: j for j in spec.joints}
    # Kinematics and mass distribution, at random configurations.
    from motiontool.kinematics import _pinocchio

    model, _ = _pinocchio.build_model(spec)
    model2, _ = _pinocchio.build_model(back)
    data, data2 = model.createData(), model2.createData()
    lo = np.array([j.lower for j in spec.joints])
    hi = np.array([j.upper for j in spec.joints])
    q = lo + (hi - lo) * np.random.default_rng(0).random((40, len(lo)))
    order = [spec.joint_names.index(n) for n in back.joint_names]
    configs = _pinocchio.configurations(spec, q)
    configs2 = _pinocchio.configurations(back, q[:, order])
    assert sum(i.mass for i in model2.inertias) == pytest.approx(
        sum(i.mass for i in model.inertias), rel=1e-12
    )
    for c, c2 in zip(configs[:5], configs2[:5], strict=True):
        pin.framesForwardKinematics(model, data, c)
        pin.framesForwardKinematics(model2, data2, c2)
        for fid, frame in enumerate(model.frames):
            if str(frame.type) == "BODY":
                np.testing.assert_allclose(
                    data2.oMf[model2.getFrameId(frame.name)].homogeneous,
                    data.oMf[fid].homogeneous,
                    atol=1e-9,
                )
        np.testing.assert_allclose(
            pin.centerOfMass(model2, data2, c2), pin.centerOfMass(model, data, c), atol=1e-9
        )
    # Collision: the same solids (a capsule is a cylinder and two spheres), so the same pairs
    # of bodies touch; a split capsule's depth is that of its deepest piece, never more than
    # the capsule's, and equal to it for shallow contacts.
    contacts = {c[:3]: c.depth_m for c in scan_self_collisions(spec, q)}
    contacts2 = {c[:3]: c.depth_m for c in scan_self_collisions(back, q[:, order])}
    assert contacts2.keys() == contacts.keys()
    for key, depth in contacts.items():
        assert contacts2[key] <= depth + 1e-6
        if depth < 0.003:
            assert contacts2[key] == pytest.approx(depth, abs=1e-6)


def _nao_v5_from(tmp_path: Path, edit: Callable[[str], str]) -> RobotSpec:
    """nao-v5 with its model file replaced by an edited copy of nao.xml."""
    model = tmp_path / "nao.xml"
    model.write_text(edit((models_dir() / "nao.xml").read_text()))
    return dataclasses.replace(load_robot("nao-v5"), model_path=model)


@pytest.mark.needs("sim")
def test_nao_v5_limits_are_written_whatever_the_attribute_order(tmp_path: Path) -> None:
    # Any valid spelling of the element: name not first, other spacing, single quotes.
    spec = _nao_v5_from(
        tmp_path,
        lambda t: t.replace(
            '<joint name="RElbowRoll" type="hinge"', "<joint  type='hinge'\n    name='RElbowRoll'"
        ).replace(
            '<velocity name="RElbowRoll" joint="RElbowRoll"',
            '<velocity joint="RElbowRoll" name="RElbowRoll"',
        ),
    )
    path = tmp_path / "nao-v5.xml"
    path.write_bytes(mjcf_bytes(spec))
    import mujoco

    model = mujoco.MjModel.from_xml_path(str(path))
    v5 = load_robot("nao-v5").joint("RElbowRoll")
    elbow = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, "RElbowRoll")
    assert model.jnt_range[elbow].tolist() == pytest.approx([v5.lower, v5.upper])
    actuator = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_ACTUATOR, "RElbowRoll")
    assert model.actuator_ctrlrange[actuator].tolist() == pytest.approx(
        [-v5.max_velocity, v5.max_velocity]
    )


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (
            lambda t: t.replace('name="RElbowRoll" type="hinge"', 'name="RElbowRol" type="hinge"'),
            r'no <joint name="RElbowRoll"> element; cannot write joint RElbowRoll',
        ),
        (
            lambda t: t.replace('<velocity name="HeadYaw"', '<velocity name="HeadYw"'),
            r'no <velocity name="HeadYaw"> element',
        ),
        (
            lambda t: t.replace(
                "</actuator>", '<velocity name="HeadYaw" joint="HeadYaw"/></actuator>'
            ),
            r'2 <velocity name="HeadYaw"> elements',
        ),
        (
            lambda t: t.replace("</actuator>", "</actuatr>"),
            r"nao.xml:\d+:\d+: not valid XML: mismatched tag",
        ),
    ],
    ids=["joint-missing", "actuator-missing", "actuator-twice", "not-xml"],
)
def test_a_limit_that_cannot_be_written_is_an_error(
    tmp_path: Path, edit: Callable[[str], str], message: str
) -> None:
    spec = _nao_v5_from(tmp_path, edit)
    with pytest.raises(MotionToolError, match=message):
        mjcf_bytes(spec)


def test_stored_urdf_is_written_once_then_read_without_pinocchio(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``play --bag``'s /robot_description: the first call writes the URDF (Pinocchio) and
    keeps it; a later process reads the same bytes without importing Pinocchio."""
    import subprocess
    import sys

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    from motiontool.kinematics.export import stored_urdf

    spec = load_robot("nao")
    first = stored_urdf(spec)
    assert first == urdf_bytes(spec)
    assert list((tmp_path / "motiontool" / "urdf").rglob("*.json"))
    probe = (
        "import sys; from motiontool.kinematics import load_robot;"
        "from motiontool.kinematics.export import stored_urdf;"
        "data = stored_urdf(load_robot('nao'));"
        "sys.stdout.buffer.write(data if 'pinocchio' not in sys.modules else b'imported')"
    )
    again = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, check=True, env={**os.environ}
    ).stdout
    assert again == first
