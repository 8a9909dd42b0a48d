"""``motiontool convert IN OUT``: a motion to another format and back (CSV, NPZ, a ROS 2 bag),
or to a real robot (formats in :data:`motiontool.motionfmt.convert.FORMATS`), checked against
the robot before anything is written."""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Annotated

import typer

from motiontool import exit_codes
from motiontool.cli.convert_blend import (
    beyond_blend_error,
    blend_acceleration,
    blend_lines,
    refuse_blend_options,
    unfit_corner,
)
from motiontool.cli.convert_checks import (
    ArmLimits,
    beyond_max_error,
    file_findings,
    motion_findings,
    real_arm_findings,
    refuse_short_lead_in,
    refuse_split_joints,
    refuse_unknown_joints,
    robot_limits,
    stream_findings,
)
from motiontool.cli.options import (
    MAX_MS,
    ROBOT_OPTION,
    finite,
    output_path,
    robot_option,
    timestep_option,
)
from motiontool.cli.output import (
    emit_files,
    emit_stderr,
    refuse_overwrite,
    refuse_shared_outputs,
    say_wrote,
)
from motiontool.cli.text import num, plural
from motiontool.errors import MotionToolError
from motiontool.kinematics.builtin_robots import DEFAULT_TIMESTEP_MS
from motiontool.kinematics.robots import AUTO, NONE, RobotSpec, pick_robot, resolve_robot
from motiontool.motionfmt.convert import FORMATS, Format, format_named, format_of
from motiontool.motionfmt.convert.base import (
    DEFAULT_JOINT_STATE_TOPIC,
    DEFAULT_LEAD_IN_MS,
    DEFAULT_MAX_ERROR_RAD,
    UNCHECKED,
    Exported,
    ExportOptions,
    Imported,
    ImportOptions,
    Recording,
    Sampled,
)
from motiontool.motionfmt.convert.blend import CornersDoNotFit
from motiontool.motionfmt.convert.joint_map import parse_joint_map
from motiontool.motionfmt.fileio import (
    is_stdin,
    is_stdout,
    output_kind,
    read_file,
    source_name,
)
from motiontool.motionfmt.units import MS_PER_S

__all__ = ["convert_command"]

_NAMES = {
    can: ", ".join(f.name for f in FORMATS if getattr(f, can) is not None)
    for can in ("read", "write")
}
"""The formats convert can read (``--from``) and write (``--to``)."""


def _format(path: Path, given: str | None, option: str, can: str) -> Format:
    """The format named by ``option`` (``--to``), else by ``path``'s ending; it must ``can``
    (``read`` or ``write``)."""
    found = format_named(given) if given else None
    if given and found is None:
        raise MotionToolError(f"{option} {given!r}: unknown format; choose one of {_NAMES[can]}")
    if found is None and not (is_stdin(path) or is_stdout(path)):
        found = format_of(str(path))
    if found is None and can == "read" and path.is_dir():  # a ROS 2 bag's folder
        found = next(f for f in FORMATS if f.read_folder is not None)
    if found is None:
        raise MotionToolError(
            f"cannot tell the format of '{path}' from its name; give {option} ({_NAMES[can]})"
        )
    if getattr(found, can) is None:
        raise MotionToolError(
            f"motiontool convert cannot {can} {found.name}; it can {can} {_NAMES[can]}"
        )
    return found


def _companion(target: Path, suffix: str) -> Path:
    """A file written beside ``target``: its name up to the first dot, then ``suffix``."""
    return target.with_name(target.name.split(".", 1)[0] + suffix)


def _beside(target: Path) -> bool:
    """Whether a companion goes beside ``target`` unasked: only a regular file (or a new
    path) has a folder of its own; standard output and a device (``/dev/null``) have none."""
    return not is_stdout(target) and output_kind(target) == "file"


def _target_name(target: Path, send_script: Path | None) -> str | None:
    """OUT as its companion opens it: its path from the companion's folder, or None where
    OUT is no regular file."""
    if not _beside(target):
        return None
    if send_script is None:
        return target.name
    return os.path.relpath(os.path.abspath(target), os.path.abspath(send_script.parent))


