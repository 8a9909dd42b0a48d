"""What the authoring commands (mirror, concat, trim, scale, resample, retime) share: time
arguments, the robot checks they run on their result, and how they report it. Their options are
in :mod:`motiontool.cli.options`; a robot is chosen by
:func:`motiontool.kinematics.robots.resolve_robot` (or ``pick_robot``)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from motiontool.motionfmt.diagnostics import Diagnostic
from motiontool.motionfmt.document import MotionDocument
from motiontool.motionfmt.errors import MotionToolError
from motiontool.motionfmt.fileio import source_name
from motiontool.motionfmt.reader import ReadResult, read_bytes
from motiontool.stamps import stamps

__all__ = ["check_result", "findings_lines", "num", "parse_time_ms", "report_header"]


def num(x: float) -> str:
    return f"{x:.6g}"


def check_result(
    doc: MotionDocument, check: Callable[[ReadResult], list[Diagnostic]]
) -> list[Diagnostic]:
    """What one of validate's robot checks reports on ``doc``."""
    return check(read_bytes(doc.to_bytes(), doc.path))


def findings_lines(findings: list[Diagnostic], heading: str, clean: str) -> list[str]:
    """The report lines of a check on a command's result: ``heading`` then one indented
    ``path:line:col: CODE: message`` line per finding, or ``clean`` when there is none."""
    if not findings:
        return [clean]
    return [heading, *(f"  {d.path}:{d.line}:{d.column}: {d.code}: {d.message}" for d in findings)]


def report_header(
    schema: str, source: Path, target: Path | None, model_hash: str | None = None
) -> dict[str, Any]:
    """The first keys of a one-input command's JSON report: ``schema`` (``motiontool.trim``),
    its version, the stamps (with the robot model's hash, if one was used), input and output
    (None: stdout)."""
    return {
        "schema": schema,
        "schema_version": 1,
        "stamps": stamps(model_hash),
        "input": source_name(source),
        "output": None if target is None else str(target),
    }


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
