"""Generate the built-in robot models from the robot data JSON (the single source of truth).

Usage (from the repository root; ``<robots-dir>`` is the folder of the robot facts, e.g. the copy
vendored in ``tests/data/robot_facts``)::

    python -m motiontool.kinematics._modelgen <robots-dir> kinematics/models
    python -m motiontool.kinematics._modelgen <robots-dir> kinematics/models --check

It reads ``nao.json`` and ``ur5e.json`` (numbers transcribed from the Webots PROTO files) and
writes ``nao.xml`` and ``ur5e.xml`` (MJCF, loadable by MuJoCo and by Pinocchio's MJCF reader) and
``nao-v5.json`` (the real NAO V5's limits, applied on top of ``nao.xml`` by
:mod:`motiontool.kinematics.robots`). The output is deterministic: the same JSON gives the same
bytes, which a test checks against the committed files.

Modelling choices (also written into each file's header comment):

* Joint names are the Webots motor names; each joint carries ``range`` (the motor's soft limits
  ``minPosition``/``maxPosition``, rad) and ``actuatorfrcrange`` (``±maxTorque``, N·m).
* ``maxVelocity`` lives in one MuJoCo ``velocity`` actuator per motor, named like its joint:
  ``ctrlrange = ±maxVelocity`` (rad/s) and ``forcerange = ±maxTorque`` (N·m). A plain XML reader
  finds both limits there and on the joint; MuJoCo compiles them as a usable (if simple) motor.
* Inertias are the PROTO tensors (about the centre of mass, body axes). The two upper-arm tensors
  violate the triangle inequality; the smallest principal moment is raised just enough to satisfy
  it (a minimal correction, so MuJoCo and Pinocchio see the same physical tensor) and the
  original PROTO values are kept in a comment next to it.
* The three massless helper frames of the Webots ``Hinge2Joint``s (``neck_virtual``,
  ``*_shoulder_virtual``) get a negligible mass (``_VIRTUAL_MASS``) so MuJoCo accepts them.
* The foot force sensors ``LFsr``/``RFsr`` are jointless child bodies of the feet (MuJoCo welds
  them, Pinocchio merges them into the ankle-roll body) carrying their 0.08057 kg and the
  0.147 x 0.089 x 0.01 m box that touches the floor.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import math
import sys
import xml.etree.ElementTree as ET
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

__all__ = ["generate", "main"]

#: Mass (kg) and diagonal inertia (kg·m²) given to the massless Hinge2Joint helper frames.
_VIRTUAL_MASS = 1e-6
_VIRTUAL_INERTIA = 1e-10
#: Velocity error (rad/s) at which the default MuJoCo velocity actuator saturates:
#: ``kv = maxTorque / _KV_SATURATION_ERROR``. A placeholder gain: ``sim`` owns the motor model.
_KV_SATURATION_ERROR = 0.1
#: Margin (kg·m²) kept above the triangle inequality when a tensor is corrected.
_TRIANGLE_MARGIN = 1e-9
#: Relative size below which a derived tensor entry is round-off and written as 0.
_RELATIVE_ZERO = 1e-9
#: MuJoCo physics step (s) written into the models; Webots' basicTimeStep is stored separately.
_PHYSICS_TIMESTEP_S = 0.002
_IDENTITY_QUAT = (1.0, 0.0, 0.0, 0.0)
_SOURCES = ("nao.json", "ur5e.json")
_OUTPUTS = ("nao.xml", "nao-v5.json", "ur5e.xml")


# --------------------------------------------------------------------------- number formatting


def _num(x: float) -> str:
    """Shortest text that round-trips ``x`` (``4`` for 4.0, ``0`` for -0.0)."""
    value = float(x)
    if value == 0.0:
        return "0"
    text = repr(value)
    if text.endswith(".0"):
        text = text[:-2]
    return text


def _sig(x: float, digits: int = 9) -> float:
    """``x`` rounded to ``digits`` significant digits (for derived values)."""
    return float(f"{x:.{digits}g}")


def _vec(values: Iterable[float]) -> str:
    return " ".join(_num(v) for v in values)


# --------------------------------------------------------------------------- small linear algebra


def _quat_to_mat(q: Sequence[float]) -> list[list[float]]:
    w, x, y, z = q
    n = math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return [
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ]


def _rotate_tensor(rot: list[list[float]], diag: Sequence[float]) -> list[list[float]]:
    """``R diag(d) R^T``."""
    return [
        [sum(rot[i][k] * diag[k] * rot[j][k] for k in range(3)) for j in range(3)] for i in range(3)
    ]


def _sym_eig(mat: list[list[float]]) -> tuple[list[float], list[list[float]]]:
    """Eigen-decomposition of a symmetric 3x3 matrix (cyclic Jacobi; stdlib only).

    Returns ascending eigenvalues and the matrix whose columns are the eigenvectors.
    """
    a = [row[:] for row in mat]
    v = [[1.0 if i == j else 0.0 for j in range(3)] for i in range(3)]
    for _sweep in range(100):
        off = a[0][1] ** 2 + a[0][2] ** 2 + a[1][2] ** 2
        if off < 1e-40:
            break
        for p, q in ((0, 1), (0, 2), (1, 2)):
            if a[p][q] == 0.0:
                continue
            theta = (a[q][q] - a[p][p]) / (2 * a[p][q])
            t = math.copysign(1.0, theta) / (abs(theta) + math.sqrt(theta * theta + 1))
            c = 1 / math.sqrt(t * t + 1)
            s = t * c
            for k in range(3):
                akp, akq = a[k][p], a[k][q]
                a[k][p], a[k][q] = c * akp - s * akq, s * akp + c * akq
            for k in range(3):
                apk, aqk = a[p][k], a[q][k]
                a[p][k], a[q][k] = c * apk - s * aqk, s * apk + c * aqk
            for k in range(3):
                vkp, vkq = v[k][p], v[k][q]
                v[k][p], v[k][q] = c * vkp - s * vkq, s * vkp + c * vkq
    order = sorted(range(3), key=lambda i: a[i][i])
    values = [a[i][i] for i in order]
    vectors = [[v[r][i] for i in order] for r in range(3)]
    return values, vectors


def _tensor(inertia: dict[str, float]) -> list[list[float]]:
    i = inertia
    return [
        [i["ixx"], i["ixy"], i["ixz"]],
        [i["ixy"], i["iyy"], i["iyz"]],
        [i["ixz"], i["iyz"], i["izz"]],
    ]


def _full6(t: list[list[float]]) -> list[float]:
    """MuJoCo ``fullinertia`` order: ixx iyy izz ixy ixz iyz; round-off (entries below
    ``_RELATIVE_ZERO`` of the largest moment) written as 0."""
    values = [t[0][0], t[1][1], t[2][2], t[0][1], t[0][2], t[1][2]]
    scale = max(abs(v) for v in values[:3])
    return [0.0 if abs(v) < _RELATIVE_ZERO * scale else v for v in values]


def _balanced(inertia: dict[str, float]) -> tuple[list[float], bool]:
    """The tensor as ``fullinertia``, minimally corrected if it breaks the triangle inequality."""
    tensor = _tensor(inertia)
    values, vectors = _sym_eig(tensor)
    low, mid, high = values
    if low + mid >= high:
        return [inertia[k] for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")], False
    fixed = [high - mid + _TRIANGLE_MARGIN, mid, high]
    corrected = _rotate_tensor(vectors, fixed)
    return [_sig(x) for x in _full6(corrected)], True


def _capsule_inertia(mass: float, radius: float, half_length: float) -> tuple[float, float]:
    """Solid capsule (uniform density) moments about its centre: (perpendicular, axial)."""
    r, length = radius, 2 * half_length
    v_cyl = math.pi * r * r * length
    v_caps = 4.0 / 3.0 * math.pi * r**3
    m_cyl = mass * v_cyl / (v_cyl + v_caps)
    m_caps = mass - m_cyl
    axial = m_cyl * r * r / 2 + m_caps * 2 * r * r / 5
    perp = m_cyl * (r * r / 4 + length * length / 12) + m_caps * (
        2 * r * r / 5 + length * length / 4 + 3 * length * r / 8
    )
    return perp, axial


def _box_inertia(mass: float, half: Sequence[float]) -> list[float]:
    a, b, c = (2 * h for h in half)
    return [mass / 12 * (b * b + c * c), mass / 12 * (a * a + c * c), mass / 12 * (a * a + b * b)]


# --------------------------------------------------------------------------- XML helpers


def _el(
    parent: ET.Element, tag: str, attrs: dict[str, str] | None = None, /, **kw: str
) -> ET.Element:
    return ET.SubElement(parent, tag, {**(attrs or {}), **kw})


def _comment(parent: ET.Element, text: str) -> None:
    parent.append(ET.Comment(" " + text.replace("--", "- -") + " "))


def _pose_attrs(pos: Sequence[float], quat: Sequence[float]) -> dict[str, str]:
    attrs = {"pos": _vec(pos)}
    if tuple(float(q) for q in quat) != _IDENTITY_QUAT:
        attrs["quat"] = _vec(quat)
    return attrs


def _hinge_body(parent: ET.Element, name: str, joint: dict[str, Any]) -> ET.Element:
    """A child body posed by its Webots joint, with the hinge (range, torque) of its motor."""
    attrs = {"name": name}
    attrs.update(_pose_attrs(joint["translation"], joint["rotation_quat_wxyz"]))
    el = _el(parent, "body", **attrs)
    torque = joint["maxTorque"]
    _el(
        el,
        "joint",
        name=joint["name"],
        type="hinge",
        axis=_vec(joint["axis"]),
        range=_vec([joint["minPosition"], joint["maxPosition"]]),
        actuatorfrcrange=_vec([-torque, torque]),
    )
    return el


def _geom(parent: ET.Element, name: str, prim: dict[str, Any]) -> None:
    mj = prim["mujoco_equivalent"]
    attrs = {"name": name, "type": mj["type"], "size": _vec(mj["size"])}
    attrs.update(_pose_attrs(mj["pos"], mj["quat_wxyz"]))
    _el(parent, "geom", **attrs)


def _sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _header(title: str, source: Path, data: dict[str, Any], notes: Sequence[str]) -> str:
    lines = [
        title,
        "",
        f"GENERATED by motiontool.kinematics._modelgen from robots/{source.name}",
        f"(sha256 {_sha256(source)}). Do not edit by hand; regenerate with",
        "  python -m motiontool.kinematics._modelgen tests/data/robot_facts kinematics/models",
        "",
        "Provenance of the numbers (transcribed into the JSON from these files):",
    ]
    for entry in data.get("provenance", []):
        path = entry.get("path", "")
        if "repo" in entry and path.endswith((".proto", ".wbt", ".xml")):
            lines.append(f"  {entry['repo']} {path} @ {entry['commit']}")
    lines.append("")
    lines.extend(notes)
    body = "\n".join(("  " + line) if line else "" for line in lines)
    return "<!--\n" + body.replace("--", "- -") + "\n-->\n"


def _render(root: ET.Element, header: str) -> str:
    ET.indent(root, space="  ")
    text = ET.tostring(root, encoding="unicode", short_empty_elements=True)
    return '<?xml version="1.0" encoding="utf-8"?>\n' + header + text + "\n"


_COMMON_NOTES = (
    "Conventions (see motiontool/kinematics/_modelgen.py):",
    "* joint names = Webots motor names; joint range = motor minPosition/maxPosition (rad);",
    "  joint actuatorfrcrange = +-maxTorque (N m).",
    "* maxVelocity: one <velocity> actuator per motor, named like its joint, with",
    "  ctrlrange = +-maxVelocity (rad/s) and forcerange = +-maxTorque (N m); kv is a",
    f"  placeholder (saturates at a {_num(_KV_SATURATION_ERROR)} rad/s velocity error): sim/ owns",
    "  the motor model.",
    "* inertial: PROTO mass, centre of mass and tensor (about the CoM, body axes);",
    "  inertiafromgeom=false, so geoms carry no mass.",
    "* custom numeric webots_basic_time_step_ms: basicTimeStep of the robot's Webots world",
    "  (the control period of motion playback); option timestep is MuJoCo's physics step.",
    "* No floor: a scene adds one at z = 0.",
)


# --------------------------------------------------------------------------- Nao


def _tree(
    data: dict[str, Any],
) -> tuple[dict[str, dict[str, Any]], dict[str, list[dict[str, Any]]]]:
    """The robot facts' bodies by name, and each body's child joints in tree order."""
    bodies = {b["name"]: b for b in data["bodies"]}
    children: dict[str, list[dict[str, Any]]] = {}
    for joint in sorted(data["joints"], key=lambda j: j["tree_index"]):
        children.setdefault(joint["parent_body"], []).append(joint)
    return bodies, children


def _inertial(el: ET.Element, body: dict[str, Any], full: Sequence[float]) -> None:
    """The ``inertial`` element of ``body``: its mass (kg), centre of mass (m) and the full
    inertia tensor ``full`` (kg·m², xx yy zz xy xz yz)."""
    _el(
        el,
        "inertial",
        pos=_vec(body["center_of_mass"]),
        mass=_num(body["mass"]),
        fullinertia=_vec(full),
    )


def _nao_xml(data: dict[str, Any], source: Path) -> str:
    joints = data["joints"]
    bodies, children = _tree(data)
    timestep_ms = data["webots_world_defaults"]["nao_demo.wbt"]["basicTimeStep_ms"]
    spawn = data["derived_checks"]["zero_pose_sole_height_below_torso_origin"]

    root = ET.Element("mujoco", {"model": "nao"})
    _el(root, "compiler", angle="radian", autolimits="true", inertiafromgeom="false")
    _el(
        root,
        "option",
        timestep=_num(_PHYSICS_TIMESTEP_S),
        integrator="implicitfast",
        jacobian="dense",
    )
    custom = _el(root, "custom")
    _el(custom, "numeric", name="webots_basic_time_step_ms", data=_num(timestep_ms))
    _el(custom, "text", name="motiontool_feet", data="LFsr RFsr")
    default = _el(_el(root, "default"), "default", {"class": "nao"})
    _comment(
        default,
        "Webots Nao PROTO default selfCollision FALSE: robot geoms collide with the floor "
        "(contype 1) but not with each other (conaffinity 0). A class, not the top-level "
        "default, so that a floor added to the model keeps MuJoCo's defaults.",
    )
    _el(default, "geom", contype="1", conaffinity="0")
    world = _el(root, "worldbody")

    def add_body(parent: ET.Element, name: str, joint: dict[str, Any] | None) -> None:
        body = bodies[name]
        if joint is None:
            el = _el(parent, "body", name=name, pos=_vec([0, 0, -spawn]), childclass="nao")
            _comment(el, "zero pose: FSR box bottoms on the floor z = 0 (torso 0.3339 m above)")
            _el(el, "freejoint", name="root")
        else:
            el = _hinge_body(parent, name, joint)
        prims = body["webots_bounding_object"]
        if body["mass"] == 0.0:
            _comment(el, "massless Hinge2Joint helper frame (not a Webots Solid): negligible mass")
            _el(
                el,
                "inertial",
                pos="0 0 0",
                mass=_num(_VIRTUAL_MASS),
                diaginertia=_vec([_VIRTUAL_INERTIA] * 3),
            )
        elif body["inertia"] is None:
            # Finger segment: Webots derives CoM and inertia from the capsule (density 200).
            (prim,) = prims
            mj = prim["mujoco_equivalent"]
            perp, axial = _capsule_inertia(body["mass"], mj["size"][0], mj["size"][1])
            tensor = _rotate_tensor(_quat_to_mat(mj["quat_wxyz"]), [perp, perp, axial])
            _comment(el, "CoM and inertia of the solid capsule at the PROTO density (derived)")
            _el(
                el,
                "inertial",
                pos=_vec(mj["pos"]),
                mass=_num(body["mass"]),
                fullinertia=_vec(_sig(x) for x in _full6(tensor)),
            )
        else:
            full, corrected = _balanced(body["inertia"])
            if corrected:
                proto = [body["inertia"][k] for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")]
                _comment(
                    el,
                    "PROTO tensor " + _vec(proto) + " breaks the triangle inequality; smallest "
                    "principal moment raised to (largest - middle) so MuJoCo and Pinocchio "
                    "agree (no balanceinertia)",
                )
            _inertial(el, body, full)
        for i, prim in enumerate(prims):
            _geom(el, f"{name}_{i}", prim)
        attached = body.get("rigidly_attached")
        if attached:
            for bumper in attached["bumpers"]:
                _geom(el, bumper["device_name"], bumper["bounding_object"])
        for child in children.get(name, []):
            add_body(el, child["child_body"], child)
        if attached:
            fsr = attached["force_sensor"]
            box = fsr["bounding_object"]["mujoco_equivalent"]
            fsr_el = _el(
                el,
                "body",
                name=fsr["device_name"],
                **_pose_attrs(fsr["translation"], box["quat_wxyz"]),
            )
            _comment(
                fsr_el,
                "TouchSensor Solid rigidly inside the foot (no joint); its box is the geometry "
                "that touches the floor. Inertia: the box at the PROTO mass (derived).",
            )
            _el(
                fsr_el,
                "inertial",
                pos="0 0 0",
                mass=_num(fsr["mass"]),
                fullinertia=_vec(
                    [_sig(x) for x in _box_inertia(fsr["mass"], box["size"])] + [0] * 3
                ),
            )
            _el(fsr_el, "geom", name=fsr["device_name"], type="box", size=_vec(box["size"]))
            _el(
                fsr_el,
                "site",
                name=fsr["device_name"] + "_site",
                type="box",
                size=_vec(box["size"]),
            )

    (root_body,) = [b["name"] for b in data["bodies"] if b["parent_joint"] is None]
    add_body(world, root_body, None)
    _add_actuators(root, joints)
    header = _header(
        "Webots Nao (V5, 25 DoF, H25 'Realistic' wrists with 8 finger motors per hand): 40 motors.",
        source,
        data,
        [
            *_COMMON_NOTES,
            "* Free-flying root body torso; Hinge2Joint helper frames neck_virtual,",
            "  r/l_shoulder_virtual carry a negligible mass. LFsr/RFsr: jointless foot bodies.",
            "* jacobian=dense: with 86 DoF MuJoCo would pick sparse Jacobians, with which the",
            "  Newton solver diverged (docs/simulation.md).",
        ],
    )
    return _render(root, header)


def _add_actuators(root: ET.Element, joints: Sequence[dict[str, Any]]) -> None:
    actuator = _el(root, "actuator")
    for joint in sorted(joints, key=lambda j: j["tree_index"]):
        velocity, torque = joint["maxVelocity"], joint["maxTorque"]
        _el(
            actuator,
            "velocity",
            name=joint["name"],
            joint=joint["name"],
            kv=_num(_sig(torque / _KV_SATURATION_ERROR)),
            ctrlrange=_vec([-velocity, velocity]),
            forcerange=_vec([-torque, torque]),
        )


# --------------------------------------------------------------------------- nao-v5 overrides

_URDF_TO_SPEC = (
    ("lower", "lower"),
    ("upper", "upper"),
    ("velocity", "max_velocity"),
    ("effort", "max_torque"),
)


def _nao_v5(data: dict[str, Any], source: Path) -> str:
    joints: dict[str, dict[str, float]] = {}
    for joint in sorted(data["joints"], key=lambda j: j["tree_index"]):
        urdf = joint.get("ros_naoV50_urdf_limits")
        if not urdf:
            continue
        differs = set(joint.get("differs_from_ros_urdf", []))
        override = {key: urdf[src] for src, key in _URDF_TO_SPEC if src in differs}
        if override:
            joints[joint["name"]] = override
    coupled: list[list[str]] = []
    for joint in sorted(data["joints"], key=lambda j: j["tree_index"]):
        mimic = (joint.get("ros_naoV50_urdf_limits") or {}).get("mimic")
        if mimic:
            coupled.append([mimic["joint"], joint["name"]])
    for side in ("L", "R"):
        coupled.extend([f"{side}Phalanx1", f"{side}Phalanx{k}"] for k in range(2, 9))
    envelope = data["real_robot_reference"]["head_pitch_limits_vs_head_yaw_rad"]
    doc = {
        "_comment": (
            "GENERATED by motiontool.kinematics._modelgen; do not edit. The real NAO V5's limits, "
            "applied by motiontool.kinematics.robots on top of nao.xml (same kinematics)."
        ),
        "source": f"robots/{source.name}",
        "source_sha256": _sha256(source),
        "base_model": "nao.xml",
        "joints_note": (
            "Per joint, the ROS naoV50 URDF values (the physical robot) where they differ from the "
            "Webots PROTO: lower/upper in rad, max_velocity in rad/s, max_torque in N m."
        ),
        "joints": joints,
        "head_pitch_envelope_note": (
            "Rows (HeadYaw, HeadPitch min, HeadPitch max) in rad, HeadYaw ascending; linear "
            "interpolation between rows. " + envelope["note"]
        ),
        "head_pitch_envelope": envelope["rows"],
        "coupled_joints_note": (
            "Pairs (leader, follower) that one motor drives on the real robot: q[follower] == "
            "q[leader]. " + data["hip_yaw_pitch_coupling"] + " " + data["hand_model"]["real_robot"]
        ),
        "coupled_joints": coupled,
    }
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"


# --------------------------------------------------------------------------- UR5e


def _ur5e_xml(data: dict[str, Any], source: Path) -> str:
    joints = data["joints"]
    bodies, children = _tree(data)
    timestep_ms = data["webots_world_defaults"]["ure.wbt"]["basicTimeStep_ms"]

    root = ET.Element("mujoco", {"model": "ur5e"})
    _el(root, "compiler", angle="radian", autolimits="true", inertiafromgeom="false")
    _el(root, "option", timestep=_num(_PHYSICS_TIMESTEP_S), integrator="implicitfast")
    custom = _el(root, "custom")
    _el(custom, "numeric", name="webots_basic_time_step_ms", data=_num(timestep_ms))
    world = _el(root, "worldbody")

    def add_body(parent: ET.Element, name: str, joint: dict[str, Any] | None) -> None:
        body = bodies[name]
        if joint is None:
            el = _el(parent, "body", name=name, pos="0 0 0")
            _comment(
                el,
                "PROTO staticBase TRUE: the base is pinned to the world (no joint, no mass). "
                "Webots PROTO default selfCollision TRUE: all geoms collide (MuJoCo skips "
                "parent-child pairs).",
            )
            _el(el, "inertial", pos="0 0 0", mass="0", diaginertia="0 0 0")
        else:
            el = _hinge_body(parent, name, joint)
        if body["mass"] is not None:
            _comment(
                el,
                "mass and CoM from the PROTO; the PROTO has no inertiaMatrix: tensor from "
                "MuJoCo Menagerie (as chosen in ur5e.json)",
            )
            full, _ = _balanced(body["inertia"])
            _inertial(el, body, full)
        for i, prim in enumerate(body["webots_bounding_object"]):
            _geom(el, f"{name}_{i}", prim)
        if name == "wrist_3_link":
            _el(el, "site", name="tool_slot", pos="0 0.1 0", size="0.005")
        for child in children.get(name, []):
            add_body(el, child["child_body"], child)

    (root_body,) = [b["name"] for b in data["bodies"] if b["parent_joint"] is None]
    add_body(world, root_body, None)
    contact = _el(root, "contact")
    _comment(
        contact,
        "MuJoCo's parent-child filter skips children of a body welded to the world: exclude "
        "the base's child explicitly (Webots never collides directly jointed Solids).",
    )
    for joint in children[root_body]:
        _el(contact, "exclude", body1=root_body, body2=joint["child_body"])
    _add_actuators(root, joints)
    header = _header(
        "Webots UR5e (Universal Robots): 6 motors, fixed base.",
        source,
        data,
        [
            *_COMMON_NOTES,
            "* Site tool_slot: the PROTO toolSlot pose in wrist_3_link.",
        ],
    )
    return _render(root, header)


# --------------------------------------------------------------------------- entry points


def generate(source_dir: Path) -> dict[str, str]:
    """Build every output file's text from the JSON in ``source_dir``; keys are file names."""
    nao_src, ur_src = (source_dir / name for name in _SOURCES)
    nao = json.loads(nao_src.read_text(encoding="utf-8"))
    ur5e = json.loads(ur_src.read_text(encoding="utf-8"))
    return {
        "nao.xml": _nao_xml(nao, nao_src),
        "nao-v5.json": _nao_v5(nao, nao_src),
        "ur5e.xml": _ur5e_xml(ur5e, ur_src),
    }


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m motiontool.kinematics._modelgen", description=__doc__.splitlines()[0]
    )
    parser.add_argument(
        "source_dir",
        type=Path,
        metavar="robots-dir",
        help="folder holding nao.json and ur5e.json (e.g. tests/data/robot_facts)",
    )
    parser.add_argument("output_dir", type=Path, help="folder to write the models into")
    parser.add_argument(
        "--check", action="store_true", help="write nothing; exit 1 if a file is out of date"
    )
    args = parser.parse_args(argv)
    for name in _SOURCES:
        if not (args.source_dir / name).is_file():
            parser.error(
                f"{args.source_dir / name}: not found (robots-dir holds {' and '.join(_SOURCES)})"
            )
    outputs = generate(args.source_dir)
    stale = []
    for name in _OUTPUTS:
        target = args.output_dir / name
        data = outputs[name].encode("utf-8")
        if target.exists() and target.read_bytes() == data:
            continue
        stale.append(name)
        if not args.check:
            args.output_dir.mkdir(parents=True, exist_ok=True)
            target.write_bytes(data)
    verb = "out of date" if args.check else "written"
    for name in stale:
        print(f"{args.output_dir / name}: {verb}")
    return 1 if (args.check and stale) else 0


if __name__ == "__main__":
    sys.exit(main())
