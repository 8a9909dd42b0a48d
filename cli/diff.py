"""``motiontool diff``: do two motion files command the robot the same way?"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated, Any

import typer

from motiontool import exit_codes
from motiontool.cli.jsontext import dumps
from motiontool.cli.options import Format, FormatOption, finite, timestep_option
from motiontool.cli.output import refuse_overwrite, say_wrote
from motiontool.cli.text import file_name, num, plural
from motiontool.errors import MotionToolError
from motiontool.extras import require
from motiontool.motionfmt.compare import (
    DEFAULT_TOLERANCE_RAD,
    JointDiff,
    MotionDiff,
    compare_motions,
    held_pair,
)
from motiontool.motionfmt.fileio import atomic_write, read_file, source_name
from motiontool.motionfmt.motion import Motion
from motiontool.motionfmt.reader import read_bytes
from motiontool.stamps import stamps

__all__ = ["diff_command"]


def _ordered(diff: MotionDiff) -> list[JointDiff]:
    """Changed joints, largest |Δq| first, then by name (the same order both ways round)."""
    return sorted(diff.changed, key=lambda j: (-j.max_delta, j.joint))


def _joint_line(j: JointDiff, tolerance: float, width: int) -> str:
    parts = []
    if j.max_delta > tolerance and j.at_ms is not None:
        parts.append(
            f"|Δq| {num(j.max_delta)} rad at {j.at_ms} ms "
            f"(old {num(j.old_value or 0.0)} rad, new {num(j.new_value or 0.0)} rad)"
        )
    if j.old_only_steps:
        parts.append(f"held only by old at {j.old_only_steps} steps")
    if j.new_only_steps:
        parts.append(f"held only by new at {j.new_only_steps} steps")
    if j.old_only_steps or j.new_only_steps:
        parts[-1] += f" (first at {j.presence_at_ms} ms)"
    return f"  {j.joint:<{width}}  " + "; ".join(parts)


def _text(diff: MotionDiff, old: Path, new: Path) -> str:
    grid = f"every {diff.timestep_ms} ms"
    if not diff.every_step:  # a motion lasting days: the steps next to each pose time
        grid = (
            f"at the {diff.compared_steps:,} of the {diff.grid_steps:,} steps of {diff.timestep_ms}"
            " ms next to each pose time, where |Δq| peaks; not the rounding between them"
        )
    how = f"every joint within {num(diff.tolerance)} rad, compared {grid}"
    lines = []
    if diff.same:
        lines.append(
            f"same: {source_name(old)} and {source_name(new)} command the same motion ({how})"
        )
    else:
        tolerance = how.replace("every joint within", "tolerance")
        lines.append(f"different: {source_name(old)} -> {source_name(new)} ({tolerance})")
    if diff.added:
        lines.append(f"joints added: {', '.join(diff.added)}")
    if diff.removed:
        lines.append(f"joints removed: {', '.join(diff.removed)}")
    if diff.reordered:
        lines.append("joint columns re-ordered (the robot is commanded the same)")
    if diff.old_duration_ms != diff.new_duration_ms:
        change = diff.new_duration_ms - diff.old_duration_ms
        lines.append(
            f"duration: {diff.old_duration_ms} ms -> {diff.new_duration_ms} ms ({change:+d} ms)"
        )
    if diff.old_poses != diff.new_poses:
        lines.append(f"poses: {diff.old_poses} -> {diff.new_poses}")
    changed = _ordered(diff)
    if changed:
        lines.append("joints commanded differently (largest |Δq| first):")
        width = max(len(j.joint) for j in changed)
        lines.extend(_joint_line(j, diff.tolerance, width) for j in changed)
        rest = len(diff.joints) - len(changed)
        if rest:
            lines.append(f"{rest} other joints within {num(diff.tolerance)} rad")
    return "\n".join(lines) + "\n"


def _json(diff: MotionDiff, old: Path, new: Path) -> str:
    doc: dict[str, Any] = {
        "schema": "motiontool.diff",
        "schema_version": 1,
        "stamps": stamps(),
        "old": source_name(old),
        "new": source_name(new),
        "same": diff.same,
        "units": {
            "tolerance": "rad (m for linear joints)",
            "max_delta": "rad (m for linear joints)",
            "old_value": "rad",
            "new_value": "rad",
            "duration_ms": "ms",
            "timestep_ms": "ms",
        },
        "tolerance": diff.tolerance,
        "timestep_ms": diff.timestep_ms,
        "grid_steps": diff.grid_steps,
        "compared_steps": diff.compared_steps,
        "joints_added": list(diff.added),
        "joints_removed": list(diff.removed),
        "joints_reordered": diff.reordered,
        "duration_ms": {"old": diff.old_duration_ms, "new": diff.new_duration_ms},
        "poses": {"old": diff.old_poses, "new": diff.new_poses},
        "changed": [j.joint for j in _ordered(diff)],
        "joints": [j.to_json() for j in diff.joints],
    }
    return dumps(doc)


def _plot(diff: MotionDiff, a: Motion, b: Motion, old: Path, new: Path, out: Path) -> None:
    from motiontool.cli._plotting import plot_diff

    changed = [j.joint for j in _ordered(diff)]
    joints = changed or [j.joint for j in diff.joints]
    # The steps that shape the lines, not every step: any duration, the same lines.
    elapsed, held_a, held_b = held_pair(a, b, diff.timestep_ms, joints)
    verdict = "same" if diff.same else "different"
    if changed:
        verdict += f": {len(changed)} joint{' differs' if len(changed) == 1 else 's differ'}"
    png = plot_diff(
        elapsed,
        {n: held_a[:, k] for k, n in enumerate(joints)},
        {n: held_b[:, k] for k, n in enumerate(joints)},
        joints,
        title=f"{file_name(old)} -> {file_name(new)}: {verdict} "
        f"(tolerance {num(diff.tolerance)} rad)",
        caption=f"motiontool {stamps()['motiontool']}\nheld targets every {diff.timestep_ms} ms:"
        " old grey, new blue, difference shaded red",
        comment=json.dumps(stamps(), sort_keys=True),
    )
    atomic_write(out, png)
    say_wrote(out, f"PNG plot, {plural(len(joints), 'joint')}")


def diff_command(
    old: Annotated[
        Path, typer.Argument(help="The old motion file ('-': stdin).", show_default=False)
    ],
    new: Annotated[
        Path, typer.Argument(help="The new motion file ('-': stdin).", show_default=False)
    ],
    tolerance: Annotated[
        float,
        typer.Option(
            "--tolerance",
            min=0.0,
            callback=finite,
            help="Largest |Δq| in rad that still counts as the same.",
        ),
    ] = DEFAULT_TOLERANCE_RAD,
    format: FormatOption = Format.text,
    plot: Annotated[
        Path | None,
        typer.Option("--plot", help="Also draw the joints that differ (old vs new) into a PNG."),
    ] = None,
    timestep: Annotated[
        int,
        timestep_option("1: every time any controller can sample", use="compare at its steps"),
    ] = 1,
) -> None:
    """Compare what two motion files command, joint by joint (matched by name).

    Both files are played as Webots plays them, on a common grid of playback times; where a
    joint gets no command ('*'), the target its motor holds (the last one commanded) is compared.
    Re-spelt numbers, re-spaced keyframes on the same lines and re-ordered columns are the same
    motion. Exit code 0 same within --tolerance, 1 different, 2 error.
    """
    if plot is not None and str(plot) == "-":
        raise MotionToolError("--plot -: the report goes to stdout; name a PNG file to write")
    refuse_overwrite(plot, [old, new], "--plot", "write the PNG to another file")
    if plot is not None:
        require("matplotlib", "plot", "motiontool diff --plot")
    a = read_bytes(read_file(old), source_name(old)).motion
    b = read_bytes(read_file(new), source_name(new)).motion
    diff = compare_motions(a, b, timestep_ms=timestep, tolerance=tolerance)
    text = _json(diff, old, new) if format is Format.json else _text(diff, old, new)
    typer.echo(text, nl=False)
    if plot is not None:
        _plot(diff, a, b, old, new, plot)
    if not diff.same:
        raise typer.Exit(exit_codes.FINDINGS)
