"""Whether a run's robot collides with itself, and why: the option's choice, the Webots world's
``selfCollision``, else the robot's model (the decision before the run, the report's
``self_collision`` after it)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from motiontool.sim._mujoco import Scene
    from motiontool.sim.measure import RunMeter
    from motiontool.sim.play_options import PlayOptions
    from motiontool.sim.world_run import WorldRun

__all__ = ["self_collision", "self_collision_doc"]


def self_collision(opts: PlayOptions, placed: WorldRun | None) -> bool | None:
    """Self-collision physics: the option's, else the world's ``selfCollision``, else None
    (as the robot's model has it)."""
    if opts.self_collision is not None:
        return opts.self_collision
    return None if placed is None else placed.world.robot.self_collision


def self_collision_doc(
    scene: Scene, opts: PlayOptions, placed: WorldRun | None, meter: RunMeter
) -> dict[str, Any]:
    """The report's ``self_collision``: whether the robot's parts collided with each other in
    the simulation, why, and how many pairs of bodies touched."""
    if opts.self_collision is not None:
        source = "option"
        why = "asked for" if opts.self_collision else "turned off, whatever the world says"
    elif placed is not None:
        robot = placed.world.robot
        value = "TRUE" if robot.self_collision else "FALSE"
        source = "world"
        why = f"{robot.type} {robot.name!r}.selfCollision {value}, line {robot.line}"
    else:
        source = "robot model"
        why = f"{scene.robot.name}'s model: as the robot's Webots PROTO has selfCollision"
    touched = meter.self_contacts()
    return {
        "physics": scene.self_collision,
        "source": source,
        "why": why,
        "touching_pairs": len(touched),
        "touching_s": round(sum(c.duration_s for c in touched), 9),
    }
