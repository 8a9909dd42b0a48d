"""What the authoring commands (mirror, concat, trim, scale) share: the robot option, time
arguments, and the robot checks they run on their result."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Annotated

import typer

from motiontool.kinematics.robots import RobotSpec, builtin_robots, detect_robot, load_robot
from motiontool.motionfmt.diagnostics import Diagnostic
from motiontool.motionfmt.document import MotionDocument
from motiontool.motionfmt.errors import MotionToolError
from motiontool.motionfmt.reader import ReadResult, read_bytes

__all__ = ["RobotOption", "check_result", "need_robot", "num", "parse_time_ms", "pick_robot"]

RobotOption = Annotated[
    str,
    typer.Option(
        "--robot",
        "-r",
        help="Robot: auto (the built-in robot with half of the file's joints or more), nao, "
        "nao-v5, ur5e, a .urdf/.xml path, or erd:<name>.",
    ),
]


def num(x: float) -> str:
    return f"{x:.6g}"


def pick_robot(name: str, joints: Sequence[str]) -> RobotSpec | None:
    """The robot named by ``--robot``: ``auto`` detects it from ``joints`` (None when no
    built-in robot fits), ``none`` is None, anything else is loaded."""
    if name == "none":
        return None
    if name == "auto":
        found = detect_robot(joints)
        return None if found is None else load_robot(found)
    return load_robot(name)


def need_robot(name: str, joints: Sequence[str]) -> RobotSpec:
    """:func:`pick_robot`, for a command that cannot work without a robot.

    Raises:
        MotionToolError: ``none``, or ``auto`` and no built-in robot fits.
    """
    spec = pick_robot(name, joints)
    if spec is None:
        if name == "none":
            raise MotionToolError("this command needs a robot's joints and limits: give --robot")
        raise MotionToolError(
            "no built-in robot ("
            + ", ".join(builtin_robots())
            + ") has half of the joints of this motion or more; name one with --robot"
        )
    return spec


def check_result(
    doc: MotionDocument, check: Callable[[ReadResult], list[Diagnostic]]
) -> list[Diagnostic]:
    """What one of validate's robot checks reports on ``doc``."""
    return check(read_bytes(doc.to_bytes(), doc.path))


def parse_time_ms(text: str, option: str) -> int:
    """A time given as ``1500`` (ms), ``1:500`` (s:ms) or ``0:01:500`` (m:s:ms), in ms."""
    fields = text.strip().split(":")
    if not 1 <= len(fields) <= 3 or not all(f.isdigit() for f in fields):
        raise MotionToolError(
            f"{option} expects a time in ms (1500), s:ms (1:500) or m:s:ms (00:01:500), "
            f"got '{text}'"
        )
    scale = (1, 1000, 60000)[: len(fields)]
    return sum(int(f) * s for f, s in zip(reversed(fields), scale, strict=True))
