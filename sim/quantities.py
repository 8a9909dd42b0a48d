"""The quantities and flags an expectation can name (:data:`QUANTITIES`, :data:`FLAGS`), the
units a value may be written in (:data:`UNITS`) and how a measured value is shown.

Adding a quantity is one entry in :data:`QUANTITIES`, with its unit and the function that reads
it off a report (:mod:`motiontool.sim.report_values`); the grammar
(:mod:`motiontool.sim.expect_syntax`) and the judge (:mod:`motiontool.sim.expect`) follow it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from motiontool.sim.report_values import (
    Measure,
    base_value,
    count,
    ee_deviation,
    ee_error,
    ee_lag,
    ee_position,
    fall_direction,
    feet,
    heading,
    joint_value,
)

__all__ = [
    "FEET_PLANTED_MM",
    "FLAGS",
    "FLAGS_DECIDING_FALL",
    "QUANTITIES",
    "UNITS",
    "Quantity",
    "format_measured",
    "format_number",
]

FEET_PLANTED_MM = 5.0
"""``feet-planted``: no foot moves further than this (mm, horizontal) from where it started."""


@dataclass(frozen=True)
class Quantity:
    """A measurable of a run.

    Attributes:
        name: as written in an expectation.
        unit: its unit (``m``, ``deg``, ``s``, ``mm``, ``rad``; ``""`` for a count).
        help: what it is, one line.
        measure: report, expectation -> (value in ``unit`` and a note, or None and why not
            measured).
        per_joint: whether it takes a joint, ``QUANTITY[JOINT]`` (default: the worst joint).
        decides_fall: an expectation on it replaces the "fell" verdict of the run.
        per_keyframe: whether it takes a keyframe, ``QUANTITY[KEYFRAME]`` (an arm's tool).
        point: whether it is a position, compared with ``=[x, y, z]±TOL`` (the distance is
            measured), at a keyframe ``[KEYFRAME]`` or a time ``@T``.
        periodic: whether it is a direction in degrees, (-180, 180]: ``=`` compares the
            wrapped difference (``fall_direction=180±45`` holds for -170).
    """

    name: str
    unit: str
    help: str
    measure: Measure
    per_joint: bool = False
    decides_fall: bool = False
    per_keyframe: bool = False
    point: bool = False
    periodic: bool = False


UNITS: dict[str, tuple[str, float]] = {
    "m": ("length", 1.0),
    "cm": ("length", 0.01),
    "mm": ("length", 0.001),
    "deg": ("angle", math.pi / 180.0),
    "°": ("angle", math.pi / 180.0),
    "rad": ("angle", 1.0),
    "s": ("time", 1.0),
    "ms": ("time", 0.001),
}
"""The units a value may be written in: unit -> (kind, its value in SI units)."""

_DIGITS = {"m": 3, "mm": 1, "deg": 1, "rad": 3, "s": 2, "ms": 0, "": 0}


def format_measured(value: float, unit: str) -> str:
    """A measured value for people, to the digits its unit deserves: ``0.470 m``, ``23.7 deg``."""
    text = f"{value:.{_DIGITS.get(unit, 3)}f}"
    return f"{text} {unit}" if unit else text


def format_number(value: float, unit: str) -> str:
    """A bound as written (shortest form): ``0.3 m``, ``60 deg``, ``2``."""
    return f"{value:g} {unit}" if unit else f"{value:g}"


QUANTITIES: dict[str, Quantity] = {
    q.name: q
    for q in [
        Quantity("dx", "m", "root displacement along world x, start to end", base_value("dx_m")),
        Quantity("dy", "m", "root displacement along world y (left)", base_value("dy_m")),
        Quantity("dz", "m", "root height change, start to end", base_value("dz_m")),
        Quantity("dx_heading", "m", "displacement along the start heading", heading(0)),
        Quantity("dy_heading", "m", "displacement to the left of the start heading", heading(1)),
        Quantity(
            "yaw", "deg", "heading change while upright (+ = left)", base_value("yaw_change_deg")
        ),
        Quantity(
            "max_tilt", "deg", "largest tilt of the root from vertical", base_value("max_tilt_deg")
        ),
        Quantity("final_tilt", "deg", "tilt of the root at the end", base_value("final_tilt_deg")),
        Quantity(
            "torso_height",
            "m",
            "root height above the floor at the end",
            base_value("final_height_m"),
        ),
        Quantity("min_height", "m", "lowest root height over the run", base_value("min_height_m")),
        Quantity("fell_at", "s", "when the robot fell", base_value("fell_at_s"), decides_fall=True),
        Quantity(
            "fall_direction",
            "deg",
            "which way it fell, from its heading before the fall (0 forward, 90 left, "
            "-90 right, 180 back)",
            fall_direction,
            decides_fall=True,
            periodic=True,
        ),
        Quantity(
            "feet_slip",
            "mm",
            "largest horizontal slip of a foot while on the floor",
            feet("slip_m"),
        ),
        Quantity(
            "feet_moved",
            "mm",
            "furthest a foot got from where it started",
            feet("max_displacement_m"),
        ),
        Quantity(
            "tracking_error",
            "rad",
            "largest |target - position| (m for a linear joint)",
            joint_value("max_error"),
            per_joint=True,
        ),
        Quantity(
            "tracking_rms",
            "rad",
            "RMS of target - position (m for a linear joint)",
            joint_value("rms_error"),
            per_joint=True,
        ),
        Quantity(
            "velocity_cap",
            "s",
            "time a motor's command sat at maxVelocity",
            joint_value("velocity_cap_s"),
            per_joint=True,
        ),
        Quantity(
            "torque_cap",
            "s",
            "time a motor's torque sat at maxTorque",
            joint_value("torque_cap_s"),
            per_joint=True,
        ),
        Quantity(
            "self_collisions", "", "pairs of robot bodies that collided", count("self_collisions")
        ),
        Quantity(
            "ee_error",
            "mm",
            "an arm's tool: distance from the keyframe's forward kinematics at its time",
            ee_error,
            per_keyframe=True,
        ),
        Quantity(
            "ee_lag",
            "ms",
            "an arm's tool: time after the keyframe until within the reach tolerance",
            ee_lag,
            per_keyframe=True,
        ),
        Quantity(
            "ee_deviation",
            "mm",
            "an arm's tool: largest distance from the forward kinematics of the commands",
            ee_deviation,
        ),
        Quantity(
            "ee",
            "m",
            "an arm's tool position at [KEYFRAME] or @TIME: distance from a point [x,y,z]",
            ee_position,
            per_keyframe=True,
            point=True,
        ),
        Quantity(
            "scene_contacts",
            "",
            "pairs robot / scene (not the floor) that touched",
            count("scene_contacts"),
        ),
    ]
}
"""Every quantity an expectation can name: name -> :class:`Quantity` (units in ``unit``; the
per-joint ones take the worst commanded joint unless a joint is named in brackets)."""

FLAGS: dict[str, str] = {
    "upright": "no fall and up at the end (the fall detector: root height and tilt)",
    "fell": "the robot falls (the fall is then expected: not a failure)",
    "no-fall": "the robot does not fall",
    "no-self-collision": "no two robot bodies collide",
    "feet-planted": f"no foot moves more than {FEET_PLANTED_MM:g} mm from where it started",
}
"""Bare-word expectations and what they require."""

FLAGS_DECIDING_FALL = {"fell", "no-fall"}
"""The flags that decide about the fall itself (a fall where ``fell`` is expected is clean)."""
