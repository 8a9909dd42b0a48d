"""Options shared by several commands: one spelling, one short form and one help text each.

``-r`` is always ``--robot``, ``-t`` ``--timestep``, ``-o`` ``--output`` and ``-f`` ``--format``
(``tests/cli/test_files.py`` keeps it so). The robot choices come from
:func:`motiontool.kinematics.builtin_robots.robot_choices`, the one list every help text and message
uses. :func:`error_line` is where the CLI adds its flags to a library error: the library says
"name the robot explicitly", the CLI says how (``--robot``).
"""

from __future__ import annotations

import enum
import math
from pathlib import Path
from typing import Annotated, Any

import typer

from motiontool.errors import MotionToolError
from motiontool.kinematics.builtin_robots import AUTO, NONE, robot_choices
from motiontool.kinematics.checks.wording import Wording
from motiontool.motionfmt.cscan import INT_MAX

__all__ = [
    "CLI_WORDING",
    "MAX_COUNT",
    "MAX_MS",
    "MAX_ROWS",
    "ROBOT_OPTION",
    "Format",
    "FormatOption",
    "InPlace",
    "MotionFile",
    "NoCacheOption",
    "Output",
    "ReportOutput",
    "ResultTimestep",
    "RobotOption",
    "TableFormat",
    "TextOrJson",
    "TextOrJsonOption",
    "Timestep",
    "error_line",
    "finite",
    "output_option",
    "output_path",
    "robot_option",
    "timestep_option",
]

MAX_MS = INT_MAX
"""The most whole ms an option takes (a time step, a grid step, a duration, a transition, a
lead-in): Webots keeps a motion's times and its controller step in a C ``int``."""


MAX_COUNT = 1_000_000
"""The most cycles ``--loop`` plays (``play``, ``sample``), samples ``--samples`` draws and
workers ``--jobs`` starts (``batch``)."""

MAX_ROWS = MAX_COUNT * (MAX_MS + 1)
"""The most rows a stream of targets has (``sample --max-rows``): every cycle of the most
``--loop`` cycles sent at every ms a C ``int`` holds."""

# Every int option has a range (tests/cli/test_files.py keeps it so): a number outside it is
# refused as a usage error naming the option and the range, where an unbounded one overflowed a
# C long (resample --step 99999999999999999999) or listed runs until memory ran out (batch
# --samples).


def finite(value: Any) -> Any:
    """Typer callback of a float option: ``nan`` and ``inf`` (which Click reads as floats and
    its ranges let through) are refused as the option's value."""
    values = value if isinstance(value, list | tuple) else [value]
    for v in values:
        if isinstance(v, float) and not math.isfinite(v):
            raise typer.BadParameter(f"{v!r} is not a finite number")
    return value


ROBOT_OPTION = "--robot"
"""How a user of the CLI names a robot."""

CLI_WORDING = Wording(
    robot_option=ROBOT_OPTION,
    ignore_option="--ignore",
    mirror_command="motiontool mirror {source} -o {target}",
)
"""The CLI's words for the remedies the robot checks' hints name (the library's hints say
"name the robot explicitly" without them)."""


NoCacheOption = Annotated[
    bool,
    typer.Option(
        "--no-cache",
        envvar="MOTIONTOOL_NO_CACHE",
        help="Check every file again: neither read nor store the robot findings of small files "
        "(kept in ~/.cache/motiontool/lint by the file's bytes, robot, checks and code).",
    ),
]
"""``validate`` and ``server``: without the findings cache
(:mod:`motiontool.kinematics.checks.findings_cache`)."""


class Format(enum.StrEnum):
    """Formats of a transform's report."""

    text = "text"
    json = "json"


class TextOrJson(enum.StrEnum):
    """Formats of a listing offered as text or JSON only."""

    text = "text"
    json = "json"


class TableFormat(enum.StrEnum):
    """Formats of a table of numbers."""

    text = "text"
    csv = "csv"
    json = "json"


