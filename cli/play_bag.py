"""``play --bag FILE``: the simulated run as a ROS 2 bag (:mod:`motiontool.sim.bag`), checked
before the run and said after it, beside what :mod:`motiontool.cli.play` renders."""

from __future__ import annotations

import re
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from motiontool.cli.output import refuse_overwrite, refuse_shared_outputs, say_wrote
from motiontool.errors import MotionToolError
from motiontool.extras import require
from motiontool.motionfmt.fileio import is_stdout

if TYPE_CHECKING:
    from motiontool.sim.bag import BagTarget
    from motiontool.sim.session import PlayResult

__all__ = ["BagOption", "BagStartOption", "bag_target", "check_bag", "parse_bag_start", "say_bag"]

BagOption = Annotated[
    Path | None,
    typer.Option(
        "--bag",
        help="Write the run as a ROS 2 bag (MCAP) for Foxglove, RViz or ros2 bag play: "
        "/joint_states (measured position, velocity, effort), /tf and /tf_static (every "
        "link, the floating base), /robot_description (the URDF, latched), /clock, and a "
        "floating base's pose on /base_pose.",
    ),
]


_NS_PER_S = 1_000_000_000
_NS_PER_US = 1_000


def parse_bag_start(value: str) -> int:
    """Typer ``parser`` of ``--bag-start``: ns since the Unix epoch, from a whole number of ns
    or an ISO-8601 time (UTC unless it gives its offset)."""
    text = value.strip()
    if re.fullmatch(r"[0-9]+", text):
        return int(text)
    try:
        when = datetime.fromisoformat(text)
    except ValueError:
        raise typer.BadParameter(
            f"{value!r} is not a time: give ISO-8601 (2024-05-01T12:00:00Z) or ns since "
            "the Unix epoch (1714564800000000000)"
        ) from None
    if when.tzinfo is None:
        when = when.replace(tzinfo=UTC)
    since = when - datetime(1970, 1, 1, tzinfo=UTC)
    ns = (since.days * 86_400 + since.seconds) * _NS_PER_S + since.microseconds * _NS_PER_US
    if ns < 0:
        raise typer.BadParameter(f"{value!r} is before the Unix epoch (1970-01-01T00:00:00Z)")
    return ns


BagStartOption = Annotated[
    int | None,
    typer.Option(
        "--bag-start",
        parser=parse_bag_start,
        metavar="TIME",
        help="Stamp the bag's first frame with this time (ISO-8601, UTC unless it gives its "
        "offset, or ns since the Unix epoch) instead of 0 s.",
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


def bag_target(bag: Path | None, start_ns: int | None) -> BagTarget | None:
    """The bag the run writes (None: no ``--bag``).

    Raises:
        MotionToolError: ``--bag-start`` without ``--bag``.
    """
    if bag is None:
        if start_ns is not None:
            raise MotionToolError("--bag-start stamps the bag: give --bag FILE too")
        return None
    from motiontool.sim.bag import BagTarget

    return BagTarget(bag, start_ns or 0)


def say_bag(result: PlayResult, bag: Path | None) -> None:
    """After the run: what the bag holds (nothing is written when the run could not start)."""
    report = result.report
    if report is None:
        return
    base = ", the base pose on /base_pose" if report.base is not None else ""
    say_wrote(
        bag,
        f"ROS 2 bag, MCAP: measured joint states on /joint_states, the links on /tf and "
        f"/tf_static, the URDF on /robot_description, /clock{base}, "
        f"{report.simulated_s:.2f} s simulated",
    )
