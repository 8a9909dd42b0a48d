"""``motiontool convert IN OUT``: a motion to another format and back (CSV, NPZ), or to a
real robot (formats in :data:`motiontool.motionfmt.convert.FORMATS`), checked against the robot
before anything is written."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from motiontool.cli.convert_checks import (
    motion_findings,
    refuse_unknown_joints,
    stream_findings,
)
from motiontool.cli.options import ROBOT_OPTION, robot_option, timestep_option
from motiontool.cli.output import emit_bytes, emit_stderr, refuse_overwrite, say_wrote
from motiontool.cli.text import num, plural
from motiontool.kinematics.builtin_robots import DEFAULT_TIMESTEP_MS
from motiontool.kinematics.robots import AUTO, RobotSpec, pick_robot, resolve_robot
from motiontool.motionfmt.convert import FORMATS, Format, format_named, format_of
from motiontool.motionfmt.convert.base import DEFAULT_LEAD_IN_MS, Exported, ExportOptions
from motiontool.motionfmt.errors import MotionToolError
from motiontool.motionfmt.fileio import is_stdin, is_stdout, read_file, source_name

__all__ = ["convert_command"]

_NAMES = ", ".join(f.name for f in FORMATS)


def _format(path: Path, given: str | None, option: str, can: str) -> Format:
    """The format named by ``option`` (``--to``), else by ``path``'s ending; it must ``can``
    (``read`` or ``write``)."""
    found = format_named(given) if given else None
    if given and found is None:
        raise MotionToolError(f"{option} {given!r}: unknown format; choose one of {_NAMES}")
    if found is None and not (is_stdin(path) or is_stdout(path)):
        found = format_of(str(path))
    if found is None:
        raise MotionToolError(
            f"cannot tell the format of '{path}' from its name; give {option} ({_NAMES})"
        )
    if getattr(found, can) is None:
        able = ", ".join(f.name for f in FORMATS if getattr(f, can) is not None)
        raise MotionToolError(f"motiontool convert cannot {can} {found.name}; it can {can} {able}")
    return found


def _companion(target: Path, suffix: str) -> Path:
    """A file written beside ``target``: its name up to the first dot, then ``suffix``."""
    return target.with_name(target.name.split(".", 1)[0] + suffix)


def _robot(requested: str | None, out: Format, joints: tuple[str, ...]) -> RobotSpec | None:
    if requested is None and out.default_robot is not None:
        return resolve_robot(out.default_robot)
    if out.for_robot:
        return resolve_robot(requested or AUTO, joints)
    return pick_robot(requested or AUTO, joints)


def _refuse(lines: list[str], heading: str) -> None:
    emit_stderr("".join(f"{line}\n" for line in [heading, *lines]))
    raise typer.Exit(1)


def _report(exported: Exported, spec: RobotSpec | None, notes: list[str]) -> str:
    """What follows the ``wrote`` lines: the robot check, and a robot format's deviation."""
    lines = []
    if spec is None:
        lines.append(f"not checked against a robot: none named or detected ({ROBOT_OPTION})")
    elif notes:
        lines += [f"checked against robot {spec.name}: {plural(len(notes), 'finding')}", *notes]
    else:
        lines.append(f"checked against robot {spec.name}: clean")
    d = exported.deviation
    if d is not None:
        where = "" if d.joint is None else f" ({d.joint} at {d.at_ms} ms)"
        where = " (bit-identical)" if d.max_rad == 0 else where
        lines.append(f"worst deviation from Webots' command stream: {num(d.max_rad)} rad{where}")
        lines.append(f"  compared: {d.compared}")
    return "".join(f"{line}\n" for line in lines)


def convert_command(
    source: Annotated[
        Path, typer.Argument(help="The motion to convert ('-': stdin).", show_default=False)
    ],
    target: Annotated[
        Path,
        typer.Argument(
            help="Where to write it ('-': stdout; never the input).", show_default=False
        ),
    ],
    to: Annotated[
        str | None,
        typer.Option("--to", help=f"Output format ({_NAMES}); default: from OUT's ending."),
    ] = None,
    from_: Annotated[
        str | None,
        typer.Option("--from", help=f"Input format ({_NAMES}); default: from IN's ending."),
    ] = None,
    robot: Annotated[
        str | None,
        robot_option(
            "Robot the export is checked against (default: the format's own: nao-v5 for naoqi, "
            "ur5e for urscript; else auto)",
            none="no checks (data formats only)",
        ),
    ] = None,
    timestep: Annotated[
        int | None, timestep_option(use="the command stream reproduced and checked")
    ] = None,
    lead_in: Annotated[
        int,
        typer.Option(
            "--lead-in",
            min=1,
            help="ms the real robot gets to reach the first pose before the motion starts "
            "(naoqi: every NAOqi time is the Webots time plus this).",
        ),
    ] = DEFAULT_LEAD_IN_MS,
    keyframes: Annotated[
        bool,
        typer.Option(
            "--keyframes",
            help="urscript: one movej per keyframe (time = the segment, blend 0) instead of "
            "servoj at every control step.",
        ),
    ] = False,
) -> None:
    """Convert a motion to CSV, NPZ, NAOqi or URScript, or a CSV or NPZ back to a motion.

    The output is checked against the robot first (validate's limit, velocity and joint
    checks, and what a robot format sends); nothing is written if it fails (exit 1). The
    command stream Webots plays is kept bit-identical through CSV and NPZ; a robot format says
    how far it is from it (rad).
    """
    fmt_in = _format(source, from_ or ("motion" if is_stdin(source) else None), "--from", "read")
    fmt_out = _format(target, to, "--to", "write")
    refuse_overwrite(target, [source], "OUT", "write to another file")
    imported = fmt_in.read(read_file(source), source_name(source))  # type: ignore[misc]
    motion = imported.motion
    spec = _robot(robot, fmt_out, motion.joints)
    step = timestep or (spec.default_timestep_ms if spec else DEFAULT_TIMESTEP_MS)
    notes: list[str] = []
    if spec is not None:
        if robot is not None or fmt_out.for_robot:
            refuse_unknown_joints(imported, spec)
        blocking, notes = motion_findings(imported, spec, step, for_robot=fmt_out.for_robot)
        if blocking:
            _refuse(blocking, f"not written: the motion fails the checks of robot {spec.name}:")
    options = ExportOptions(
        timestep_ms=step,
        source=source_name(source),
        robot=None if spec is None else spec.name,
        joint_order=None if spec is None else spec.joint_names,
        lead_in_ms=lead_in,
        keyframes=keyframes,
        target_name=None if is_stdout(target) else target.name,
    )
    exported = fmt_out.write(motion, options)  # type: ignore[misc]
    if spec is not None and exported.stream is not None:
        bad = stream_findings(exported.stream, spec, f"{fmt_out.name} export")
        if bad:
            _refuse(bad, f"not written: what the export sends fails robot {spec.name}'s limits:")
    companions = [_companion(target, suffix) for suffix, _ in exported.companions]
    if companions and is_stdout(target):
        raise MotionToolError(f"{fmt_out.name} writes a script beside its file: give OUT a name")
    for path in companions:
        refuse_overwrite(path, [source], "OUT's companion", "write to another file")
    emit_bytes(exported.data, None if is_stdout(target) else target)
    for path, (_, data) in zip(companions, exported.companions, strict=True):
        emit_bytes(data, path)
    say_wrote(target, f"{plural(exported.poses, 'pose')}, {exported.detail}")
    for path in companions:
        say_wrote(path, "the script that sends it")
    emit_stderr(_report(exported, spec, notes))