def output_path(value: str | Path) -> Path:
    """Typer ``parser`` of every option and argument naming a file to write: any path but the
    empty one, which pathlib reads as ``.`` (the folder) and which names no file (``-o ''`` is
    a usage error, exit 2)."""
    if isinstance(value, Path):
        return value
    if value == "":
        raise typer.BadParameter("an empty path names no file; give a file name, or '-' for stdout")
    return Path(value)


MotionFile = Annotated[Path, typer.Argument(help="A motion file ('-': stdin).", show_default=False)]
"""The one motion file a command reads."""
FormatOption = Annotated[
    Format, typer.Option("--format", "-f", help="Report as text for people or json for CI.")
]
TextOrJsonOption = Annotated[
    TextOrJson, typer.Option("--format", "-f", help="Text for people or json for CI.")
]


def output_option(help: str, **more: Any) -> Any:
    """``--output`` / ``-o``: a file to write (parsed by :func:`output_path`), ``help`` saying
    what goes there; ``more``: other keywords of :func:`typer.Option`."""
    return typer.Option("--output", "-o", parser=output_path, metavar="PATH", help=help, **more)


Output = Annotated[
    Path | None,
    output_option("Write the result here ('-': stdout). Never the input file, unless --in-place."),
]
ReportOutput = Annotated[
    Path | None,
    output_option("Write the report to this file instead of stdout (never over an input file)."),
]
InPlace = Annotated[bool, typer.Option("--in-place", help="Replace the input file (atomically).")]

_AUTO_HELP = (
    "auto: the built-in robot that has the most of the file's joints, at least half "
    "('motiontool robots' lists them)"
)


def robot_option(role: str, *, none: str | None = None, more: str = "") -> Any:
    """``--robot`` / ``-r``: ``role`` (``Robot to check against``), then the choices.

    Args:
        role: what the command uses the robot for.
        none: what ``none`` means to the command (it is offered only then).
        more: a last sentence of the command's own (``Repeat to ...``).
    """
    keywords = (AUTO, NONE) if none is not None else (AUTO,)
    text = f"{role}: {robot_choices(*keywords)}. {_AUTO_HELP}"
    if none is not None:
        text += f"; none: {none}"
    return typer.Option(ROBOT_OPTION, "-r", help=f"{text}.{' ' + more if more else ''}")


def timestep_option(
    default: str = "the robot's Webots world: Nao 20, UR5e 8", use: str = ""
) -> Any:
    """``--timestep`` / ``-t``, whole ms >= 1: ``Controller time step in ms`` and what the
    command does at that step (``use``), then its ``default``."""
    return typer.Option(
        "--timestep",
        "-t",
        min=1,
        max=MAX_MS,
        help=f"Controller time step in ms{': ' + use if use else ''} (default: {default}).",
    )


RobotOption = Annotated[
    str, robot_option("Robot whose limits apply", none="no robot: no limits, nothing checked")
]
"""``--robot`` of a command that works without a robot too (``none``, or ``auto`` finding none)."""
Timestep = Annotated[int | None, timestep_option()]
"""``--timestep`` of a command whose default is the robot's."""
ResultTimestep = Annotated[
    int | None, timestep_option(use="the velocity check run on the result's command stream")
]
"""``--timestep`` of a command that writes a motion and checks its velocities."""


def error_line(exc: MotionToolError) -> str:
    """How the CLI prints ``exc`` after ``motiontool: error:``: the library's message, with
    the option that fixes it where the library only says what to do."""
    from motiontool.kinematics.export import NoMjcfError  # the model exporter: only on an error
    from motiontool.kinematics.robots import NoRobotDetectedError

    if isinstance(exc, NoRobotDetectedError):
        return f"{exc.reason}; name one with {ROBOT_OPTION} ({robot_choices()})"

    if isinstance(exc, NoMjcfError):
        return str(NoMjcfError(exc.spec, how="with --urdf"))
    return str(exc)
