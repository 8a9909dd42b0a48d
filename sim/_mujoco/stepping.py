"""Stepping a scene (:func:`run`): Webots' motor law every control step, the state measured into
a :class:`~motiontool.sim.trace.Trace` every frame (positions, poses, contacts,
self-collisions); the tool's forward kinematics (:func:`tool_poses`)."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.sim._mujoco.api import mj, warning_labels
from motiontool.sim._mujoco.scene import ROBOT_CLASSES, GeomClass, Scene
from motiontool.sim.motor import velocity_command
from motiontool.sim.trace import ContactEvent, Trace, concatenate

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.sim._mujoco.api import MjData, MuJoCo


def run(
    scene: Scene,
    targets: npt.NDArray[np.float64],
    commanded: npt.NDArray[np.bool_],
    *,
    record_bodies: bool = False,
) -> Trace:
    """Play ``targets`` (S, J), one row per control step, from the scene's start state, and
    return the trace of the whole run (:func:`run_chunks` with one chunk)."""
    return concatenate(list(run_chunks(scene, [(targets, commanded)], record_bodies=record_bodies)))


def run_chunks(
    scene: Scene,
    commands: Iterable[tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]],
    *,
    record_bodies: bool = False,
) -> Iterator[Trace]:
    """Play the command stream ``commands`` from the scene's start state, a chunk at a time: the
    trace of each chunk of steps as it is simulated (see :mod:`motiontool.sim.trace`), so that
    nothing of the run need be held.

    Args:
        scene: a freshly built scene (its data is stepped in place).
        commands: the stream in consecutive chunks: (K, J) target positions in force at each
            step (NaN-free), rad (m), before clipping to the motor limits, and (K, J) bool,
            whether the motion sent the target at that step.
        record_bodies: also keep every robot body's pose at every frame (for a recording).

    An error MuJoCo raises (:class:`mujoco.FatalError`) stops the run: the chunk it stopped in
    keeps what was simulated, says why, and is the last. Any other exception is a bug, and
    propagates.
    """
    mujoco = mj()
    import numpy as np

    model, data = scene.model, scene.data
    limits, driver_dof, substeps = scene.limits, scene.driver_dof, scene.control_substeps
    before: Trace | None = None
    for targets, commanded in commands:
        first = 0 if before is None else before.last_frame
        trace = _new_trace(scene, targets, commanded, record_bodies, first)
        observe = _observer(scene, trace, record_bodies)
        position, velocity_cmd, torque = trace.position, trace.velocity_cmd, trace.torque
        try:
            if before is None:
                observe(0)
            else:
                _carry(before, trace)
            for k in range(len(targets)):
                command = velocity_command(limits, targets[k], position[k])  # Webots' motor law
                velocity_cmd[k] = command
                data.qvel[driver_dof] = command
                mujoco.mj_step(model, data, substeps)
                torque[k] = data.qfrc_constraint[driver_dof]
                np.negative(torque[k], out=torque[k])
                observe(k + 1)
                trace.steps_done = k + 1
        except mujoco.FatalError as exc:  # MuJoCo's own error: the report says why it stopped
            trace.error = f"simulation stopped at step {first + trace.steps_done}: {exc}"
        trace.warnings = {name: int(data.warning[i].number) for i, name in warning_labels().items()}
        if trace.error is not None:
            yield trace.truncated()
            return
        yield trace
        before = trace


def _carry(before: Trace, trace: Trace) -> None:
    """Frame 0 of the chunk ``trace``: the last frame of the chunk ``before``."""
    for name in ("position", "velocity", "base_pos", "base_quat", "foot_pos", "foot_contact"):
        getattr(trace, name)[0] = getattr(before, name)[-1]
    if trace.body_pos.shape[0]:
        trace.body_pos[0] = before.body_pos[-1]
        trace.body_quat[0] = before.body_quat[-1]
    if trace.tool_pos is not None and before.tool_pos is not None:
        trace.tool_pos[0] = before.tool_pos[-1]
    if trace.tool_quat is not None and before.tool_quat is not None:
        trace.tool_quat[0] = before.tool_quat[-1]


def _new_trace(
    scene: Scene,
    targets: npt.NDArray[np.float64],
    commanded: npt.NDArray[np.bool_],
    record_bodies: bool,
    first_frame: int = 0,
) -> Trace:
    """An empty trace for ``targets`` (S, J): S + 1 frames from ``first_frame``, zero-filled."""
    import numpy as np

    steps, n_joints = targets.shape
    n_frames = steps + 1
    body_frames = n_frames if record_bodies else 0
    feet, bodies = scene.foot_geoms, scene.robot_bodies
    return Trace(
        joints=scene.joints,
        control_step_s=scene.control_step_s,
        physics_step_s=scene.physics_step_s,
        time_s=Trace.frame_times(first_frame, n_frames, scene.control_step_s),
        commanded=commanded,
        targets=targets,
        velocity_cmd=np.zeros((steps, n_joints)),
        torque=np.zeros((steps, n_joints)),
        position=np.zeros((n_frames, n_joints)),
        velocity=np.zeros((n_frames, n_joints)),
        base_pos=np.zeros((n_frames, 3)),
        base_quat=np.zeros((n_frames, 4)),
        feet=tuple(scene.geom_name(int(g)) for g in feet),
        foot_pos=np.zeros((n_frames, len(feet), 3)),
        foot_contact=np.zeros((n_frames, len(feet)), dtype=bool),
        bodies=tuple(scene.body_name(int(b)) for b in bodies),
        body_pos=np.zeros((body_frames, len(bodies), 3)),
        body_quat=np.zeros((body_frames, len(bodies), 4)),
        tool=scene.tool[0] if scene.tool else "",
        tool_pos=np.zeros((n_frames, 3)) if scene.tool else None,
        tool_quat=np.zeros((n_frames, 4)) if scene.tool else None,
        first_frame=first_frame,
    )


def _observer(scene: Scene, trace: Trace, record_bodies: bool) -> Callable[[int], None]:
    """A function that measures the state of ``scene.data`` into frame ``frame`` of ``trace``:
    positions, poses, contacts, self-collisions."""
    mujoco = mj()  # once, not every frame
    model, data, feet, bodies = scene.model, scene.data, scene.foot_geoms, scene.robot_bodies
    qpos_adr, root = scene.qpos_adr, scene.root_body
    dof_adr = _motor_dofs(scene)
    read_tool = _tool_reader(scene, data, trace.tool_pos, trace.tool_quat)
    geoms = _GeomLookup.of(scene)

    def observe(frame: int) -> None:
        trace.position[frame] = data.qpos[qpos_adr]
        trace.velocity[frame] = data.qvel[dof_adr]
        if read_tool is not None:
            read_tool(frame)
        trace.base_pos[frame] = data.xpos[root]
        trace.base_quat[frame] = data.xquat[root]
        if len(feet):
            trace.foot_pos[frame] = data.geom_xpos[feet]
        if record_bodies:  # the poses of the joints measured (mj_step leaves those before)
            mujoco.mj_kinematics(model, data)  # positions only: the next mj_step redoes them
            trace.body_pos[frame] = data.xpos[bodies]
            trace.body_quat[frame] = data.xquat[bodies]
        if data.ncon:
            _contacts(scene, geoms, data, frame, trace)
        if scene.probe is not None:
            _self_collisions(mujoco, scene, geoms, data, trace.first_frame + frame, trace)

    return observe


def _motor_dofs(scene: Scene) -> npt.NDArray[np.intp]:
    """(J,) the qvel address of each motor joint (a hinge or a slide: one dof each)."""
    import numpy as np

    model = scene.model
    joint_at = {int(a): j for j, a in enumerate(model.jnt_qposadr.tolist())}
    dofs = [int(model.jnt_dofadr[joint_at[int(a)]]) for a in scene.qpos_adr]
    return np.array(dofs, dtype=np.intp)


def _tool_reader(
    scene: Scene,
    data: MjData,
    pos: npt.NDArray[np.float64] | None,
    quat: npt.NDArray[np.float64] | None,
) -> Callable[[int], None] | None:
    """A function that copies the tool's pose of ``data`` into row ``frame`` of ``pos`` (m)
    and ``quat`` (w, x, y, z), or None without a tool."""
    if scene.tool is None or pos is None or quat is None:
        return None
    mujoco = mj()
    _name, kind, index = scene.tool
    if kind == "site":

        def read_site(frame: int) -> None:
            pos[frame] = data.site_xpos[index]
            mujoco.mju_mat2Quat(quat[frame], data.site_xmat[index])

        return read_site

    def read_body(frame: int) -> None:
        pos[frame] = data.xpos[index]
        quat[frame] = data.xquat[index]

    return read_body


def tool_poses(
    scene: Scene, q: npt.NDArray[np.float64]
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Forward kinematics of the tool: its world pose for each row of motor positions.

    MuJoCo's own ``mj_kinematics`` on a scratch ``MjData`` of the scene's model, so that the
    commanded and the measured poses come from one model in one world frame (the arm on its
    box), with no second model to keep in step.

    Args:
        scene: a scene with a tool (:attr:`Scene.tool`).
        q: (N, J) motor positions, rad (m), in ``scene.joints`` order.

    Returns:
        positions (N, 3), m, and orientations (N, 4), unit quaternions (w, x, y, z).
    """
    mujoco = mj()
    import numpy as np

    if scene.tool is None:
        raise MotionToolError(f"{scene.robot.name} has no end effector (a free-flying robot)")
    model = scene.model
    data = mujoco.MjData(model)
    rows = np.asarray(q, dtype=np.float64).reshape(-1, len(scene.joints))
    pos = np.zeros((len(rows), 3))
    quat = np.zeros((len(rows), 4))
    read = _tool_reader(scene, data, pos, quat)
    assert read is not None
    for i, row in enumerate(rows):
        data.qpos[scene.qpos_adr] = row
        mujoco.mj_kinematics(model, data)
        read(i)
    return pos, quat


