"""``motiontool generate``: write a motion of the project's library from its generator."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from motiontool.cli.options import output_option
from motiontool.cli.output import emit, say_wrote, written_motion
from motiontool.kinematics.robots import RobotSpec, load_robot
from motiontool.kinematics.ur5e_tasks import ROBOT, Task, generate, peak_speeds
from motiontool.motionfmt.motion import Motion
from motiontool.motionfmt.units import MS_PER_S
from motiontool.motionfmt.writer import format_motion
from motiontool.stamps import stamps

__all__ = ["generate_command"]


def _report(task: Task, motion: Motion, spec: RobotSpec, target: str) -> str:
    speeds = peak_speeds(motion)
    limits = [spec.joint(name).max_velocity for name in motion.joints]
    ratios = [s / v for s, v in zip(speeds, limits, strict=True)]
    worst = max(range(motion.n_joints), key=ratios.__getitem__)
    lines = [
        f"{task.value} -> {target}: {motion.n_poses} poses, {motion.duration_ms / MS_PER_S:.3f} s",
        f"max joint speed {speeds[worst]:.3f} rad/s ({motion.joints[worst]}; limit "
        f"{limits[worst]:g} rad/s, {100 * ratios[worst]:.0f} %)",
    ]
    lines += [
        f"  {name:<20} {s:.3f} rad/s of {v:g} rad/s"
        for name, s, v in zip(motion.joints, speeds, limits, strict=True)
    ]
    stamp = stamps(spec.model_hash)
    lines.append(
        "stamps: "
        + ", ".join(f"{k} {v}" for k, v in stamp.items() if v is not None and k != "model_sha256")
        + f", model {spec.name} sha256 {stamp['model_sha256']}"
    )
    return "\n".join(lines) + "\n"


def generate_command(
    task: Annotated[
        Task,
        typer.Argument(help="The motion to generate.", show_default=False),
    ],
    output: Annotated[
        Path | None,
        output_option(
            "Write the motion file here (atomically); without it the motion goes to "
            "stdout and the report to stderr."
        ),
    ] = None,
) -> None:
    """Generate a motion of the project's library (joint values from inverse kinematics or the
    jog rule, never typed in) and print a short report: poses, duration in s, peak joint
    speed in rad/s against the motor's limit."""
    motion = generate(task)
    text = format_motion(motion)
    spec = load_robot(ROBOT)
    to_file = output is not None and str(output) != "-"
    emit(text, output)
    say_wrote(output, written_motion(motion.n_poses, motion.duration_ms))
    typer.echo(
        _report(task, motion, spec, str(output) if to_file else "stdout"), nl=False, err=not to_file
    )
