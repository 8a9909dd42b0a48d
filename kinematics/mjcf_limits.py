"""A robot's joint limits written into its MJCF file, through an XML parser.

``nao-v5`` is ``nao.xml`` with the real robot's limits (``models/nao-v5.json``): each motor's
``<joint>`` gets its ``range`` and ``actuatorfrcrange``, its ``<velocity>`` actuator its
``ctrlrange`` and ``forcerange``. The elements are found by tag and ``name`` in the parsed tree,
whatever the attribute order, spacing or quoting; a motor without exactly one such element is an
error naming it, never a file left silently unchanged.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
import xml.parsers.expat
from collections.abc import Iterable
from pathlib import Path

from motiontool.errors import MotionToolError
from motiontool.kinematics.robot_spec import JointSpec

__all__ = ["write_limits", "xml_number"]


def xml_number(x: float) -> str:
    """A number as a model file writes it: the shortest text that reads back exactly."""
    return repr(float(x))


def _root_offset(raw: bytes, path: Path) -> int:
    """The byte offset of the root element's ``<``: what comes before it (the XML declaration,
    the generated file's leading comment) is kept as it is."""
    offsets: list[int] = []
    parser = xml.parsers.expat.ParserCreate()

    def start(_name: str, _attrs: dict[str, str]) -> None:
        if not offsets:
            offsets.append(parser.CurrentByteIndex)

    parser.StartElementHandler = start
    try:
        parser.Parse(raw, True)
    except xml.parsers.expat.ExpatError as exc:
        where = f"{path}:{exc.lineno}:{exc.offset + 1}"
        why = xml.parsers.expat.ErrorString(exc.code)
        raise MotionToolError(f"{where}: not valid XML: {why}") from None
    return offsets[0]


def _one(root: ET.Element, tag: str, name: str, path: Path) -> ET.Element:
    """The one ``<tag name="name">`` of the model; an error if there is none or several."""
    found = [e for e in root.iter(tag) if e.get("name") == name]
    if len(found) != 1:
        what = "no" if not found else f"{len(found)}"
        raise MotionToolError(
            f'{path}: {what} <{tag} name="{name}"> element{"s" if found else ""}; '
            f"cannot write joint {name}'s limits into the model"
        )
    return found[0]


def write_limits(path: Path, joints: Iterable[JointSpec]) -> str:
    """The MJCF text of ``path`` with each of ``joints``' limits (rad or m, rad/s or m/s, N·m or
    N) set on its ``<joint>`` and its ``<velocity>`` actuator; comments and the text around the
    elements are kept.

    Raises:
        MotionToolError: the file is not valid XML, or a joint has no (or more than one)
            ``<joint>`` or ``<velocity>`` element of its name.
    """
    raw = path.read_bytes()
    start = _root_offset(raw, path)
    root = ET.fromstring(raw, parser=ET.XMLParser(target=ET.TreeBuilder(insert_comments=True)))
    for joint in joints:
        force = f"{xml_number(-joint.max_torque)} {xml_number(joint.max_torque)}"
        element = _one(root, "joint", joint.name, path)
        element.set("range", f"{xml_number(joint.lower)} {xml_number(joint.upper)}")
        element.set("actuatorfrcrange", force)
        actuator = _one(root, "velocity", joint.name, path)
        actuator.set(
            "ctrlrange", f"{xml_number(-joint.max_velocity)} {xml_number(joint.max_velocity)}"
        )
        actuator.set("forcerange", force)
    return raw[:start].decode("utf-8") + ET.tostring(root, encoding="unicode") + "\n"