@dataclass(frozen=True)
class _GeomLookup:
    """What the contact bookkeeping asks of each geom, as Python lists read once per chunk:
    indexing NumPy arrays per contact, and comparing their scalars with :class:`GeomClass`
    members (NumPy looks up its protocol attributes on the enum class each time), cost more
    than the physics step when the robot's parts touch."""

    cls: list[int]
    """:class:`GeomClass` of each geom, as an int."""
    body: list[int]
    """Body id of each geom."""
    foot: dict[int, int]
    """Index in :attr:`Scene.foot_geoms` of each foot geom."""

    @classmethod
    def of(cls, scene: Scene) -> _GeomLookup:
        return cls(
            cls=[int(c) for c in scene.geom_class.tolist()],
            body=[int(b) for b in scene.model.geom_bodyid.tolist()],
            foot={int(g): i for i, g in enumerate(scene.foot_geoms.tolist())},
        )


_ROBOT = frozenset(int(c) for c in ROBOT_CLASSES)
_FOOT, _FLOOR = int(GeomClass.FOOT), int(GeomClass.FLOOR)


def _contacts(scene: Scene, geoms: _GeomLookup, data: MjData, frame: int, trace: Trace) -> None:
    """Foot-floor contacts into ``foot_contact`` (``frame``: of the trace); every other robot
    contact into events."""
    cls = geoms.cls
    seen: dict[tuple[str, str, str], float] = {}
    for (g1, g2), d in zip(data.contact.geom.tolist(), data.contact.dist.tolist(), strict=True):
        if cls[g1] not in _ROBOT:
            g1, g2 = g2, g1
        if cls[g1] not in _ROBOT:
            continue  # scene-scene
        if cls[g1] == _FOOT and cls[g2] == _FLOOR:
            trace.foot_contact[frame, geoms.foot[g1]] = True
            continue
        key = _contact_event_key(scene, geoms, g1, g2)
        seen[key] = max(seen.get(key, 0.0), max(0.0, -d))
    at = trace.first_frame + frame
    for (kind, body, other), depth in seen.items():
        trace.events.append(ContactEvent(at, kind, body, other, depth))  # type: ignore[arg-type]


