"""Joint names between a motion and ROS: a robot's ROS driver may name a joint otherwise than
its Webots model. A joint map is a small flat table, the motion's joint -> the ROS name, in TOML
or YAML::

    # nao_ros.toml
    HeadYaw = "head_yaw_joint"

    # nao_ros.yaml
    HeadYaw: head_yaw_joint

A joint the map does not name keeps its name, but for the Nao's hands (:data:`NAO_HANDS`). The
built-in robots need no map: the UR5e's Webots motors are the names Universal Robots' ROS 2
driver publishes (``shoulder_pan_joint`` ... ``wrist_3_joint``), and the Webots Nao's are
NAOqi's, which ``naoqi_driver`` publishes, once its eight phalanges per hand are NAOqi's one
hand joint (``LPhalanx1..8`` -> ``LHand``).

Several joints may go to one ROS name (the phalanges of a hand, or a map's many-to-one): a ROS
joint has one position, so the first of them in the motion's order gives it, and the caller
checks that the others agree with it (:func:`disagreement`). Read back, a ROS name becomes the
first joint the map gives it, and a NAO's ``LHand`` the eight phalanges, but for those the map
keeps apart (:func:`spread_hands`).
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from motiontool.errors import MotionSyntaxError, MotionToolError
from motiontool.motionfmt.structured_text import load_toml, load_yaml, shown

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["NAO_HANDS", "disagreement", "from_ros", "parse_joint_map", "spread_hands", "to_ros"]

NAO_HANDS: dict[str, str] = {
    f"{side}Phalanx{i}": f"{side}Hand" for side in "LR" for i in range(1, 9)
}
"""Webots Nao motor -> the real robot's joint: one motor opens and closes each hand (``LHand``,
``RHand``: 0 closed to 1 open, as the simulated phalanges), the name NAOqi and ``naoqi_driver``
give it. The NAOqi export and the ROS exports name the hands by it."""


def _where(text: str, key: str) -> tuple[int, int]:
    """(line, column) of ``key`` where a line defines it, else (1, 1)."""
    quoted = "|".join(re.escape(q) for q in (key, f'"{key}"', f"'{key}'"))
    pattern = re.compile(rf"^(\s*)(?:{quoted})\s*[=:]")
    for number, line in enumerate(text.splitlines(), start=1):
        found = pattern.match(line)
        if found:
            return number, len(found.group(1)) + 1
    return 1, 1


def _load(text: str, path: str) -> Any:
    if path.lower().endswith(".toml"):
        return load_toml(text, path, "a joint map")
    if path.lower().endswith((".yaml", ".yml")):
        documents = [d for d in load_yaml(text, path, "a joint map") if d is not None]
        if len(documents) > 1:
            raise MotionSyntaxError("a joint map is one YAML document, not several", path, 1, 1)
        return documents[0] if documents else None
    raise MotionToolError(f"'{path}': a joint map is a .toml or a .yaml (.yml) file")


def parse_joint_map(data: bytes, path: str) -> tuple[tuple[str, str], ...]:
    """The (motion joint, ROS name) pairs of a joint map file, in file order (one ROS name
    may be given to several joints: :func:`to_ros`).

    Raises:
        MotionSyntaxError: not TOML or YAML, or a value that is not a name, at its line and
            column.
        MotionToolError: not a flat table, or a file that is neither ``.toml`` nor ``.yaml``.
    """
    text = data.decode("utf-8", "surrogateescape")
    table = _load(text, path)
    if table is None:
        table = {}
    if not isinstance(table, dict):
        raise MotionSyntaxError("a joint map is a table: joint = ROS name", path, 1, 1)
    pairs: list[tuple[str, str]] = []
    for key, value in table.items():
        joint = str(key)
        if not isinstance(value, str) or not value:
            line, col = _where(text, joint)
            raise MotionSyntaxError(
                f"{joint}: the ROS name must be a non-empty string, got {shown(value)}",
                path,
                line,
                col,
            )
        pairs.append((joint, value))
    return tuple(pairs)


def to_ros(joints: Sequence[str], joint_map: Sequence[tuple[str, str]]) -> tuple[str, ...]:
    """The ROS name of each of ``joints``: the map's, else :data:`NAO_HANDS`', else its own.
    Several joints may get one name (see the module)."""
    table: Mapping[str, str] = {**NAO_HANDS, **dict(joint_map)}
    return tuple(table.get(j, j) for j in joints)


def disagreement(
    values: npt.NDArray[np.float64], names: Sequence[str], tolerance: float
) -> tuple[int, int, int] | None:
    """The first cell where two columns that get one ROS name differ: (pose, the first
    column of that name, the column that differs from it), or None.

    Args:
        values: float64 (P, J), rad (m); NaN for ``*``.
        names: the ROS name of each of the J columns (:func:`to_ros`).
        tolerance: the largest difference that agrees, rad (m); ``*`` agrees with ``*`` only.
    """
    import numpy as np

    first: dict[str, int] = {}
    found: tuple[int, int, int] | None = None
    for j, name in enumerate(names):
        lead = first.setdefault(name, j)
        if lead == j:
            continue
        a, b = values[:, lead], values[:, j]
        with np.errstate(invalid="ignore"):
            apart = (np.isnan(a) != np.isnan(b)) | (np.abs(a - b) > tolerance)
        if apart.any():
            pose = int(np.argmax(apart))
            if found is None or (pose, j) < (found[0], found[2]):
                found = (pose, lead, j)
    return found


def from_ros(names: Sequence[str], joint_map: Sequence[tuple[str, str]]) -> tuple[str, ...]:
    """The motion joint of each ROS name (the map read backwards, else the name itself).

    Raises:
        MotionToolError: two ROS names would become one joint.
    """
    table: dict[str, str] = {}
    for joint, ros in joint_map:
        table.setdefault(ros, joint)
    joints = tuple(table.get(n, n) for n in names)
    _unique(joints, names, "joint")
    return joints


def spread_hands(joints: Sequence[str]) -> tuple[tuple[str, ...], list[int]]:
    """A real NAO's hands as the Webots Nao's phalanges (:data:`NAO_HANDS` read backwards):
    ``LHand`` becomes, in its place, those of ``LPhalanx1..8`` that the joints do not already
    have (a joint map that keeps ``LPhalanx7`` apart sends it under its own name), and stays
    ``LHand`` where they have all eight. Returns (the joints, the index in ``joints`` of each
    one's column)."""
    fingers: dict[str, list[str]] = {}
    for finger, hand in NAO_HANDS.items():
        fingers.setdefault(hand, []).append(finger)
    out: list[str] = []
    columns: list[int] = []
    for j, name in enumerate(joints):
        spread = [f for f in fingers.get(name, []) if f not in joints] or [name]
        out += spread
        columns += [j] * len(spread)
    return tuple(out), columns


def _unique(mapped: Sequence[str], given: Sequence[str], what: str) -> None:
    first: dict[str, str] = {}
    for new, old in zip(mapped, given, strict=True):
        if new in first:
            raise MotionToolError(
                f"{first[new]} and {old} both become {what} {new!r}: fix the joint map"
            )
        first[new] = old
