"""``motiontool plot``: every joint over time, against the robot's limits, as a PNG."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from motiontool.cli.options import (
    ROBOT_OPTION,
    MotionFile,
    output_option,
    robot_option,
    timestep_option,
)
from motiontool.cli.output import emit_bytes, refuse_overwrite, say_wrote
from motiontool.cli.text import file_name, plural
from motiontool.extras import require
from motiontool.kinematics.robots import AUTO, RobotSpec, pick_robot
from motiontool.motionfmt.fileio import is_stdout, read_file, source_name
from motiontool.motionfmt.player import WEBOTS_DEFAULT_TIMESTEP_MS
from motiontool.motionfmt.reader import read_bytes
from motiontool.stamps import stamps

if TYPE_CHECKING:
    from motiontool.cli._plotting import JointLimits
    from motiontool.motionfmt.motion import Motion

__all__ = ["plot_command"]


_Output = Annotated[Path, output_option("The PNG file to write ('-': stdout).", show_default=False)]
_Robot = Annotated[
    str, robot_option("Robot whose limits are drawn", none="no limits (as auto finding none)")
]
_Timestep = Annotated[
    int | None,
    timestep_option(
        f"the robot's, else Webots' {WEBOTS_DEFAULT_TIMESTEP_MS}",
        use="held targets ('*' spans, dotted) are drawn at its steps",
    ),
]


def plot_command(
    path: MotionFile,
    output: _Output,
    robot: _Robot = AUTO,
    timestep: _Timestep = None,
) -> None:
    """Draw every joint over time into a PNG: grouped by limb (head, arms, legs, hands for the
    Nao; arm, wrist for the UR5e), the robot's limits as dashed lines with the out-of-range
    bands shaded, values outside them marked x and segments faster than maxVelocity drawn thick
    red; dotted where a joint gets no command ('*') and holds its previous target.
    Deterministic (same input, same bytes), no display needed.
    """
    from motiontool.cli._held_lines import held_lines
    from motiontool.cli._plotting import limb_groups, plot_motion

    refuse_overwrite(output, [path], "-o", "write the PNG to another file")
    require("matplotlib", "plot", "motiontool plot")
    motion = read_bytes(read_file(path), source_name(path)).motion
    spec = pick_robot(robot, motion.joints)
    step = timestep or (spec.default_timestep_ms if spec else WEBOTS_DEFAULT_TIMESTEP_MS)
    names = tuple(dict.fromkeys(motion.joints))
    groups = limb_groups(
        motion.joints, spec.name if spec else None, spec.joint_names if spec else ()
    )
    name = file_name(path)
    who = f"robot {spec.name} (model {spec.model_hash[:12]})" if spec else "no robot: no limits"
    png, n_limit, n_fast = plot_motion(
        motion,
        groups=groups,
        limits=_limits(motion, spec),
        held=held_lines(motion, step),
        title=f"{name}: {len(names)} joints, {motion.n_poses} poses, {motion.duration_ms} ms",
        caption=f"{who} | motiontool {stamps()['motiontool']}\n"
        "dashed: joint range, shaded beyond · x: outside the range · thick red: above "
        f"maxVelocity · dotted: target held over '*' ({step} ms step)",
        comment=json.dumps(stamps(spec.model_hash if spec else None), sort_keys=True),
    )
    emit_bytes(png, output)  # '-': the PNG to stdout, the summary line to stderr
    findings = _findings(spec, robot, n_limit, n_fast)
    summary = f"{plural(len(names), 'joint')} in {plural(len(groups), 'group')}; {who}; {findings}"
    if is_stdout(output):  # the PNG on stdout: what it shows on stderr
        typer.echo(f"PNG on stdout: {summary}", err=True)
    say_wrote(output, f"PNG: {summary}")


def _limits(motion: Motion, spec: RobotSpec | None) -> dict[str, JointLimits]:
    """The robot's limits of each joint of ``motion`` it has (none without a robot)."""
    from motiontool.cli._plotting import JointLimits

    if spec is None:
        return {}
    return {
        j.name: JointLimits(j.lower, j.upper, j.max_velocity, j.unit)
        for j in spec.joints
        if j.name in motion.joints
    }


def _findings(spec: RobotSpec | None, robot: str, n_limit: int, n_fast: int) -> str:
    """What the plot shows against the limits: ``n_limit`` keyframe values outside them and
    ``n_fast`` segments above maxVelocity, or that no limits are drawn (and how to name a robot
    where ``auto`` found none)."""
    if spec is not None:
        return (
            f"{plural(n_limit, 'keyframe value')} outside the limits, "
            f"{plural(n_fast, 'segment')} above maxVelocity"
        )
    findings = "no robot limits drawn"
    if robot == AUTO:
        findings += (
            f" (no built-in robot has half of the joints or more; name one with {ROBOT_OPTION})"
        )
    return findings
