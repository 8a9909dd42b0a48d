"""``ur5e.xml``: the Webots UR5e (Universal Robots), a fixed-base arm of 6 motors."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

from motiontool.kinematics._modelgen.inertia import balanced
from motiontool.kinematics._modelgen.mjcf import (
    COMMON_NOTES,
    PHYSICS_TIMESTEP_S,
    Facts,
    add_actuators,
    comment,
    element,
    file_header,
    geom,
    hinge_body,
    inertial,
    num,
    render,
    tree,
)

__all__ = ["ur5e_xml"]


def ur5e_xml(data: Facts, source: Path) -> str:
    """The text of ``ur5e.xml`` from the facts ``data`` read from ``source``."""
    joints = data["joints"]
    bodies, children = tree(data)
    timestep_ms = data["webots_world_defaults"]["ure.wbt"]["basicTimeStep_ms"]

    root = ET.Element("mujoco", {"model": "ur5e"})
    element(root, "compiler", angle="radian", autolimits="true", inertiafromgeom="false")
    element(root, "option", timestep=num(PHYSICS_TIMESTEP_S), integrator="implicitfast")
    custom = element(root, "custom")
    element(custom, "numeric", name="webots_basic_time_step_ms", data=num(timestep_ms))
    world = element(root, "worldbody")

    (root_body,) = [b["name"] for b in data["bodies"] if b["parent_joint"] is None]
    _add_body(children, bodies, world, root_body, None)
    contact = element(root, "contact")
    comment(
        contact,
        "MuJoCo's parent-child filter skips children of a body welded to the world: exclude "
        "the base's child explicitly (Webots never collides directly jointed Solids).",
    )
    for joint in children[root_body]:
        element(contact, "exclude", body1=root_body, body2=joint["child_body"])
    add_actuators(root, joints)
    header = file_header(
        "Webots UR5e (Universal Robots): 6 motors, fixed base.",
        source,
        data,
        [
            *COMMON_NOTES,
            "* Site tool_slot: the PROTO toolSlot pose in wrist_3_link.",
        ],
    )
    return render(root, header)


def _add_body(
    children: dict[str, list[Facts]],
    bodies: dict[str, Facts],
    parent: ET.Element,
    name: str,
    joint: Facts | None,
) -> None:
    """Body ``name`` under ``parent`` (posed by ``joint``; the fixed base if None), then its
    children."""
    body = bodies[name]
    if joint is None:
        el = element(parent, "body", name=name, pos="0 0 0")
        comment(
            el,
            "PROTO staticBase TRUE: the base is pinned to the world (no joint, no mass). "
            "Webots PROTO default selfCollision TRUE: all geoms collide (MuJoCo skips "
            "parent-child pairs).",
        )
        element(el, "inertial", pos="0 0 0", mass="0", diaginertia="0 0 0")
    else:
        el = hinge_body(parent, name, joint)
    if body["mass"] is not None:
        comment(
            el,
            "mass and CoM from the PROTO; the PROTO has no inertiaMatrix: tensor from "
            "MuJoCo Menagerie (as chosen in ur5e.json)",
        )
        full, _ = balanced(body["inertia"])
        inertial(el, body, full)
    for i, prim in enumerate(body["webots_bounding_object"]):
        geom(el, f"{name}_{i}", prim)
    if name == "wrist_3_link":
        element(el, "site", name="tool_slot", pos="0 0.1 0", size="0.005")
    for child in children.get(name, []):
        _add_body(children, bodies, el, child["child_body"], child)
