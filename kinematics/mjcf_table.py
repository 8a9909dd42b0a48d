"""A shipped robot's joint table, read from its MJCF model with :mod:`xml.etree` alone (no
Pinocchio or MuJoCo), and the JSON file of limits and rules that may replace the model's
(``nao-v5``). :func:`~motiontool.kinematics.builtin_robots.builtin` reads a robot's model here
when it is first asked for: the table of robots and their names come without it.
"""

from __future__ import annotations

import functools
import hashlib
import math
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from motiontool.kinematics.builtin_robots import DEFAULT_TIMESTEP_MS
from motiontool.kinematics.robot_spec import JointSpec, RobotSpec

if TYPE_CHECKING:
    import xml.etree.ElementTree as ET

__all__ = ["parse_mjcf_table", "velocity_actuators", "with_overrides"]


@functools.cache
def parse_mjcf_table(path: Path) -> RobotSpec:
    """Joint table of a built-in MJCF: joints' ``range``/``actuatorfrcrange``, velocity
    actuators' ``ctrlrange`` (maxVelocity) and the ``custom`` entries written by _modelgen."""
    import xml.etree.ElementTree as ET  # a robot's model is parsed only where it is used

    raw = path.read_bytes()
    root = ET.fromstring(raw)
    velocity = velocity_actuators(root)
    compiler = root.find("compiler")
    degrees = compiler is None or compiler.get("angle", "degree") != "radian"
    joints = []
    for el in root.iterfind(".//body/joint"):
        kind = el.get("type", "hinge")
        if kind not in ("hinge", "slide"):
            continue
        name = el.get("name", "")
        lower, upper = _floats(el.get("range", "-inf inf"))
        if degrees and kind == "hinge":  # MJCF's default angle unit
            lower, upper = math.radians(lower), math.radians(upper)
        _tlo, torque = _floats(el.get("actuatorfrcrange", "-inf inf"))
        joints.append(
            JointSpec(
                name=name,
                lower=lower,
                upper=upper,
                max_velocity=velocity.get(name, math.inf),
                max_torque=torque,
                kind="hinge" if kind == "hinge" else "slide",
                unit="rad" if kind == "hinge" else "m",
            )
        )
    custom = root.find("custom")
    timestep = DEFAULT_TIMESTEP_MS
    feet: tuple[str, ...] = ()
    if custom is not None:
        for numeric in custom.iterfind("numeric"):
            if numeric.get("name") == "webots_basic_time_step_ms":
                timestep = int(float(numeric.get("data", DEFAULT_TIMESTEP_MS)))
        for text in custom.iterfind("text"):
            if text.get("name") == "motiontool_feet":
                feet = tuple(text.get("data", "").split())
    return RobotSpec(
        name=path.stem,
        model_path=path,
        model_hash=hashlib.sha256(raw).hexdigest(),
        joints=tuple(joints),
        default_timestep_ms=timestep,
        model_format="mjcf",
        floating_base=root.find(".//body/freejoint") is not None,
        feet=feet,
    )


def velocity_actuators(root: ET.Element) -> dict[str, float]:
    """maxVelocity (rad/s or m/s) per joint: upper ``ctrlrange`` of its ``<velocity>`` actuator."""
    velocity = {}
    for act in root.iterfind("actuator/velocity"):
        if act.get("joint") and act.get("ctrlrange"):
            velocity[act.get("joint", "")] = _floats(act.get("ctrlrange", ""))[1]
    return velocity


def _floats(text: str) -> tuple[float, float]:
    a, b = text.split()
    return float(a), float(b)


def with_overrides(base: RobotSpec, name: str, path: Path) -> RobotSpec:
    """``base`` named ``name``, with the limits and rules of the JSON file at ``path`` (the
    real NAO V5's for ``nao-v5``); its model hash covers both files."""
    import json  # where an overrides file is read: a run on the Nao reads none

    raw = path.read_bytes()
    doc: dict[str, Any] = json.loads(raw)
    by_joint: dict[str, dict[str, float]] = doc.get("joints", {})
    joints = []
    for joint in base.joints:
        override = by_joint.get(joint.name, {})
        joints.append(
            replace(
                joint,
                lower=float(override.get("lower", joint.lower)),
                upper=float(override.get("upper", joint.upper)),
                max_velocity=float(override.get("max_velocity", joint.max_velocity)),
                max_torque=float(override.get("max_torque", joint.max_torque)),
            )
        )
    envelope = tuple(
        (float(y), float(lo), float(hi)) for y, lo, hi in doc.get("head_pitch_envelope", [])
    )
    coupled = tuple((str(a), str(b)) for a, b in doc.get("coupled_joints", []))
    model_bytes = base.model_path.read_bytes()
    return replace(
        base,
        name=name,
        model_hash=hashlib.sha256(model_bytes + raw).hexdigest(),
        joints=tuple(joints),
        overrides_path=path,
        head_pitch_envelope=envelope,
        coupled_joints=coupled,
    )
