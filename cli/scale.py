"""``motiontool scale``: bigger or smaller moves about a reference pose, within the limits."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

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
    write_result,
)
from motiontool.cli.options import (
    Format,
    FormatOption,
    InPlace,
    MotionFile,
    Output,
    ResultTimestep,
    RobotOption,
    finite,
)
from motiontool.cli.text import num
from motiontool.kinematics.checks import Velocity
from motiontool.kinematics.robots import AUTO, RobotSpec, pick_robot
from motiontool.motionfmt.diagnostics import Diagnostic
from motiontool.motionfmt.fileio import source_name
from motiontool.motionfmt.ops.scale import Scaled, scale

__all__ = ["scale_command"]


def scale_command(
    path: MotionFile,
    amplitude: Annotated[
        float,
        typer.Option(
            "--amplitude",
            "-k",
            callback=finite,
            help="Factor K on every joint's excursion from the reference: q' = ref + K (q - ref).",
            show_default=False,
        ),
    ],
    about: Annotated[
        str,
        typer.Option(
            "--about",
            help="Reference pose: first (each joint's first commanded value), zero (the "
            "robot's zero pose) or the name of a pose of the file.",
        ),
    ] = "first",
    robot: RobotOption = AUTO,
    timestep: ResultTimestep = None,
    output: Output = None,
    in_place: InPlace = False,
    format: FormatOption = Format.text,
) -> None:
    """Scale a motion's amplitude about a reference pose, clipping to the robot's limits.

    Every commanded cell becomes ref + K (q - ref); a value beyond a joint's limits is set to
    the limit, and the clipped cells are reported (count, worst excess in the joint's unit).
    '*' stays '*', and cells that do not change keep their spelling. With K > 1 the moves get
    faster too: the result is checked with validate's velocity check, and the command exits 1
    if it finds more than in the input (then: motiontool retime --fit-limits). --robot none
    scales without clipping.
    """
    target = output_target(path, output, in_place)
    doc = load_input(path)
    spec = pick_robot(robot, doc.joints)
    limits = None if spec is None else {j.name: (j.lower, j.upper, j.unit) for j in spec.joints}
    result = scale(doc, amplitude, about=about, limits=limits)
    new: list[Diagnostic] = []
    if spec is not None:
        check = Velocity(spec, timestep)
        before = check_result(doc, check)
        after = check_result(result.document, check)
        new = after if values_count(after) > values_count(before) else []
    write_result(result.document, target)
    if format is Format.json:
        say(_json(result, path, target, spec, new), target)
    else:
        say(_text(result, path, target, spec, new), target)
    if new:
        raise typer.Exit(exit_codes.FINDINGS)


def _about(r: Scaled) -> str:
    if r.about == "first":
        return "each joint's first commanded value"
    if r.about == "zero":
        return "the zero pose (0 rad)"
    return f"pose '{r.about}'"


def _text(
    r: Scaled, source: Path, target: Path | None, spec: RobotSpec | None, new: list[Diagnostic]
) -> str:
    dest = destination(target)
    lines = [
        f"scaled {source_name(source)} -> {dest}: amplitude x{num(r.amplitude)} about {_about(r)}",
        f"changed {r.changed} cells",
    ]
    if spec is None:
        lines.append("limits: no robot (--robot none or none detected): nothing clipped")
    elif r.clips:
        lines.append(f"clipped {r.clipped} cells to {spec.name}'s limits:")
        for c in r.clips:
            side = "above its upper" if c.side == "upper" else "below its lower"
            lines.append(
                f"  {c.joint}: {c.count} cells, worst {num(c.worst_excess)} {c.unit} {side} "
                f"limit {num(c.bound)} {c.unit} at {c.at_ms} ms"
            )
    else:
        lines.append(f"limits: every scaled value within {spec.name}'s limits, nothing clipped")
    if spec is not None:
        unlimited = [j for j in r.unlimited if j not in spec]
        if unlimited:
            lines.append(f"not motors of {spec.name}, not clipped: " + ", ".join(unlimited))
        lines += findings_lines(
            new,
            f"velocity check: {values_count(new)} warnings (more than the input's); "
            "motiontool retime --fit-limits slows the fast segments down:",
            "velocity check: no warning more than the input's",
        )
    return "\n".join(lines) + "\n"


def _json(
    r: Scaled, source: Path, target: Path | None, spec: RobotSpec | None, new: list[Diagnostic]
) -> str:
    doc = {
        **report_header(
            "motiontool.scale", source, target, None if spec is None else spec.model_hash
        ),
        "units": {"worst_excess": "rad (m for linear joints)", "at_ms": "ms", "bound": "rad (m)"},
        "robot": None if spec is None else spec.name,
        "amplitude": r.amplitude,
        "about": r.about,
        "changed": r.changed,
        "clipped": r.clipped,
        "clips": [
            {
                "joint": c.joint,
                "count": c.count,
                "worst_excess": c.worst_excess,
                "unit": c.unit,
                "at_ms": c.at_ms,
                "bound": c.bound,
                "side": c.side,
            }
            for c in r.clips
        ],
        "new_velocity_findings": findings_json(new),
    }
    return jsontext.dumps(doc)
