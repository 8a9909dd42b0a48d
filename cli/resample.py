"""``motiontool resample``: keyframes on a uniform grid, or fewer keyframes, within a bound."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from motiontool.cli import jsontext
from motiontool.cli._authoring import (
    destination,
    load_input,
    output_target,
    report_header,
    say,
    write_blocks,
)
from motiontool.cli.options import (
    MAX_MS,
    Format,
    FormatOption,
    InPlace,
    MotionFile,
    Output,
    finite,
)
from motiontool.cli.text import num, plural
from motiontool.errors import MotionToolError
from motiontool.motionfmt.compare import MotionDiff
from motiontool.motionfmt.fileio import source_name
from motiontool.motionfmt.resample import ROUNDING_RAD, Resampled, resample

__all__ = ["deviation_json", "deviation_text", "resample_command"]


def deviation_text(diff: MotionDiff) -> str:
    """One line: the largest deviation of a transformed motion from the original."""
    worst = diff.largest
    if worst is None or worst.at_ms is None:
        line = "largest deviation from the original command stream: none (no joint commanded)"
    elif worst.max_delta <= ROUNDING_RAD:
        line = (
            f"largest deviation from the original command stream: {num(worst.max_delta)} rad "
            "(floating-point rounding only)"
        )
    else:
        line = (
            f"largest deviation from the original command stream: {num(worst.max_delta)} rad "
            f"at {worst.at_ms} ms ({worst.joint})"
        )
    line += f", compared every {diff.timestep_ms} ms\n"
    presence = [j for j in diff.joints if j.old_only_steps or j.new_only_steps]
    for j in presence:
        line += (
            f"  {j.joint}: commanded where the original sends no command (or the reverse) at "
            f"{j.old_only_steps + j.new_only_steps} steps, first at {j.presence_at_ms} ms\n"
        )
    return line


def deviation_json(diff: MotionDiff) -> dict[str, Any]:
    worst = diff.largest
    return {
        "max_delta": None if worst is None else worst.max_delta,
        "at_ms": None if worst is None else worst.at_ms,
        "joint": None if worst is None else worst.joint,
        "compared_every_ms": diff.timestep_ms,
        "joints": [j.to_json() for j in diff.joints],
    }


def _text(r: Resampled, source: Path, target: Path | None, max_error: float | None) -> str:
    old_poses = r.deviation.old_poses
    poses = f"{old_poses} -> {r.deviation.new_poses} poses"
    lines = [f"resampled {source_name(source)} -> {destination(target)}: {poses}"]
    if r.step_ms is not None:
        if r.grid_has_keyframes:
            lines.append(
                f"grid: every {r.step_ms} ms; it holds every original pose time, so the result "
                f"is lossless ({plural(r.inserted, 'pose')} inserted on their segments)"
            )
        else:
            lines.append(
                f"grid: every {r.step_ms} ms; {plural(r.dropped_off_grid, 'original pose')} off "
                f"the grid dropped, {plural(r.inserted, 'pose')} inserted: NOT lossless"
            )
    if max_error is not None:
        lines.append(
            f"removed {r.removed} of {old_poses - r.dropped_off_grid + r.inserted} keyframes "
            f"({r.collinear} exactly collinear), keeping every joint within {num(max_error)} rad"
        )
    return "\n".join(lines) + "\n" + deviation_text(r.deviation)


def _json(r: Resampled, source: Path, target: Path | None, max_error: float | None) -> str:
    doc = {
        **report_header("motiontool.resample", source, target),
        "units": {"step_ms": "ms", "max_error": "rad (m for linear joints)", "max_delta": "rad"},
        "step_ms": r.step_ms,
        "max_error": max_error,
        "grid_has_keyframes": r.grid_has_keyframes,
        "poses": {"old": r.deviation.old_poses, "new": r.deviation.new_poses},
        "inserted": r.inserted,
        "dropped_off_grid": r.dropped_off_grid,
        "removed": r.removed,
        "collinear": r.collinear,
        "deviation": deviation_json(r.deviation),
    }
    return jsontext.dumps(doc)


def resample_command(
    path: MotionFile,
    step: Annotated[
        int | None,
        typer.Option(
            "--step",
            min=1,
            max=MAX_MS,
            help="Grid step in ms: keyframes at every multiple of it from the first to the last "
            "pose (both kept). Lossless when the grid holds every pose time.",
        ),
    ] = None,
    max_error: Annotated[
        float | None,
        typer.Option(
            "--max-error",
            min=0.0,
            callback=finite,
            help="Remove keyframes while every joint stays within this many rad of the "
            "original command stream (0: only exactly collinear ones).",
        ),
    ] = None,
    output: Output = None,
    in_place: InPlace = False,
    format: FormatOption = Format.text,
) -> None:
    """Put keyframes on a uniform time grid, or drop the ones the motion does not need.

    Kept lines keep their spelling; new poses are spelt canonically and named Pose<ms>ms. A new
    keyframe inside a segment that touches '*' gets '*': that span stays uncommanded. The report
    gives the largest deviation from the original command stream (rad, time, joint), compared
    at every millisecond.
    """
    if step is None and max_error is None:
        raise MotionToolError("give --step MS, --max-error RAD, or both")
    target = output_target(path, output, in_place)
    doc = load_input(path)
    result = resample(doc, step_ms=step, max_error=max_error)
    write_blocks(result.blocks(), target, result.n_poses, result.duration_ms)
    report = _json if format is Format.json else _text
    say(report(result, path, target, max_error), target)
