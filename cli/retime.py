"""``motiontool retime``: new pose times, never new values."""

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
    write_blocks,
    write_result,
)
from motiontool.cli.options import (
    MAX_MS,
    Format,
    FormatOption,
    InPlace,
    MotionFile,
    Output,
    ResultTimestep,
    finite,
    robot_option,
)
from motiontool.cli.text import num
from motiontool.errors import MotionToolError
from motiontool.kinematics.checks import Velocity
from motiontool.kinematics.robots import AUTO, RobotSpec, resolve_robot
from motiontool.motionfmt.diagnostics import Diagnostic
from motiontool.motionfmt.document import MotionDocument
from motiontool.motionfmt.fileio import source_name
from motiontool.motionfmt.nonfinite import refuse_non_finite
from motiontool.motionfmt.retime import (
    DEFAULT_MARGIN,
    Retimed,
    fit_duration,
    fit_limits,
    retimed_blocks,
    scale_times,
)

__all__ = ["retime_command"]

_LISTED = 10  # stretched segments listed in the text report (all of them in JSON)


def _duration_line(r: Retimed) -> str:
    pct = r.added_percent
    share = "" if pct is None else f", {pct:+.1f}%"
    return f"duration: {r.old_duration_ms} ms -> {r.duration_ms} ms ({r.added_ms:+d} ms{share})"


def _stretch_lines(r: Retimed) -> list[str]:
    out = []
    for s in r.stretches[:_LISTED]:
        t0, t1 = r.old_times_ms[s.segment], r.old_times_ms[s.segment + 1]
        out.append(
            f"  {t0} ms to {t1} ms (poses {s.segment + 1} to {s.segment + 2}): "
            f"{s.old_ms} ms -> {s.new_ms} ms, {s.joint} ({s.reason})"
        )
    if len(r.stretches) > _LISTED:
        out.append(f"  ... and {len(r.stretches) - _LISTED} more (--format json lists them all)")
    return out


_Speed = Annotated[
    float | None,
    typer.Option(
        "--speed",
        callback=finite,
        help="Play this many times as fast: 0.5 takes twice as long (times scaled from 0).",
    ),
]
_Duration = Annotated[
    int | None,
    typer.Option(
        "--duration", min=0, max=MAX_MS, help="Scale the times so the last pose is at this ms."
    ),
]
_FitLimits = Annotated[
    bool,
    typer.Option(
        "--fit-limits",
        help="Stretch each segment that is too fast for a joint to the shortest duration "
        "within maxVelocity x margin, in whole controller steps (-t, else the robot's) where "
        "it was a whole number of them, else whole ms; other segments keep theirs.",
    ),
]
_Robot = Annotated[str, robot_option("Robot whose limits --fit-limits uses")]
_Margin = Annotated[
    float,
    typer.Option(
        "--margin",
        callback=finite,
        help="Fraction of maxVelocity --fit-limits allows, in (0, 1].",
    ),
]
_Accel = Annotated[
    float | None,
    typer.Option(
        "--accel",
        callback=finite,
        help="Also limit each joint's velocity change at a pose to this many rad/s² "
        "(over the half segments around it; the motion starts and ends at rest).",
    ),
]


def _fit_to(
    spec: RobotSpec, doc: MotionDocument, margin: float, accel: float | None, timestep: int | None
) -> Retimed:
    """``--fit-limits``: ``doc``'s times stretched to ``spec``'s velocity limits, in whole
    controller steps (``timestep``, else the robot's) where a segment was whole steps."""
    motion = doc.motion
    # A nan/inf command has no speed to fit (and an infinite one no finite duration).
    refuse_non_finite(motion, doc.result, "fitting it to the robot's limits")
    return fit_limits(
        [int(t) for t in motion.times_ms],
        motion.joints,
        motion.values,
        {j.name: j.max_velocity for j in spec.joints},
        margin=margin,
        max_acceleration=accel,
        step_ms=timestep or spec.default_timestep_ms,
    )