def _robot(requested: str | None, out: Format, joints: tuple[str, ...]) -> RobotSpec | None:
    """The robot the export is checked against; None: no checks (``--robot none``, for every
    format, or no robot detected for a data format)."""
    if requested == NONE:
        if "joint_order" in out.uses:
            example = f"{ROBOT_OPTION} {out.default_robot}, or a model file"
            raise MotionToolError(
                f"{ROBOT_OPTION} {NONE}: {out.name} sends the robot's joints in the robot's "
                f"order; name the robot ({example})"
            )
        return None
    if requested is None and out.default_robot is not None:
        return resolve_robot(out.default_robot)
    if out.for_robot:
        return resolve_robot(requested or AUTO, joints)
    return pick_robot(requested or AUTO, joints)


def _refuse(lines: list[str], heading: str) -> None:
    emit_stderr("".join(f"{line}\n" for line in [heading, *lines]))
    raise typer.Exit(exit_codes.FINDINGS)


def _recording(r: Recording, poses: int) -> list[str]:
    """What an imported recording held, and the motion's worst deviation from it."""
    d = r.deviation
    rate = f", {(r.messages - 1) * MS_PER_S / r.duration_ms:.4g} Hz" if r.duration_ms else ""
    read = r.heading or (
        f"read {plural(r.messages, 'sensor_msgs/JointState message')} of {r.topic} "
        f"({r.duration_ms / MS_PER_S:g} s{rate})"
    )
    lines = [
        read,
        f"keyframes: {poses}, reduced within {num(r.reduced_rad)} rad (as resample "
        "--max-error reduces them)"
        + (
            ""
            if r.reduced_rad == r.max_error_rad
            else f" to keep within {num(r.max_error_rad)} rad"
        ),
        f"worst deviation from {r.against}: {num(d.max_rad)} rad ({d.joint} at {d.at_ms} ms)",
        f"  compared: {d.compared}",
    ]
    lines[1:1] = r.notes
    if r.merged:
        lines.insert(1, f"{plural(r.merged, 'sample')} left out: on a whole ms an earlier one has")
    return lines


def _sampled(s: Sampled, poses: int) -> list[str]:
    """What an imported animation of curves held, and the motion's worst deviation from it."""
    d = s.deviation
    return [
        f"read {plural(s.keys, 'key')} of {plural(s.curves, 'joint curve')} ({s.what}); its "
        f"first key, at {s.start_s:g} s, is the motion's 0 ms",
        *(f"  {note}" for note in s.notes),
        f"sampled every {s.step_ms} ms ({plural(s.samples, 'time')}); keyframes: {poses}, "
        f"reduced within {num(s.max_error_rad)} rad (as resample --max-error reduces them)",
        f"worst deviation from the curves: {num(d.max_rad)} rad ({d.joint} at {d.at_ms} ms)",
        f"  compared: {d.compared}",
    ]


def _reading(
    fmt_in: Format,
    topic: str | None,
    pairs: tuple[tuple[str, str], ...],
    max_error: float | None,
    timestep: int | None,
    robot: str | None,
) -> ImportOptions:
    """What the reader is given. An animation of curves is sampled at ``--timestep``, else the
    named robot's control step, else that of the robot the format is for (ms)."""
    step = timestep or DEFAULT_TIMESTEP_MS
    if timestep is None and "timestep_ms" in fmt_in.uses:
        name = robot if robot not in (None, AUTO, NONE) else fmt_in.default_robot
        step = resolve_robot(name).default_timestep_ms if name else DEFAULT_TIMESTEP_MS
    error = DEFAULT_MAX_ERROR_RAD if max_error is None else max_error
    return ImportOptions(topic or DEFAULT_JOINT_STATE_TOPIC, pairs, error, step)


