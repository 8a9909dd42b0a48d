"""Webots' position control of a motor, as a pure function of the target and the position.

Webots (``docs/reference/motor.md``, ``rotationalmotor.md``): at every basic time step the target
set by ``wb_motor_set_position`` is clipped to ``[minPosition, maxPosition]``, a P controller turns
the position error into a velocity ``Vc = P * (target - position)`` (``controlPID`` defaults to
``(10, 0, 0)``), ``|Vc|`` is capped at ``maxVelocity``, and ODE's joint motor realises ``Vc`` with a
force bounded by ``maxTorque``. This module computes ``Vc``; :mod:`motiontool.sim._mujoco`
realises it as a bounded-force velocity constraint.

Depends on numpy only.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["DEFAULT_P_GAIN", "MotorLimits", "velocity_command"]

DEFAULT_P_GAIN = 10.0
"""Webots' default ``controlPID`` P gain, 1/s (velocity command per unit of position error)."""


@dataclass(frozen=True, eq=False)
class MotorLimits:
    """The limits of J motors, as float64 arrays of shape (J,).

    Attributes:
        lower: minPosition, rad (m for linear motors); ``-inf`` when unbounded.
        upper: maxPosition, same unit; ``+inf`` when unbounded.
        max_velocity: maxVelocity, rad/s (m/s).
        max_torque: maxTorque, N·m (maxForce, N, for linear motors).
        p_gain: the P gain of the position controller, 1/s.
    """

    lower: npt.NDArray[np.float64]
    upper: npt.NDArray[np.float64]
    max_velocity: npt.NDArray[np.float64]
    max_torque: npt.NDArray[np.float64]
    p_gain: float = DEFAULT_P_GAIN


def velocity_command(
    limits: MotorLimits,
    target: npt.NDArray[np.float64],
    position: npt.NDArray[np.float64],
) -> npt.NDArray[np.float64]:
    """Velocity command (J,) in rad/s (m/s): ``clip(P * (clip(target) - position), ±maxVelocity)``.

    Args:
        limits: the motors.
        target: commanded positions (J,), rad (m); clipped to the motor limits first.
        position: measured positions (J,), rad (m).
    """
    import numpy as np

    clipped = np.clip(target, limits.lower, limits.upper)
    return np.clip(limits.p_gain * (clipped - position), -limits.max_velocity, limits.max_velocity)