def _contact_event_key(
    scene: Scene, geoms: _GeomLookup, robot_geom: int, other_geom: int
) -> tuple[str, str, str]:
    """(kind, robot body, other) of a contact between a robot geom and another geom that is not
    a foot on the floor (see :class:`~motiontool.sim.trace.ContactEvent`)."""
    body = scene.body_name(geoms.body[robot_geom])
    other_class = geoms.cls[other_geom]
    if other_class in _ROBOT:  # the robot touches itself (self-collision physics, the UR5e)
        other = scene.body_name(geoms.body[other_geom])
        return "touch", min(body, other), max(body, other)
    if other_class == _FLOOR:
        return ("scene" if not scene.floating else "ground"), body, "floor"
    return "scene", body, scene.geom_name(other_geom)


def _self_collisions(
    mujoco: MuJoCo, scene: Scene, geoms: _GeomLookup, data: MjData, frame: int, trace: Trace
) -> None:
    assert scene.probe is not None
    probe, probe_data = scene.probe
    probe_data.qpos[:] = data.qpos
    mujoco.mj_kinematics(probe, probe_data)
    mujoco.mj_collision(probe, probe_data)
    if not probe_data.ncon:
        return
    seen: dict[tuple[str, str], float] = {}
    for (g1, g2), d in zip(
        probe_data.contact.geom.tolist(), probe_data.contact.dist.tolist(), strict=True
    ):
        a = scene.body_name(geoms.body[g1])  # the probe's geoms are the scene's
        b = scene.body_name(geoms.body[g2])
        key = (a, b) if a < b else (b, a)
        seen[key] = max(seen.get(key, 0.0), max(0.0, -d))
    for (a, b), depth in seen.items():
        trace.events.append(ContactEvent(frame, "self", a, b, depth))
