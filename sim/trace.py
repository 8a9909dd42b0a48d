"""What a simulated run leaves behind: per-step arrays and sparse contact events (numpy only).

:mod:`motiontool.sim._mujoco` fills a :class:`Trace`; :mod:`motiontool.sim.play` turns it into a
report and :mod:`motiontool.sim.recording` into a Rerun recording, neither touching MuJoCo.

Frames: frame 0 is the state before the first control step; frame ``k >= 1`` the state after
control step ``k - 1``, at ``time_s[k] = k * control_step_ms / 1000``. Step ``k`` sends
``targets[k]`` at ``time_s[k]`` (from the state of frame ``k``) and runs the physics to frame
``k + 1``.

A run is simulated a chunk of control steps at a time, so that memory stays flat whatever its
duration (:func:`motiontool.sim._mujoco.run_chunks`): each chunk is a :class:`Trace` of its own
steps, whose frame 0 repeats the last frame of the chunk before (``first_frame`` says which
frame of the run it is). Its ``events`` are those of its frames but that first one (the chunk
before has them), and :func:`concatenate` joins chunks into the trace of the whole run.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

from motiontool.motionfmt.units import MS_PER_S

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["BodyShapes", "ContactEvent", "Shape", "Trace", "concatenate"]


@dataclass(frozen=True)
class Shape:
    """One collision primitive, in its body's frame.

    Attributes:
        kind: ``box``, ``capsule``, ``cylinder``, ``sphere``, ``ellipsoid`` or ``plane``.
        size: MuJoCo's geom size, m: box half-sizes (x, y, z); capsule / cylinder (radius,
            half-length along local z, 0); sphere (radius, 0, 0); ellipsoid semi-axes; plane
            (half-x, half-y, grid spacing), 0 meaning infinite.
        pos: position in the body frame, m.
        quat: orientation in the body frame, unit quaternion (w, x, y, z).
        name: the geom's name ('' if unnamed).
    """

    kind: str
    size: tuple[float, float, float]
    pos: tuple[float, float, float]
    quat: tuple[float, float, float, float]
    name: str = ""


@dataclass(frozen=True)
class BodyShapes:
    """A body of the scene and its collision primitives.

    Attributes:
        name: the body's name.
        limb: for robot bodies, the limb it belongs to (``LArm``, ``RLeg``, ...), '' otherwise.
        robot: whether the body belongs to the robot (posed every frame) or to the scene (static).
        shapes: its primitives.
    """

    name: str
    limb: str
    robot: bool
    shapes: tuple[Shape, ...]


@dataclass(frozen=True)
class ContactEvent:
    """A contact or interpenetration seen at one frame.

    Attributes:
        frame: frame index in the run (see the module docstring).
        kind: ``self`` (two robot bodies interpenetrate, seen by the self-collision probe; the
            Webots Nao has selfCollision FALSE, so they pass through each other, but the motion
            asks for it), ``touch`` (two robot bodies in contact in the simulation itself, for
            robots whose model has self-collision on, like Webots' UR5e), ``scene`` (the robot
            touches something else than the floor) or ``ground`` (a robot body other than a
            foot touches the floor).
        body_a: robot body name.
        body_b: other robot body (``self``, ``touch``), scene geom name (``scene``) or
            ``floor``.
        depth_m: penetration depth, m (>= 0).
    """

    frame: int
    kind: Literal["self", "touch", "scene", "ground"]
    body_a: str
    body_b: str
    depth_m: float


@dataclass(eq=False)
class Trace:
    """Per-frame arrays of a run, or of a chunk of it (float64 unless noted; S control steps,
    S + 1 frames).

    Attributes:
        joints: the J motors, in model order.
        control_step_s: control period T, s.
        physics_step_s: MuJoCo step, s.
        time_s: (S + 1,) frame times, s (frame ``k`` at ``k * control_step_ms / 1000``: whole
            ms, rounded once).
        commanded: (S, J) bool, whether the motion file commanded the joint at that step (as
            opposed to keeping the previous target).
        targets: (S, J) target in force at each step before clipping, rad (m).
        velocity_cmd: (S, J) velocity command of the P controller, rad/s (m/s).
        torque: (S, J) motor torque at the end of each step, N·m (N).
        position: (S + 1, J) measured joint positions, rad (m).
        velocity: (S + 1, J) measured joint velocities, rad/s (m/s).
        base_pos: (S + 1, 3) root body position, m.
        base_quat: (S + 1, 4) root body orientation (w, x, y, z).
        feet: names of the foot geometries (may be empty).
        foot_pos: (S + 1, F, 3) foot geometry centres, m.
        foot_contact: (S + 1, F) bool, whether each foot touches the floor.
        bodies: names of the B robot bodies posed in ``body_pos`` / ``body_quat``.
        body_pos: (S + 1, B, 3) robot body positions, m (only when recording, else (0, B, 3)).
        body_quat: (S + 1, B, 4) robot body orientations (w, x, y, z) (same).
        tool: the end-effector frame of a fixed-base arm (a site, or the last body of the
            chain; :func:`motiontool.sim._mujoco.build_scene`), '' when there is none.
        tool_pos: (S + 1, 3) its position in the world, m (None without a tool).
        tool_quat: (S + 1, 4) its orientation, unit quaternion (w, x, y, z) (same).
        events: contacts seen, frame by frame (frames of the run).
        warnings: MuJoCo warning name -> count over the run (so far, for a chunk).
        steps_done: control steps actually simulated (< S if the run stopped on an error).
        error: why the run stopped early, or None.
        first_frame: the frame of the run that is this trace's frame 0 (0: the whole run, or
            its first chunk).
    """

    joints: tuple[str, ...]
    control_step_s: float
    physics_step_s: float
    time_s: npt.NDArray[np.float64]
    commanded: npt.NDArray[np.bool_]
    targets: npt.NDArray[np.float64]
    velocity_cmd: npt.NDArray[np.float64]
    torque: npt.NDArray[np.float64]
    position: npt.NDArray[np.float64]
    velocity: npt.NDArray[np.float64]
    base_pos: npt.NDArray[np.float64]
    base_quat: npt.NDArray[np.float64]
    feet: tuple[str, ...]
    foot_pos: npt.NDArray[np.float64]
    foot_contact: npt.NDArray[np.bool_]
    bodies: tuple[str, ...]
    body_pos: npt.NDArray[np.float64]
    body_quat: npt.NDArray[np.float64]
    tool: str = ""
    tool_pos: npt.NDArray[np.float64] | None = None
    tool_quat: npt.NDArray[np.float64] | None = None
    events: list[ContactEvent] = field(default_factory=list)
    warnings: dict[str, int] = field(default_factory=dict)
    steps_done: int = 0
    error: str | None = None
    first_frame: int = 0

    @property
    def control_step_ms(self) -> int:
        """The control period in whole ms (Webots' basicTimeStep is an int): what a report's
        times and durations are counted in, ``steps * control_step_ms / 1000`` s rounded once
        (201 steps of 20 ms are 4.02 s, where 201 * 0.02 is 4.0200000000000005)."""
        return round(self.control_step_s * MS_PER_S)

    @staticmethod
    def frame_times(
        first_frame: int, n_frames: int, control_step_s: float
    ) -> npt.NDArray[np.float64]:
        """``time_s`` of ``n_frames`` frames from ``first_frame``: each frame's whole ms
        (``control_step_s`` is whole ms), then s, rounded once."""
        import numpy as np

        step_ms = round(control_step_s * MS_PER_S)
        frames = np.arange(first_frame, first_frame + n_frames, dtype=np.int64)
        times: npt.NDArray[np.float64] = frames * step_ms / MS_PER_S
        return times

    @property
    def last_frame(self) -> int:
        """The frame of the run that is this trace's last frame."""
        return self.first_frame + len(self.time_s) - 1

    def truncated(self) -> Trace:
        """The trace cut to the steps actually simulated (a copy of the arrays' views)."""
        s = self.steps_done
        body_frames = min(self.body_pos.shape[0], s + 1)
        return Trace(
            joints=self.joints,
            control_step_s=self.control_step_s,
            physics_step_s=self.physics_step_s,
            time_s=self.time_s[: s + 1],
            commanded=self.commanded[:s],
            targets=self.targets[:s],
            velocity_cmd=self.velocity_cmd[:s],
            torque=self.torque[:s],
            position=self.position[: s + 1],
            velocity=self.velocity[: s + 1],
            base_pos=self.base_pos[: s + 1],
            base_quat=self.base_quat[: s + 1],
            feet=self.feet,
            foot_pos=self.foot_pos[: s + 1],
            foot_contact=self.foot_contact[: s + 1],
            bodies=self.bodies,
            body_pos=self.body_pos[:body_frames],
            body_quat=self.body_quat[:body_frames],
            tool=self.tool,
            tool_pos=None if self.tool_pos is None else self.tool_pos[: s + 1],
            tool_quat=None if self.tool_quat is None else self.tool_quat[: s + 1],
            events=[e for e in self.events if e.frame <= self.first_frame + s],
            warnings=dict(self.warnings),
            steps_done=s,
            error=self.error,
            first_frame=self.first_frame,
        )


def concatenate(chunks: Sequence[Trace]) -> Trace:
    """The trace of a run from its consecutive chunks (the one chunk itself when there is one)."""
    import numpy as np

    if len(chunks) == 1:
        return chunks[0]
    first, last = chunks[0], chunks[-1]

    def steps(name: str) -> Any:
        return np.concatenate([getattr(c, name) for c in chunks])

    def frames(name: str) -> Any:
        parts = [getattr(first, name)] + [getattr(c, name)[1:] for c in chunks[1:]]
        return np.concatenate(parts)

    recorded = first.body_pos.shape[0] > 0
    return Trace(
        joints=first.joints,
        control_step_s=first.control_step_s,
        physics_step_s=first.physics_step_s,
        time_s=frames("time_s"),
        commanded=steps("commanded"),
        targets=steps("targets"),
        velocity_cmd=steps("velocity_cmd"),
        torque=steps("torque"),
        position=frames("position"),
        velocity=frames("velocity"),
        base_pos=frames("base_pos"),
        base_quat=frames("base_quat"),
        feet=first.feet,
        foot_pos=frames("foot_pos"),
        foot_contact=frames("foot_contact"),
        bodies=first.bodies,
        body_pos=frames("body_pos") if recorded else first.body_pos,
        body_quat=frames("body_quat") if recorded else first.body_quat,
        tool=first.tool,
        tool_pos=None if first.tool_pos is None else frames("tool_pos"),
        tool_quat=None if first.tool_quat is None else frames("tool_quat"),
        events=[e for c in chunks for e in c.events],
        warnings=dict(last.warnings),
        steps_done=sum(c.steps_done for c in chunks),
        error=last.error,
        first_frame=first.first_frame,
    )
