"""What the authoring commands (mirror, concat, trim, scale) share: time arguments, and the
robot checks they run on their result. Their options are in :mod:`motiontool.cli.options`; a
robot is chosen by :func:`motiontool.kinematics.robots.resolve_robot` (or ``pick_robot``)."""

from __future__ import annotations

from collections.abc import Callable

from motiontool.motionfmt.diagnostics import Diagnostic
from motiontool.motionfmt.document import MotionDocument
from motiontool.motionfmt.errors import MotionToolError
from motiontool.motionfmt.reader import ReadResult, read_bytes

__all__ = ["check_result", "num", "parse_time_ms"]


def num(x: float) -> str:
    return f"{x:.6g}"


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
