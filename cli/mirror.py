"""``motiontool mirror``: the left/right mirror image of a motion, signs from the model's axes."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from motiontool import exit_codes
from motiontool.cli import jsontext
from motiontool.cli._authoring import (
    check_result,
    destination,
    findings_json,
    findings_lines,
    load_input,
    output_target,
    report_header,
    say,
    values_count,
)
from motiontool.cli.options import Format, FormatOption, InPlace, Output, robot_option
from motiontool.cli.output import emit_bytes, say_wrote, written_motion
from motiontool.cli.progress import progress
from motiontool.cli.text import plural
from motiontool.errors import MotionToolError
from motiontool.kinematics.checks import Limits
from motiontool.kinematics.mirror import MirrorMap, mirror_map
from motiontool.kinematics.robots import AUTO, NONE, resolve_robot
from motiontool.motionfmt.diagnostics import Diagnostic
from motiontool.motionfmt.fileio import source_name
from motiontool.motionfmt.ops.mirror import Mirrored, mirror
from motiontool.motionfmt.reader import read_bytes
from motiontool.motionfmt.units import MM_PER_M
from motiontool.stamps import stamps

__all__ = ["mirror_command"]


def _map_lines(m: MirrorMap) -> list[str]:
    lines = [f"mirror map of {m.robot} (model {m.model_hash[:12]}), reflection y -> -y:"]
    for p in m.pairs:
        sign = "keeps its sign" if p.sign > 0 else "negated"
        lines.append(f"  {p.joint} -> {p.partner}: {sign} ((M a).b = {p.dot:+.6g})")
    lines.append(
        f"largest anchor asymmetry: {m.largest_offset_m * MM_PER_M:.1f} mm"
        " (0 for a symmetric model)"
    )
    return lines


def _map_json(m: MirrorMap) -> list[dict[str, Any]]:
    return [
        {
            "joint": p.joint,
            "partner": p.partner,
            "sign": p.sign,
            "dot": p.dot,
            "offset_m": p.offset_m,
        }
        for p in m.pairs
    ]


def _map_doc(m: MirrorMap) -> dict[str, Any]:
    """The JSON report of ``mirror --show-map`` alone (``motiontool.mirror_map``)."""
    return {
        "schema": "motiontool.mirror_map",
        "schema_version": 1,
        "stamps": stamps(m.model_hash),
        "robot": m.robot,
        "map": _map_json(m),
    }


def _text(
    r: Mirrored,
    m: MirrorMap,
    source: Path,
    target: Path | None,
    show_map: bool,
    new: list[Diagnostic],
) -> str:
    dest = destination(target)
    lines = [
        f"mirrored {source_name(source)} -> {dest}: robot {m.robot} (model {m.model_hash[:12]})"
    ]
    if r.swapped:
        lines.append("swapped: " + ", ".join(f"{a} <-> {b}" for a, b in r.swapped))
    if r.renamed:
        lines.append(
            "renamed (partner not in the file): " + ", ".join(f"{a} -> {b}" for a, b in r.renamed)
        )
    lines.append(
        "negated (roll/yaw axes: their mirror turns the other way): "
        + (", ".join(r.negated) if r.negated else "none")
    )
    if r.unmapped:
        lines.append(f"not motors of {m.robot}, unchanged: " + ", ".join(r.unmapped))
    if show_map:
        lines.extend(_map_lines(m))
    lines += findings_lines(
        new,
        f"limits: {values_count(new)} mirrored values fall outside the partner's limits (the "
        "model's left and right ranges differ):",
        "limits: every mirrored value within the partner's limits",
    )
    return "\n".join(lines) + "\n"


def _json(
    r: Mirrored, m: MirrorMap, source: Path, target: Path | None, new: list[Diagnostic]
) -> str:
    doc = {
        **report_header("motiontool.mirror", source, target, m.model_hash),
        "units": {"dot": "1", "offset_m": "m"},
        "robot": m.robot,
        "swapped": [list(p) for p in r.swapped],
        "renamed": [list(p) for p in r.renamed],
        "negated": list(r.negated),
        "unmapped": list(r.unmapped),
        "map": _map_json(m),
        "limit_findings": findings_json(new),
    }
    return jsontext.dumps(doc)


def mirror_command(
    path: Annotated[
        Path | None,
        typer.Argument(
            help="A motion file ('-': stdin); none with --show-map.", show_default=False
        ),
    ] = None,
    robot: Annotated[str, robot_option("Robot whose joint axes give the signs")] = AUTO,
    show_map: Annotated[
        bool,
        typer.Option(
            "--show-map", help="Print every joint's partner and sign (alone: the map only)."
        ),
    ] = False,
    output: Output = None,
    in_place: InPlace = False,
    format: FormatOption = Format.text,
) -> None:
    """Mirror a motion left/right: swap each L/R pair, negate the joints whose mirror image
    turns the other way.

    Signs come from the robot model's joint axes reflected through its x-z plane (on the Nao:
    pitch joints and HipYawPitch keep their sign; roll and yaw joints, HeadYaw included, are
    negated). A column whose partner is missing is renamed to it. Lines keep their spelling;
    a negated number keeps its digits. Mirroring twice gives back the same command stream.
    Exits 1 if a mirrored value falls outside the partner's limits (and the input's did not).
    """
    if path is None:
        if not show_map:
            raise MotionToolError("give a motion file to mirror, or --show-map --robot NAME")
        if robot in (AUTO, NONE):
            raise MotionToolError("--show-map without a motion file needs --robot NAME (e.g. nao)")
        m = mirror_map(resolve_robot(robot))
        if format is Format.json:
            typer.echo(jsontext.dumps(_map_doc(m)), nl=False)
        else:
            typer.echo("\n".join(_map_lines(m)))
        return
    target = output_target(path, output, in_place)
    doc = load_input(path)
    spec = resolve_robot(robot, doc.joints)
    m = mirror_map(spec)
    with progress("mirror") as step:
        step(f"{source_name(path)} ({plural(doc.n_poses, 'pose')})")
        result = mirror(doc, m.as_dict())
    limits = Limits(spec)
    before = check_result(doc.result, limits)
    after = check_result(read_bytes(result.data, result.path), limits)  # its one read
    new = after if values_count(after) > values_count(before) else []
    emit_bytes(result.data, target)
    say_wrote(target, written_motion(doc.n_poses, doc.motion.duration_ms))  # mirror keeps the times
    if format is Format.json:
        say(_json(result, m, path, target, new), target)
    else:
        say(_text(result, m, path, target, show_map, new), target)
    if new:
        raise typer.Exit(exit_codes.FINDINGS)