def _report(
    exported: Exported,
    spec: RobotSpec | None,
    notes: list[str],
    imported: Imported,
    robot: str | None,
) -> str:
    """What follows the ``wrote`` lines: what a recording held, the robot check, and a robot
    format's deviation."""
    lines = []
    if imported.recording is not None:
        lines += _recording(imported.recording, imported.motion.n_poses)
    if imported.sampled is not None:
        lines += _sampled(imported.sampled, imported.motion.n_poses)
    if spec is None and robot == NONE:
        lines += [f"not checked against a robot: {ROBOT_OPTION} {NONE} ({UNCHECKED})", *notes]
    elif spec is None:
        lines += [f"not checked against a robot: none named or detected ({ROBOT_OPTION})", *notes]
    elif notes:
        lines += [f"checked against robot {spec.name}: {plural(len(notes), 'finding')}", *notes]
    else:
        lines.append(f"checked against robot {spec.name}: clean")
    lines += blend_lines(exported.blends, imported)
    d = exported.deviation
    if d is not None:
        where = "" if d.joint is None else f" ({d.joint} at {d.at_ms} ms)"
        where = " (bit-identical)" if d.max_rad == 0 else where
        lines.append(f"worst deviation from Webots' command stream: {num(d.max_rad)} rad{where}")
        lines.append(f"  compared: {d.compared}")
    return "".join(f"{line}\n" for line in lines)


_Source = Annotated[
    Path, typer.Argument(help="The motion to convert ('-': stdin).", show_default=False)
]
_Target = Annotated[
    Path,
    typer.Argument(
        parser=output_path,
        help="Where to write it ('-': stdout; never the input).",
        show_default=False,
    ),
]
_To = Annotated[
    str | None,
    typer.Option("--to", help=f"Output format ({_NAMES['write']}); default: from OUT's ending."),
]
_From = Annotated[
    str | None,
    typer.Option("--from", help=f"Input format ({_NAMES['read']}); default: from IN's ending."),
]
_Robot = Annotated[
    str | None,
    robot_option(
        "Robot the export is checked against (default: the format's own: nao-v5 for naoqi "
        "and choregraphe-py, ur5e for urscript; else auto); reading Choregraphe, its control "
        "step is the sampling step",
        none="no checks, for any format: what is written says 'unchecked'",
    ),
]
_Timestep = Annotated[int | None, timestep_option(use="the command stream reproduced and checked")]
_LeadIn = Annotated[
    int,
    typer.Option(
        "--lead-in",
        min=1,
        max=MAX_MS,
        help="ms the real robot gets to reach the first pose before the motion starts "
        "(naoqi, ros-trajectory, rosbag's trajectory: every time is the Webots time plus "
        "this); refused where the robot's maxVelocity cannot get there from 0 in it.",
    ),
]
_Keyframes = Annotated[
    bool,
    typer.Option(
        "--keyframes",
        help="urscript: one movej per keyframe (time = the segment, blend 0) instead of "
        "servoj at every control step.",
    ),
]
_NoBlend = Annotated[
    bool,
    typer.Option(
        "--no-blend",
        help="urscript: send the corners of Webots' straight lines as they are, step by step "
        "(refused at the real arm's 40 rad/s² where a velocity changes), for a motion retimed "
        "to its own corners; by default servoj rounds them at the real arm's acceleration.",
    ),
]
_Limits = Annotated[
    ArmLimits | None,
    typer.Option(
        "--limits",
        help="urscript: check against the real arm (real: 180 °/s on every joint, 40 rad/s² "
        "joint acceleration, movej's rest-to-rest trapezoids, servoj t of 2 ms or more; the "
        "default for ur5e) or the Webots model's limits (webots: 360 °/s on the wrists).",
    ),
]
_Topic = Annotated[
    str | None,
    typer.Option(
        "--topic",
        help="rosbag: the sensor_msgs/JointState topic read or written "
        f"(default: {DEFAULT_JOINT_STATE_TOPIC}).",
    ),
]
_JointMap = Annotated[
    Path | None,
    typer.Option(
        "--joint-map",
        help="rosbag, ros-trajectory: a TOML or YAML table, motion joint = ROS name, for the "
        "joints whose ROS names differ (the UR5e and the Nao need none); joints given one ROS "
        "name must agree, as a Nao's phalanges do as LHand.",
    ),
]
_MaxError = Annotated[
    float | None,
    typer.Option(
        "--max-error",
        min=0.0,
        callback=finite,
        help="rosbag, ros-trajectory, choregraphe, choregraphe-py to motion: keep keyframes "
        "within this many rad of the recording, of the trajectory's points or of the curves "
        "sampled at the control step, as resample "
        f"--max-error (default: {DEFAULT_MAX_ERROR_RAD:g}). urscript: refuse (exit 1) where "
        "servoj's blended corners pass farther than this from a keyframe (default: no bound; "
        "the deviation is always said).",
    ),
]