def retime_command(
    path: MotionFile,
    speed: _Speed = None,
    duration: _Duration = None,
    fit: _FitLimits = False,
    robot: _Robot = AUTO,
    margin: _Margin = DEFAULT_MARGIN,
    accel: _Accel = None,
    timestep: ResultTimestep = None,
    output: Output = None,
    in_place: InPlace = False,
    format: FormatOption = Format.text,
) -> None:
    """Change pose times only, never values: --speed, --duration or --fit-limits.

    Times are whole ms, rounded so that no limit is exceeded and they stay strictly increasing;
    the lines keep their spelling except for the times that change. --fit-limits checks the
    result with validate's velocity check and exits 1 if a warning remains (a target jump after
    a '*' stretch, which no retiming removes). Running it again changes nothing.
    """
    _refuse_modes(speed, duration, fit, accel)
    target = output_target(path, output, in_place)
    doc = load_input(path)
    motion = doc.motion
    times = [int(t) for t in motion.times_ms]
    spec: RobotSpec | None = None
    findings: list[Diagnostic] = []
    if speed is not None:
        result = scale_times(times, speed)
        how = f"speed x{num(speed)}"
    elif duration is not None:
        result = fit_duration(times, duration)
        how = f"duration {duration} ms"
    else:
        spec = resolve_robot(robot, motion.joints)
        result = _fit_to(spec, doc, margin, accel, timestep)
        how = f"fit to {spec.name}'s limits"
    times_ms = list(result.times_ms)
    if spec is None:  # times only: the lines are written a block at a time, never all held
        blocks = retimed_blocks(doc, range(doc.n_poses), times_ms, ends_as_header=False)
        write_blocks(blocks, target, doc.n_poses, times_ms[-1])
    else:
        doc.set_times(times_ms)
        findings = check_result(doc, Velocity(spec, timestep))
        write_result(doc, target)
    if format is Format.json:
        say(_json(result, path, target, spec, margin, accel, findings), target)
    else:
        say(_text(result, path, target, how, spec, margin, accel, findings, timestep), target)
    if findings:
        raise typer.Exit(exit_codes.FINDINGS)


def _refuse_modes(
    speed: float | None, duration: int | None, fit: bool, accel: float | None
) -> None:
    """Raise :class:`MotionToolError` unless exactly one of --speed, --duration and
    --fit-limits is given, and --accel only with --fit-limits."""
    modes = [
        m
        for m, on in (
            ("--speed", speed is not None),
            ("--duration", duration is not None),
            ("--fit-limits", fit),
        )
        if on
    ]
    if len(modes) != 1:
        raise MotionToolError(
            "give exactly one of --speed, --duration or --fit-limits"
            + (f" (got {' and '.join(modes)})" if modes else "")
        )
    if accel is not None and not fit:
        raise MotionToolError("--accel applies to --fit-limits only")


def _text(
    r: Retimed,
    source: Path,
    target: Path | None,
    how: str,
    spec: RobotSpec | None,
    margin: float,
    accel: float | None,
    findings: list[Diagnostic],
    timestep: int | None,
) -> str:
    lines = [f"retimed {source_name(source)} -> {destination(target)}: {how}"]
    if spec is not None:
        limit = f"velocity within {num(margin * 100)}% of maxVelocity"
        if accel is not None:
            limit += f", acceleration within {num(accel)} rad/s²"
        lines.append(f"robot: {spec.name} (model {spec.model_hash[:12]}); {limit}")
        if r.unconstrained:
            lines.append(
                f"not motors of {spec.name}, not constrained: {', '.join(r.unconstrained)}"
            )
        segments = len(r.times_ms) - 1
        lines.append(
            f"stretched {len(r.stretches)} of {segments} segments" + (":" if r.stretches else "")
        )
        lines.extend(_stretch_lines(r))
    else:
        lines.append(
            f"pose times rounded to whole ms: at most {num(r.rounding_ms)} ms from exact scaling"
        )
    lines.append(_duration_line(r))
    if spec is not None:
        step = timestep or spec.default_timestep_ms
        lines += findings_lines(
            findings,
            f"velocity check ({step} ms controller step): {values_count(findings)} warnings remain "
            "that retiming cannot remove:",
            f"velocity check ({step} ms controller step): no warning",
        )
    return "\n".join(lines) + "\n"


def _json(
    r: Retimed,
    source: Path,
    target: Path | None,
    spec: RobotSpec | None,
    margin: float,
    accel: float | None,
    findings: list[Diagnostic],
) -> str:
    doc: dict[str, Any] = {
        **report_header(
            "motiontool.retime", source, target, None if spec is None else spec.model_hash
        ),
        "units": {
            "times_ms": "ms",
            "duration_ms": "ms",
            "added_percent": "%",
            "rounding_ms": "ms",
            "max_acceleration": "rad/s²",
        },
        "robot": None if spec is None else spec.name,
        "margin": margin if spec is not None else None,
        "max_acceleration": accel,
        "old_times_ms": list(r.old_times_ms),
        "times_ms": list(r.times_ms),
        "duration_ms": {"old": r.old_duration_ms, "new": r.duration_ms},
        "added_ms": r.added_ms,
        "added_percent": r.added_percent,
        "rounding_ms": r.rounding_ms,
        "stretches": [
            {
                "segment": s.segment,
                "old_ms": s.old_ms,
                "new_ms": s.new_ms,
                "joint": s.joint,
                "reason": s.reason,
            }
            for s in r.stretches
        ],
        "unconstrained": list(r.unconstrained),
        "remaining_velocity_findings": findings_json(findings),
    }
    return jsontext.dumps(doc)
