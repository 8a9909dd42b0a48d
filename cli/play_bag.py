"""``play --bag FILE``: the simulated run as a ROS 2 bag (:mod:`motiontool.sim.bag`), checked
before the run and said after it, beside what :mod:`motiontool.cli.play` renders."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from motiontool.cli.output import refuse_overwrite, refuse_shared_outputs, say_wrote
from motiontool.errors import MotionToolError
from motiontool.extras import require
from motiontool.motionfmt.fileio import is_stdout

if TYPE_CHECKING:
    from motiontool.sim.session import PlayResult

__all__ = ["BagOption", "check_bag", "say_bag"]

BagOption = Annotated[
    Path | None,
    typer.Option(
        "--bag",
        help="Write the run as a ROS 2 bag (MCAP): measured joint positions as "
        "sensor_msgs/JointState on /joint_states, a floating base's pose as "
        "geometry_msgs/PoseStamped on /base_pose.",
    ),
]

_WHAT = "motiontool play --bag"


def check_bag(bag: Path | None, files: list[Path], outputs: dict[str, Path | None]) -> None:
    """Before the run: ``--bag`` is a file (not stdout, where the report goes), not an input,
    not another output's file, and the ROS 2 libraries are installed.

    Raises:
        MotionToolError: one line (MissingExtraError: the ``pip install`` that brings them).
    """
    if bag is None:
        return
    if is_stdout(bag):
        raise MotionToolError("--bag writes a binary file beside the report: give it a path")
    refuse_overwrite(bag, files, "--bag")
    refuse_shared_outputs({**outputs, "--bag": bag})
    require("rosbags", "ros", _WHAT)
    require("mcap_ros2.writer", "ros", _WHAT)


def say_bag(result: PlayResult, bag: Path | None) -> None:
    """After the run: what the bag holds (nothing is written when the run could not start)."""
    report = result.report
    if report is None:
        return
    base = ", the base pose on /base_pose" if report.base is not None else ""
    say_wrote(
        bag,
        f"ROS 2 bag, MCAP: measured joint positions on /joint_states{base}, "
        f"{report.simulated_s:.2f} s simulated",
    )