_SendScript = Annotated[
    Path | None,
    typer.Option(
        "--send-script",
        parser=output_path,
        metavar="PATH",
        help="naoqi: write the script that sends the JSON here (default: beside OUT, "
        "'wave_send.py' for 'wave.naoqi.json'; none where OUT is stdout or a device).",
    ),
]

#: The options of some formats only, and the field of ImportOptions / ExportOptions each sets.
_FIELDS = {
    "--topic": "topic",
    "--joint-map": "joint_map",
    "--max-error": "max_error_rad",
    "--send-script": "script_name",
    "--limits": "limits",
    "--no-blend": "blend_rad_s2",
}


def _refuse_unused(given: Mapping[str, object], fmt_in: Format, fmt_out: Format) -> None:
    """An option neither format reads is an error, not silently ignored."""
    for option, value in given.items():
        field = _FIELDS[option]
        if value is not None and field not in fmt_in.uses | fmt_out.uses:
            able = ", ".join(f.name for f in FORMATS if field in f.uses)
            raise MotionToolError(
                f"{option} applies to {able}, not to {fmt_in.name} -> {fmt_out.name}"
            )


def _checked(
    imported: Imported,
    spec: RobotSpec | None,
    fmt_out: Format,
    robot: str | None,
    ask: ExportOptions,
) -> list[str]:
    """Every check before the export: what validate finds in the file, one position per ROS
    name, the robot checks of the motion (stop, exit 1, on a blocking finding) and the
    lead-in; the findings that do not stop it."""
    notes = file_findings(imported)
    if "joint_map" in fmt_out.uses:  # a ROS export: one position per ROS name
        refuse_split_joints(imported, ask.joint_map)
    if spec is None:
        return notes
    if robot is not None or fmt_out.for_robot:
        refuse_unknown_joints(imported, spec)
    blocking, more = motion_findings(imported, spec, ask.timestep_ms, for_robot=fmt_out.for_robot)
    if blocking:
        _refuse(blocking, f"not written: the motion fails the checks of robot {spec.name}:")
    if "lead_in_ms" in fmt_out.uses:
        refuse_short_lead_in(imported.motion, spec, ask.lead_in_ms, "--lead-in")
    return notes + more


def _check_stream(
    exported: Exported, imported: Imported, spec: RobotSpec, what: str, real: ExportOptions | None
) -> None:
    """What the export sends to the robot: its motors only (exit 2), within their limits and
    maxVelocity, and for a real arm its acceleration and control cycle (exit 1)."""
    if exported.stream is None:
        return
    refuse_unknown_joints(imported, spec)
    bad = stream_findings(exported.stream, spec, what)
    if real is not None:  # checked against the real arm (--limits real)
        bad += real_arm_findings(exported.stream, real.keyframes, real.timestep_ms, what)
    if bad:
        _refuse(bad, f"not written: what the export sends fails robot {spec.name}'s limits:")


def _export(fmt_out: Format, imported: Imported, options: ExportOptions) -> Exported:
    """The export; where the servoj stream's corners cannot be blended, one line at the
    keyframe and exit 1, nothing written."""
    try:
        return fmt_out.write(imported.motion, options)  # type: ignore[misc]
    except CornersDoNotFit as e:
        emit_stderr(unfit_corner(e, imported) + "\n")
        raise typer.Exit(exit_codes.FINDINGS) from None


def _write(exported: Exported, source: Path, target: Path, send_script: Path | None) -> None:
    """Write OUT and its companion, both or neither (none over the input): the companion
    where ``--send-script`` names it, else beside OUT where OUT is a regular file, else none
    (said in one line); say what was written."""
    companions: list[tuple[Path | None, bytes]] = []
    unwritten: list[str] = []  # said once OUT is written: a failed write is its one line
    for suffix, data in exported.companions:
        if send_script is not None:
            companions.append((send_script, data))
        elif _beside(target):
            companions.append((_companion(target, suffix), data))
        else:
            what = (
                "OUT is standard output"
                if is_stdout(target)
                else f"'{target}' is not a regular file"
            )
            unwritten.append(
                f"motiontool: no script written: {what} (give --send-script PATH for one)\n"
            )
    for path, _ in companions:
        refuse_overwrite(path, [source], "OUT's companion", "write to another file")
        refuse_shared_outputs({"OUT": target, "its companion": path})
    emit_files([(None if is_stdout(target) else target, exported.data), *companions])
    emit_stderr("".join(unwritten))
    say_wrote(target, f"{plural(exported.poses, 'pose')}, {exported.detail}")
    for path, _ in companions:
        say_wrote(path, "the script that sends it")


