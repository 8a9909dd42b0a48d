"""``nao.xml``: the Webots Nao (V5, H25 'Realistic' wrists), a free-flying humanoid of 40 motors."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path
from typing import NamedTuple

from motiontool.kinematics._modelgen.inertia import (
    balanced,
    box_inertia,
    capsule_inertia,
    full6,
    quat_to_mat,
    rotate_tensor,
)
from motiontool.kinematics._modelgen.mjcf import (
    COMMON_NOTES,
    PHYSICS_TIMESTEP_S,
    VIRTUAL_INERTIA,
    VIRTUAL_MASS,
    Facts,
    add_actuators,
    comment,
    element,
    file_header,
    geom,
    hinge_body,
    inertial,
    num,
    pose_attrs,
    render,
    sig,
    tree,
    vec,
)

__all__ = ["nao_xml"]


class _Tree(NamedTuple):
    """The robot facts' bodies by name, each body's child joints, and the height (m) of the
    torso origin above the soles at the zero pose."""

    bodies: dict[str, Facts]
    children: dict[str, list[Facts]]
    spawn: float


def nao_xml(data: Facts, source: Path) -> str:
    """The text of ``nao.xml`` from the facts ``data`` read from ``source``."""
    bodies, children = tree(data)
    spawn = data["derived_checks"]["zero_pose_sole_height_below_torso_origin"]
    root, world = _skeleton(data)
    (root_body,) = [b["name"] for b in data["bodies"] if b["parent_joint"] is None]
    _add_body(_Tree(bodies, children, spawn), world, root_body, None)
    add_actuators(root, data["joints"])
    header = file_header(
        "Webots Nao (V5, 25 DoF, H25 'Realistic' wrists with 8 finger motors per hand): 40 motors.",
        source,
        data,
        [
            *COMMON_NOTES,
            "* Free-flying root body torso; Hinge2Joint helper frames neck_virtual,",
            "  r/l_shoulder_virtual carry a negligible mass. LFsr/RFsr: jointless foot bodies.",
            "* jacobian=dense: with 86 DoF MuJoCo would pick sparse Jacobians, with which the",
            "  Newton solver diverged (docs/simulation.md).",
        ],
    )
    return render(root, header)


def _skeleton(data: Facts) -> tuple[ET.Element, ET.Element]:
    """The ``mujoco`` root with compiler, option, custom data and the robot's default class,
    and its (still empty) ``worldbody``."""
    timestep_ms = data["webots_world_defaults"]["nao_demo.wbt"]["basicTimeStep_ms"]
    root = ET.Element("mujoco", {"model": "nao"})
    element(root, "compiler", angle="radian", autolimits="true", inertiafromgeom="false")
    element(
        root,
        "option",
        timestep=num(PHYSICS_TIMESTEP_S),
        integrator="implicitfast",
        jacobian="dense",
    )
    custom = element(root, "custom")
    element(custom, "numeric", name="webots_basic_time_step_ms", data=num(timestep_ms))
    element(custom, "text", name="motiontool_feet", data="LFsr RFsr")
    default = element(element(root, "default"), "default", {"class": "nao"})
    comment(
        default,
        "Webots Nao PROTO default selfCollision FALSE: robot geoms collide with the floor "
        "(contype 1) but not with each other (conaffinity 0). A class, not the top-level "
        "default, so that a floor added to the model keeps MuJoCo's defaults.",
    )
    element(default, "geom", contype="1", conaffinity="0")
    return root, element(root, "worldbody")


def _add_body(facts: _Tree, parent: ET.Element, name: str, joint: Facts | None) -> None:
    """Body ``name`` under ``parent`` (posed by ``joint``; the free-flying root if None), its
    inertia, geometries and bumpers, then its children and its foot force sensor."""
    body = facts.bodies[name]
    if joint is None:
        el = element(parent, "body", name=name, pos=vec([0, 0, -facts.spawn]), childclass="nao")
        comment(el, "zero pose: FSR box bottoms on the floor z = 0 (torso 0.3339 m above)")
        element(el, "freejoint", name="root")
    else:
        el = hinge_body(parent, name, joint)
    _body_inertial(el, body)
    for i, prim in enumerate(body["webots_bounding_object"]):
        geom(el, f"{name}_{i}", prim)
    attached = body.get("rigidly_attached")
    if attached:
        for bumper in attached["bumpers"]:
            geom(el, bumper["device_name"], bumper["bounding_object"])
    for child in facts.children.get(name, []):
        _add_body(facts, el, child["child_body"], child)
    if attached:
        _force_sensor(el, attached["force_sensor"])


def _body_inertial(el: ET.Element, body: Facts) -> None:
    """The inertia of a body: negligible for a Hinge2Joint helper frame, derived from the
    capsule for a finger segment, the PROTO tensor (corrected if need be) otherwise."""
    if body["mass"] == 0.0:
        comment(el, "massless Hinge2Joint helper frame (not a Webots Solid): negligible mass")
        element(
            el,
            "inertial",
            pos="0 0 0",
            mass=num(VIRTUAL_MASS),
            diaginertia=vec([VIRTUAL_INERTIA] * 3),
        )
    elif body["inertia"] is None:
        # Finger segment: Webots derives CoM and inertia from the capsule (density 200).
        (prim,) = body["webots_bounding_object"]
        mj = prim["mujoco_equivalent"]
        perp, axial = capsule_inertia(body["mass"], mj["size"][0], mj["size"][1])
        tensor = rotate_tensor(quat_to_mat(mj["quat_wxyz"]), [perp, perp, axial])
        comment(el, "CoM and inertia of the solid capsule at the PROTO density (derived)")
        element(
            el,
            "inertial",
            pos=vec(mj["pos"]),
            mass=num(body["mass"]),
            fullinertia=vec(sig(x) for x in full6(tensor)),
        )
    else:
        full, corrected = balanced(body["inertia"])
        if corrected:
            proto = [body["inertia"][k] for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")]
            comment(
                el,
                "PROTO tensor " + vec(proto) + " breaks the triangle inequality; smallest "
                "principal moment raised to (largest - middle) so MuJoCo and Pinocchio "
                "agree (no balanceinertia)",
            )
        inertial(el, body, full)


def _force_sensor(el: ET.Element, fsr: Facts) -> None:
    """The foot's TouchSensor: a jointless child body whose box touches the floor."""
    box = fsr["bounding_object"]["mujoco_equivalent"]
    fsr_el = element(
        el,
        "body",
        name=fsr["device_name"],
        **pose_attrs(fsr["translation"], box["quat_wxyz"]),
    )
    comment(
        fsr_el,
        "TouchSensor Solid rigidly inside the foot (no joint); its box is the geometry "
        "that touches the floor. Inertia: the box at the PROTO mass (derived).",
    )
    element(
        fsr_el,
        "inertial",
        pos="0 0 0",
        mass=num(fsr["mass"]),
        fullinertia=vec([sig(x) for x in box_inertia(fsr["mass"], box["size"])] + [0] * 3),
    )
    element(fsr_el, "geom", name=fsr["device_name"], type="box", size=vec(box["size"]))
    element(
        fsr_el,
        "site",
        name=fsr["device_name"] + "_site",
        type="box",
        size=vec(box["size"]),
    )
