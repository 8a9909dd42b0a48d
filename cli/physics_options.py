"""``--physics-step``, ``--friction``, ``--profile``, ``--world``, ``--robot-node`` and
``--[no-]self-collision``: the physics
options of ``play`` and ``batch`` (one spelling and help text each; :mod:`motiontool.sim.physics`
and :mod:`motiontool.sim.world_run` say what they do)."""

from __future__ import annotations

import enum
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from motiontool.cli.options import finite

if TYPE_CHECKING:
    from motiontool.cli.config import Settings

__all__ = [
    "FrictionOption",
    "PhysicsStepOption",
    "Profile",
    "ProfileOption",
    "RobotNodeOption",
    "SelfCollisionOption",
    "WorldOption",
    "chosen_world",
]


class Profile(enum.StrEnum):
    """Physics profiles (:data:`motiontool.sim.physics.PROFILES`)."""

    default = "default"
    webots = "webots"


PhysicsStepOption = Annotated[
    float | None,
    typer.Option(
        "--physics-step",
        callback=finite,
        help="MuJoCo step in ms; it must divide the controller time step (default: 2, or the"
        " control step with --profile webots).",
        show_default=False,
    ),
]
FrictionOption = Annotated[
    float | None,
    typer.Option(
        "--friction",
        callback=finite,
        help="Robot-floor friction coefficient, > 0 (default: 1, or 7 with --profile webots;"
        " batch's --perturb friction multiplies it).",
        show_default=False,
    ),
]
ProfileOption = Annotated[
    Profile,
    typer.Option(
        "--profile",
        help="default (friction 1, 2 ms) or webots (Webots' friction 7 and physics step = the"
        " control step; not what makes walks match: see docs/play.md, Fidelity). --friction and"
        " --physics-step override it.",
    ),
]
WorldOption = Annotated[
    Path | None,
    typer.Option(
        "--world",
        help="A Webots world (.wbt) to play in: its basicTimeStep (the control step),"
        " gravity, the feet-floor contactProperties, the robot's start position and heading"
        " and what it stands on; an option given on the command line wins over the world's"
        " field; the report says what was applied and what was not.",
        show_default=False,
    ),
]
RobotNodeOption = Annotated[
    str | None,
    typer.Option(
        "--robot-node",
        metavar="NAME|DEF",
        help="The robot node of --world that plays the motion, by its name or DEF (needed"
        " when the world has several robots of the motion's kind).",
        show_default=False,
    ),
]
SelfCollisionOption = Annotated[
    bool | None,
    typer.Option(
        "--self-collision/--no-self-collision",
        help="Self-collision physics: the robot's parts collide with each other, but solids"
        " joined by a joint (Webots' selfCollision rule). Default: --world's selfCollision,"
        " else as the robot's Webots PROTO has it (Nao: off; UR5e: on).",
        show_default=False,
    ),
]


def chosen_world(
    given: tuple[Path | None, str | None],
    sidecar: tuple[Path | None, str | None],
    settings: Settings,
) -> tuple[Path | None, str | None]:
    """The world a motion plays in, with its robot node: ``--world`` (``given``), else its
    ``motions.toml`` entry's (``sidecar``), else the configuration's ``world`` (``settings``;
    none with ``--isolated``); (None, None): no world."""
    for world, node in (given, sidecar, (settings.world, settings.robot_node)):
        if world is not None:
            return world, node
    return None, None