def convert_command(
    source: _Source,
    target: _Target,
    to: _To = None,
    from_: _From = None,
    robot: _Robot = None,
    timestep: _Timestep = None,
    lead_in: _LeadIn = DEFAULT_LEAD_IN_MS,
    keyframes: _Keyframes = False,
    topic: _Topic = None,
    joint_map: _JointMap = None,
    max_error: _MaxError = None,
    send_script: _SendScript = None,
    limits: _Limits = None,
    no_blend: _NoBlend = False,
) -> None:
    """Convert a motion to CSV, NPZ, NAOqi, URScript, a ROS 2 trajectory or bag, or a CSV, NPZ,
    a ROS trajectory (YAML), a bag's recorded joint states, a Choregraphe timeline (.xar) or
    Python export back to a motion (and a motion to that Python: choregraphe-py).

    The output is checked against the robot first (validate's limit, velocity and joint
    checks, and what a robot format sends); nothing is written if it fails (exit 1). The
    command stream Webots plays is kept bit-identical through CSV and NPZ; a robot format says
    how far it is from it (rad), a recording or Choregraphe's curves how far the motion made of
    them is from them (rad).
    """
    fmt_in = _format(source, from_ or ("motion" if is_stdin(source) else None), "--from", "read")
    fmt_out = _format(target, to, "--to", "write")
    given = {
        "--topic": topic,
        "--joint-map": joint_map,
        "--max-error": max_error,
        "--send-script": send_script,
        "--limits": limits,
        "--no-blend": True if no_blend else None,
    }
    _refuse_unused(given, fmt_in, fmt_out)
    if "blend_rad_s2" in fmt_out.uses:
        refuse_blend_options(no_blend, keyframes, max_error)
    refuse_overwrite(target, [source], "OUT", "write to another file")
    pairs = () if joint_map is None else parse_joint_map(read_file(joint_map), str(joint_map))
    reading = _reading(fmt_in, topic, pairs, max_error, timestep, robot)
    if fmt_in.read_folder is not None and source.is_dir():
        imported = fmt_in.read_folder(str(source), reading)
    else:
        imported = fmt_in.read(read_file(source), source_name(source), reading)  # type: ignore[misc]
    if beyond := beyond_max_error(imported.recording, "--max-error"):
        _refuse(beyond, "not written: on whole ms the motion cannot keep within it:")
    model = _robot(robot, fmt_out, imported.motion.joints)
    spec = robot_limits(limits, model, "--limits") if "limits" in fmt_out.uses else model
    step = timestep or (spec.default_timestep_ms if spec else DEFAULT_TIMESTEP_MS)
    # The robot a format drives (nao-v5 for NAOqi) says which joints one motor drives there.
    real = resolve_robot(fmt_out.default_robot) if fmt_out.default_robot else spec
    options = ExportOptions(
        timestep_ms=step,
        source=source_name(source),
        robot=None if spec is None else spec.name,
        joint_order=None if spec is None else spec.joint_names,
        coupled_joints=() if real is None else real.coupled_joints,
        lead_in_ms=lead_in,
        keyframes=keyframes,
        target_name=_target_name(target, send_script),
        script_name=None if send_script is None else send_script.name,
        joint_map=pairs,
        topic=reading.topic,
        blend_rad_s2=blend_acceleration(spec is not model, no_blend, keyframes),
    )
    notes = _checked(imported, spec, fmt_out, robot, options)
    exported = _export(fmt_out, imported, options)
    if spec is not None:
        arm = options if spec is not model else None  # checked against the real arm
        _check_stream(exported, imported, spec, f"{fmt_out.name} export", arm)
    if too_far := beyond_blend_error(exported.blends, max_error, imported):
        _refuse([], too_far)
    _write(exported, source, target, send_script)
    emit_stderr(_report(exported, spec, notes, imported, robot))
