"""What the authoring commands (mirror, concat, trim, scale, resample, retime) share: where the
result goes (``-o`` or ``--in-place``, never over the input otherwise), time arguments, the robot
checks they run on their result, and how they report it. Their options are in
:mod:`motiontool.cli.options`; a robot is chosen by
:func:`motiontool.kinematics.robots.resolve_robot` (or ``pick_robot``)."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import typer

from motiontool.cli.output import (
    refuse_overwrite,
    same_file,
    say_wrote,
    written_motion,
)
from motiontool.errors import MotionToolError
from motiontool.motionfmt.diagnostics import Diagnostic
from motiontool.motionfmt.document import MotionDocument, loads
from motiontool.motionfmt.fileio import STDOUT, is_stdin, open_output, read_file, source_name
from motiontool.motionfmt.reader import ReadResult
from motiontool.motionfmt.units import time_fields_ms
from motiontool.motionfmt.validate import run_check
from motiontool.stamps import stamps

if TYPE_CHECKING:
    from motiontool.motionfmt.validate import Check

__all__ = [
    "check_result",
    "destination",
    "findings_json",
    "findings_lines",
    "load_input",
    "output_target",
    "parse_time_ms",
    "read_result",
    "report_header",
    "say",
    "values_count",
    "write_result",
]


def output_target(path: Path, output: Path | None, in_place: bool) -> Path | None:
    """Where to write the result of transforming ``path``: a file, or None for stdout.

    Raises :class:`MotionToolError` when neither ``-o`` nor ``--in-place`` is given, when ``-o``
    names the input (or a symlink or hard link to it) without ``--in-place``, when both name
    different files, or for ``--in-place`` on standard input (``-``).
    """
    if in_place and is_stdin(path):
        raise MotionToolError(
            "--in-place cannot replace standard input ('-'); give -o FILE, or -o - for stdout"
        )
    if output is not None and str(output) == "-":
        if in_place:
            raise MotionToolError("--in-place writes the input file; do not give -o - with it")
        return None
    if in_place:
        if output is not None and not same_file(output, path):
            raise MotionToolError(
                f"--in-place writes '{path}'; -o names another file '{output}': give one of them"
            )
        return path
    if output is None:
        raise MotionToolError(
            f"say where to write the result: -o FILE, -o - for stdout, or --in-place to "
            f"replace '{path}'"
        )
    refuse_overwrite(
        output, [path], "-o", "add --in-place to overwrite it, or write to another file"
    )
    return output


def load_input(path: Path) -> MotionDocument:
    """The input as a lossless document (:class:`MotionSyntaxError` where Webots rejects it);
    ``-`` reads standard input."""
    return loads(read_file(path), source_name(path))


def write_result(doc: MotionDocument, target: Path | None) -> None:
    """Write ``doc`` atomically to ``target``, or to stdout when None; a file written is said
    on stderr (:func:`~motiontool.cli.output.say_wrote`). The document is read first (an
    edited one: its bytes joined once, and kept as what it writes)."""
    duration_ms = doc.motion.duration_ms
    write_blocks((doc.to_bytes(),), target, doc.n_poses, duration_ms)


def write_blocks(
    blocks: Iterable[bytes], target: Path | None, n_poses: int, duration_ms: int
) -> None:
    """Write a motion of ``n_poses`` poses lasting ``duration_ms`` (ms), given a block of
    bytes at a time, as :func:`write_result` writes one: never all held."""
    with open_output(STDOUT if target is None else target) as sink:
        for block in blocks:
            sink.write(block)
    say_wrote(target, written_motion(n_poses, duration_ms))


def say(text: str, target: Path | None) -> None:
    """Print a report: on stdout, or on stderr when the motion itself goes to stdout."""
    typer.echo(text, nl=False, err=target is None)


def read_result(doc: MotionDocument | ReadResult) -> ReadResult:
    """``doc`` as Webots reads it (a document's current bytes, read once: see
    :attr:`MotionDocument.result`)."""
    return doc if isinstance(doc, ReadResult) else doc.result


def check_result(doc: MotionDocument | ReadResult, check: Check) -> list[Diagnostic]:
    """What one of validate's robot checks reports on ``doc``, grouped as validate groups it
    by default (a run of one code on one joint is one finding: a handful, whatever the
    file's size)."""
    return list(run_check(check, read_result(doc), group=True))


def values_count(findings: Sequence[Diagnostic]) -> int:
    """How many values (poses, segments) ``findings`` stand for (a grouped finding, many)."""
    return sum(d.count for d in findings)


def findings_lines(findings: list[Diagnostic], heading: str, clean: str) -> list[str]:
    """The report lines of a check on a command's result: ``heading`` then one indented
    ``path:line:col: CODE: message`` line per finding, or ``clean`` when there is none."""
    if not findings:
        return [clean]
    return [heading, *(f"  {d.path}:{d.line}:{d.column}: {d.code}: {d.message}" for d in findings)]


def findings_json(findings: list[Diagnostic]) -> list[dict[str, Any]]:
    """The JSON of a check's findings on a command's result: code, line, column, message and
    how many values a finding stands for."""
    return [
        {"code": d.code, "line": d.line, "column": d.column, "message": d.message, "count": d.count}
        for d in findings
    ]


def destination(target: Path | None) -> str:
    """Where the result went, for a report: the file, or ``stdout`` (None)."""
    return "stdout" if target is None else str(target)


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
    return time_fields_ms([int(f) for f in fields])
