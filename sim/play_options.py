"""How to play a run: :class:`PlayOptions` (units in the names; the defaults reproduce the Webots
Nao worlds), checked before anything runs."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from motiontool.errors import MotionToolError
from motiontool.kinematics.checks import DEFAULT_PENETRATION_TOLERANCE_MM
from motiontool.sim.motor import DEFAULT_P_GAIN
from motiontool.sim.physics import check_physics
from motiontool.sim.start import StartState

__all__ = ["PlayOptions"]


@dataclass(frozen=True)
class PlayOptions:
    """How to play (units in the names; defaults reproduce the Webots Nao worlds).

    Attributes:
        timestep_ms: control step (Webots' basicTimeStep), ms; None = the robot's world (Nao 20,
            UR5e 8).
        loops: cycles of each motion (Webots' loop mode).
        reverse: play each motion backwards.
        start: ``standing``, ``lying-front`` (face down) or ``lying-back`` (face up).
        physics_step_ms: MuJoCo's step, ms; it must divide the control step. None: the
            profile's (2 ms; ``webots``: the control step). See :mod:`motiontool.sim.physics`.
        p_gain: P gain of the motors' position controllers, 1/s (Webots' controlPID P).
        hold_s: time to keep simulating after the last motion, the last targets held, s.
        floor_friction: robot-floor Coulomb friction coefficient (pyramidal cone), > 0.
            None: the profile's (1; ``webots``: 7).
        friction_scale: factor on the floor friction (batch's ``friction`` perturbation).
        profile: ``default`` (μ = 1, 2 ms: what makes the Webots walks walk in MuJoCo) or
            ``webots`` (Webots' μ = 7 and physics step = control step, for comparison; its
            report says that this is not what makes walks match).
        mass_scale, torque_scale: factors on the robot's masses / motor torque limits.
        start_yaw_deg: start heading, degrees.
        start_noise_rad: standard deviation of random offsets added to the start joint
            positions, rad (drawn from ``seed``).
        seed: seed of every random draw (none without start noise).
        fall_height_m, fall_tilt_deg: the robot goes down when its root is lower than this
            (m) or tilted more than this (degrees), and is up again a margin past both
            (:class:`motiontool.sim.measure.DownFrames`); the Nao's torso defaults.
        collision_tolerance_mm: interpenetrations of two robot bodies shallower than this (mm)
            are not self-collisions: the bounding primitives of Webots' robots overlap that
            much in the motions that ship with Webots (the same threshold as ``validate``,
            :data:`motiontool.kinematics.checks.DEFAULT_PENETRATION_TOLERANCE_MM`).
        reach_tolerance_mm: an arm's tool has reached a keyframe once it is this close (mm)
            to the keyframe's commanded position (the report's ``end_effector`` lags).
        self_collision: self-collision physics: the robot's parts collide with each other
            (Webots' ``selfCollision``); None: the world's ``selfCollision`` with a world,
            else as the robot's model has it (the Nao: off, Webots' default; the UR5e: on).
        chain: the motions are the elements of a chain (``play --chain``): the text report
            lists each with its time in the run and what its base did.
        chain_loops: cycles of each motion, in order (``--loop NAME=N``); empty: ``loops``
            each.
        start_pose: the pose the run starts from, as given (``FILE:POSE``; None: the zero
            stance, or the first motion's first pose lying), and ``start_pose_joints`` its
            motor positions, rad (m), (name, value) pairs.
    """

    timestep_ms: int | None = None
    loops: int = 1
    reverse: bool = False
    start: StartState = StartState.STANDING
    physics_step_ms: float | None = None
    p_gain: float = DEFAULT_P_GAIN
    hold_s: float = 1.0
    floor_friction: float | None = None
    friction_scale: float = 1.0
    profile: Literal["default", "webots"] = "default"
    mass_scale: float = 1.0
    torque_scale: float = 1.0
    start_yaw_deg: float = 0.0
    start_noise_rad: float = 0.0
    seed: int = 0
    fall_height_m: float = 0.2
    fall_tilt_deg: float = 50.0
    collision_tolerance_mm: float = DEFAULT_PENETRATION_TOLERANCE_MM
    reach_tolerance_mm: float = 1.0
    self_collision: bool | None = None
    chain: bool = False
    chain_loops: tuple[int, ...] = ()
    start_pose: str | None = None
    start_pose_joints: tuple[tuple[str, float], ...] = ()

    def check(self) -> None:
        """Raise :class:`MotionToolError` for an out-of-range option."""
        if self.timestep_ms is not None and self.timestep_ms < 1:
            raise MotionToolError(f"the time step must be >= 1 ms, got {self.timestep_ms}")
        if self.loops < 1 or any(n < 1 for n in self.chain_loops):
            raise MotionToolError(f"loops must be >= 1, got {self.chain_loops or self.loops}")
        StartState.parse(self.start)
        for name in ("p_gain", "mass_scale", "torque_scale"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise MotionToolError(f"{name} must be a positive number, got {value}")
        if not (math.isfinite(self.collision_tolerance_mm) and self.collision_tolerance_mm >= 0):
            raise MotionToolError(
                f"collision tolerance must be >= 0 mm, got {self.collision_tolerance_mm}"
            )
        if not (math.isfinite(self.reach_tolerance_mm) and self.reach_tolerance_mm > 0):
            raise MotionToolError(f"reach tolerance must be > 0 mm, got {self.reach_tolerance_mm}")
        if not (math.isfinite(self.hold_s) and self.hold_s >= 0):
            raise MotionToolError(f"the hold time must be >= 0 s, got {self.hold_s}")
        check_physics(
            profile=self.profile,
            physics_step_ms=self.physics_step_ms,
            friction=self.floor_friction,
            friction_scale=self.friction_scale,
        )
