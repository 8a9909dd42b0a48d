"""Play motion files headlessly in MuJoCo as a Webots controller would, and measure the run.

A run: the motions' command streams (:func:`motiontool.motionfmt.sample`, the exact targets a
Webots controller sends) are played one after another, each starting at the control step after
the previous one is over (``wbu_motion_is_over``), then the last targets are held for
``hold_s``. Every control step the Webots motor law (:mod:`motiontool.sim.motor`) turns targets
into velocity commands that MuJoCo realises with bounded-force velocity constraints
(:mod:`motiontool.sim._mujoco`). The trace is then measured into a :class:`PlayReport` and, on
request, recorded to a Rerun ``.rrd`` (:mod:`motiontool.sim.recording`).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from motiontool.kinematics.checks import DEFAULT_PENETRATION_TOLERANCE_MM
from motiontool.kinematics.robots import RobotSpec, resolve_robot
from motiontool.motionfmt import Motion, read_bytes, read_file, sample
from motiontool.motionfmt.errors import MotionSyntaxError, MotionToolError
from motiontool.motionfmt.fileio import source_name
from motiontool.motionfmt.player import Held, hold_targets
from motiontool.motionfmt.units import MM_PER_M, MS_PER_S
from motiontool.sim.arm import measure_end_effector
from motiontool.sim.motor import DEFAULT_P_GAIN
from motiontool.sim.physics import check_physics, read_back, resolve_physics
from motiontool.sim.report import (
    BaseStats,
    ContactSummary,
    FileRun,
    FootStats,
    JointStats,
    PlayReport,
)
from motiontool.sim.start import StartState

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.sim._mujoco import Scene
    from motiontool.sim.motor import MotorLimits
    from motiontool.sim.physics import Physics
    from motiontool.sim.trace import ContactEvent, Trace

__all__ = [
    "LIMIT_TOLERANCE",
    "TORQUE_CAP_FRACTION",
    "Marker",
    "PlayOptions",
    "command_matrix",
    "play",
    "read_playable",
]

log = logging.getLogger("motiontool")

TORQUE_CAP_FRACTION = 0.999
"""A motor counts as torque-limited when its torque reaches this fraction of maxTorque."""

LIMIT_TOLERANCE = 0.01
"""How far past a motor limit (rad, or m) a position must be to count as beyond the limits."""


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
        fall_height_m, fall_tilt_deg: the robot is down while its root is lower than this (m)
            or tilted more than this (degrees); the Nao's torso defaults.
        collision_tolerance_mm: interpenetrations of two robot bodies shallower than this (mm)
            are not self-collisions: the bounding primitives of Webots' robots overlap that
            much in the motions that ship with Webots (the same threshold as ``validate``,
            :data:`motiontool.kinematics.checks.DEFAULT_PENETRATION_TOLERANCE_MM`).
        reach_tolerance_mm: an arm's tool has reached a keyframe once it is this close (mm)
            to the keyframe's commanded position (the report's ``end_effector`` lags).
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

    def check(self) -> None:
        """Raise :class:`MotionToolError` for an out-of-range option."""
        if self.timestep_ms is not None and self.timestep_ms < 1:
            raise MotionToolError(f"the time step must be >= 1 ms, got {self.timestep_ms}")
        if self.loops < 1:
            raise MotionToolError(f"loops must be >= 1, got {self.loops}")
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


@dataclass(frozen=True)
class Marker:
    """Something that happened during the run, for the recording's event log.

    Attributes:
        time_s: when, simulated s. level: ``INFO``, ``WARN`` or ``ERROR``. text: what.
        entity: which part of the recording it concerns (``fall``, ``collision``, ``limit``,
            ``motion``, ``simulator``).
    """

    time_s: float
    level: str
    text: str
    entity: str


def read_playable(path: str | Path) -> Motion:
    """The motion Webots plays from ``path`` (``-``: standard input), refused at its first
    ``nan`` / ``inf`` cell: Webots would send that to the motor (MT113), and the physics must not
    be fed it.

    Raises:
        MotionToolError: the file cannot be read; :class:`MotionSyntaxError` Webots rejects it,
            or a cell is not a finite number.
    """
    import numpy as np

    result = read_bytes(read_file(path), source_name(path))
    motion = result.motion
    bad = np.argwhere(motion.commanded & ~np.isfinite(motion.values))
    if bad.shape[0]:
        p, j = (int(x) for x in bad[0])
        line, column, _ = result.cell_span(p, j)
        value = float(motion.values[p, j])
        raise MotionSyntaxError(
            f"{motion.joints[j]} = {value!r} is not a finite number; Webots would send it to the"
            " motor, so it is not played (write a number, or '*' for no command)"
            " [MT113]",
            result.path,
            line,
            column,
        )
    return motion


def command_matrix(
    motions: Sequence[Motion],
    joints: Sequence[str],
    timestep_ms: int,
    initial: npt.NDArray[np.float64],
    *,
    reverse: bool = False,
    loops: int = 1,
    hold_steps: int = 0,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_], list[int], list[str]]:
    """The targets in force at each control step of the sequence ``motions``.

    Args:
        motions: played one after another; each starts at the step after the previous ends.
        joints: the robot's J motors.
        timestep_ms: control step, ms.
        initial: (J,) positions the motors hold before their first command, rad (m).
        reverse, loops: Webots' reverse and loop modes, applied to each motion.
        hold_steps: steps appended after the last motion, with no command.

    Returns:
        targets (S, J) float64 (a step without a command keeps the previous target; before the
        first, ``initial``), commanded (S, J) bool (the motion sent a target at that step), the
        number of steps of each motion, and the motion columns that are not motors (ignored,
        as Webots does, with a warning).
    """
    import numpy as np

    streams = [sample(m, timestep_ms, reverse=reverse, loops=loops) for m in motions]
    motors = set(joints)
    ignored = list(dict.fromkeys(n for s in streams for n in s.joints if n not in motors))
    idle = np.zeros((hold_steps, len(joints)), dtype=np.bool_)  # the hold steps send nothing
    chunks = [(s.targets, s.commanded, s.joints) for s in streams]
    chunks.append((np.full(idle.shape, np.nan), idle, tuple(joints)))
    held: list[Held] = []
    for targets, sent, names in chunks:  # each goes on from what the one before left held
        start = held[-1].targets[-1] if held else initial
        held.append(hold_targets(targets, sent, names, joints, initial=start))
    targets = np.concatenate([h.targets for h in held])
    commanded = np.concatenate([h.sent for h in held])
    if not bool(np.isfinite(targets[commanded]).all()):  # the files are checked first: see play()
        raise MotionToolError("a motion commands a non-finite target (nan or inf): not played")
    lengths = [len(s.elapsed_ms) for s in streams]
    return targets, commanded, lengths, ignored


def play(
    motions: Sequence[str | Path | Motion],
    *,
    names: Sequence[str] | None = None,
    robot: str | RobotSpec = "auto",
    options: PlayOptions | None = None,
    rrd: str | Path | None = None,
    stamps: Mapping[str, Any] | None = None,
) -> PlayReport:
    """Play ``motions`` one after another on ``robot`` and measure the run.

    Args:
        motions: motion files (read with :func:`read_playable`) or :class:`Motion` objects
            (already read, or made in memory: a batch's retimed motion).
        names: how the report and the recording name each motion; default: the path as given,
            ``<motion N>`` for a Motion object.
        robot: a RobotSpec, or a name for :func:`motiontool.kinematics.resolve_robot`
            (``auto``: the built-in robot the joints of all the motions fit).
        options: how to play (:class:`PlayOptions`).
        rrd: write a Rerun recording of the run there (also when the run fails).
        stamps: versions to stamp the report and the recording with (tool, libraries, model
            hash; :func:`motiontool.stamps.stamps`); the time steps and seed are added.

    Raises:
        MotionToolError: a file Webots would reject, a bad option, or no robot
            (:class:`~motiontool.kinematics.robots.RobotError`: unknown, or none fits). A run
            that fails (falls, collides, raises a warning, stops on a MuJoCo error) is reported,
            not raised.
    """
    from motiontool.sim import _mujoco

    opts = options or PlayOptions()
    opts.check()
    if not motions:
        raise MotionToolError("no motion file to play")
    loaded = [m if isinstance(m, Motion) else read_playable(m) for m in motions]
    labels = _names(motions, names)
    spec = robot if isinstance(robot, RobotSpec) else resolve_robot(robot, _columns(loaded))
    timestep = opts.timestep_ms or spec.default_timestep_ms
    physics = resolve_physics(
        timestep,
        profile=opts.profile,
        physics_step_ms=opts.physics_step_ms,
        friction=opts.floor_friction,
        friction_scale=opts.friction_scale,
    )
    scene = _scene(spec, timestep, physics, opts, loaded[0])
    targets, commanded, lengths, ignored = command_matrix(
        loaded,
        scene.joints,
        timestep,
        scene.data.qpos[scene.qpos_adr].copy(),
        reverse=opts.reverse,
        loops=opts.loops,
        hold_steps=round(opts.hold_s * MS_PER_S / timestep),
    )
    for name in ignored:
        log.info("joint %r is not a motor of robot %s: ignored (as Webots does)", name, spec.name)
    trace = _mujoco.run(scene, targets, commanded, record_bodies=rrd is not None)
    files = _file_runs(labels, lengths, scene.control_step_s)
    run = _Run(scene, trace, opts, loaded, lengths, timestep, files)
    all_stamps = _all_stamps(stamps, scene, timestep, opts)
    report = _report(run, physics, all_stamps, ignored)
    if rrd is not None:
        _record(Path(rrd), run, report, all_stamps, labels)
    return report


@dataclass(frozen=True)
class _Run:
    """A simulated run and how it was asked for: what the report and recording are made of.

    Attributes:
        motions: the motions played, ``lengths`` their control steps, ``files`` their
            report entries; timestep_ms: the control step, ms.
    """

    scene: Scene
    trace: Trace
    opts: PlayOptions
    motions: list[Motion]
    lengths: list[int]
    timestep_ms: int
    files: list[FileRun]


def _columns(motions: Sequence[Motion]) -> Iterator[str]:
    """The joint names of every column of ``motions``."""
    return (j for m in motions for j in m.joints)


def _names(motions: Sequence[str | Path | Motion], names: Sequence[str] | None) -> list[str]:
    """The name of each motion in the report (see :func:`play`)."""
    if names is None:
        return [
            f"<motion {k + 1}>" if isinstance(m, Motion) else str(m) for k, m in enumerate(motions)
        ]
    if len(names) != len(motions):
        raise MotionToolError(f"{len(names)} names for {len(motions)} motions")
    return list(names)


def _start_joints(
    spec: RobotSpec, opts: PlayOptions, first: Motion, timestep_ms: int
) -> dict[str, float]:
    """Each motor's start position, rad (m): zero; lying, the first motion's first pose; then
    the start noise (drawn from the seed)."""
    import numpy as np

    start_joints = {j: 0.0 for j in spec.joint_names}
    if StartState(opts.start).lying:  # lying: the joints at the first motion's first pose
        stream = sample(first, timestep_ms, reverse=opts.reverse)
        for name, value, sent in zip(
            stream.joints, stream.targets[0].tolist(), stream.commanded[0].tolist(), strict=True
        ):
            if name in start_joints and sent:
                start_joints[name] = value
    if opts.start_noise_rad > 0:
        rng = np.random.default_rng(opts.seed)
        noise = rng.normal(0.0, opts.start_noise_rad, len(start_joints))
        start_joints = {
            k: v + float(e) for (k, v), e in zip(start_joints.items(), noise, strict=True)
        }
    return start_joints


def _scene(
    spec: RobotSpec, timestep_ms: int, physics: Physics, opts: PlayOptions, first: Motion
) -> Scene:
    """The scene at its start state (:func:`motiontool.sim._mujoco.build_scene`)."""
    from motiontool.sim import _mujoco

    return _mujoco.build_scene(
        spec,
        timestep_ms,
        physics_step_ms=physics.timestep_ms,
        start=opts.start,
        start_joints=_start_joints(spec, opts, first, timestep_ms),
        floor_friction=physics.friction,
        mass_scale=opts.mass_scale,
        torque_scale=opts.torque_scale,
        start_yaw_deg=opts.start_yaw_deg,
        p_gain=opts.p_gain,
    )


def _file_runs(names: Sequence[str], lengths: Sequence[int], step_s: float) -> list[FileRun]:
    """Where each motion starts and how long it plays, its ``lengths`` in control steps."""
    files = []
    step = 0
    for name, n in zip(names, lengths, strict=True):
        files.append(FileRun(name, step * step_s, n * step_s, n))
        step += n
    return files


def _all_stamps(
    stamps: Mapping[str, Any] | None, scene: Scene, timestep_ms: int, opts: PlayOptions
) -> dict[str, Any]:
    """``stamps``, MuJoCo's version and the model hash where missing, the steps and the seed."""
    from motiontool.sim import _mujoco

    out = dict(stamps or {})
    out.setdefault("mujoco", _mujoco.mujoco_version())
    out.setdefault("model_sha256", scene.robot.model_hash)
    out.update(
        control_step_ms=timestep_ms,
        physics_step_ms=scene.physics_step_s * MS_PER_S,
        seed=opts.seed,
    )
    return out


def _options_doc(opts: PlayOptions, physics: Physics) -> dict[str, Any]:
    """The report's ``options``: the options but those stamped, the floor friction used."""
    doc = {
        k: v for k, v in asdict(opts).items() if k not in ("timestep_ms", "physics_step_ms", "seed")
    }
    doc["p_gain_per_s"] = doc.pop("p_gain")
    doc["floor_friction"] = physics.friction
    return doc


def _report(run: _Run, physics: Physics, stamps: dict[str, Any], ignored: list[str]) -> PlayReport:
    """The report of ``run``."""
    scene, opts = run.scene, run.opts
    report = _measure(run, _options_doc(opts, physics), stamps, ignored)
    report.unplayed_files = [
        f.path
        for f, m in zip(run.files, run.motions, strict=True)
        if not any(j in scene.robot for j in m.joints)
    ]
    timestep_ms, friction = read_back(scene)  # what the compiled model really has
    report.physics = {**physics.to_json(), "timestep_ms": timestep_ms, "friction": friction}
    report.end_effector = measure_end_effector(
        scene,
        run.trace,
        run.motions,
        run.lengths,
        run.timestep_ms,
        reverse=opts.reverse,
        loops=opts.loops,
        reach_tolerance_mm=opts.reach_tolerance_mm,
    )
    return report


def _record(
    path: Path, run: _Run, report: PlayReport, stamps: dict[str, Any], names: Sequence[str]
) -> None:
    """Write the Rerun recording of ``run`` (:mod:`motiontool.sim.recording`)."""
    from motiontool.sim import _mujoco, recording

    scene = run.scene
    recording.write_recording(
        path,
        run.trace,
        _mujoco.scene_shapes(scene),
        limits=scene.limits,
        joint_limbs=scene.joint_limbs,
        markers=_markers(run, report),
        end_effector=report.end_effector,
        properties={k: "" if v is None else str(v) for k, v in stamps.items()},
        name=" + ".join(Path(n).name for n in names) + f" on {scene.robot.name}",
    )


# ------------------------------------------------------------------------------- measuring


def _tilt_and_heading(quat: npt.NDArray[np.float64]) -> tuple[Any, Any]:
    """(tilt, heading) in degrees of (N, 4) quaternions (w, x, y, z)."""
    import numpy as np

    w, x, y, z = quat.T
    r22 = np.clip(1.0 - 2.0 * (x * x + y * y), -1.0, 1.0)
    r00 = 1.0 - 2.0 * (y * y + z * z)
    r10 = 2.0 * (x * y + w * z)
    return np.degrees(np.arccos(r22)), np.degrees(np.arctan2(r10, r00))


def _down(trace: Trace, opts: PlayOptions) -> npt.NDArray[np.bool_]:
    tilt, _heading = _tilt_and_heading(trace.base_quat)
    down: npt.NDArray[np.bool_] = (trace.base_pos[:, 2] < opts.fall_height_m) | (
        tilt > opts.fall_tilt_deg
    )
    return down


def _fall_direction_deg(quat: npt.NDArray[np.float64], heading_deg: float) -> float:
    """Which way a root with orientation ``quat`` (w, x, y, z) leans, in degrees from
    ``heading_deg`` (the heading it had while up), in (-180, 180]: 0 forward, 90 left, -90
    right, 180 back (the horizontal direction of its z axis)."""
    w, x, y, z = (float(v) for v in quat)
    lean = math.degrees(math.atan2(2.0 * (y * z - w * x), 2.0 * (x * z + w * y)))
    turned = (lean - heading_deg + 180.0) % 360.0 - 180.0
    return 180.0 if turned == -180.0 else turned


def _base(trace: Trace, opts: PlayOptions) -> BaseStats:
    import numpy as np

    tilt, heading = _tilt_and_heading(trace.base_quat)
    down = _down(trace, opts)
    up = np.flatnonzero(~down)
    yaw: float | None = None
    if len(up):
        steps = np.diff(heading[up])
        yaw = float(np.sum((steps + 180.0) % 360.0 - 180.0))
    fell_at: float | None = None
    direction: float | None = None
    if len(up):
        after = np.flatnonzero(down[up[0] :])
        if len(after):
            k = up[0] + after[0]  # the first frame down; k - 1 was up
            fell_at = float(trace.time_s[k])
            direction = _fall_direction_deg(trace.base_quat[k], float(heading[k - 1]))
    d = trace.base_pos[-1] - trace.base_pos[0]
    return BaseStats(
        dx_m=float(d[0]),
        dy_m=float(d[1]),
        dz_m=float(d[2]),
        yaw_change_deg=yaw,
        max_tilt_deg=float(tilt.max()),
        final_tilt_deg=float(tilt[-1]),
        min_height_m=float(trace.base_pos[:, 2].min()),
        final_height_m=float(trace.base_pos[-1, 2]),
        started_down=bool(down[0]),
        fell=fell_at is not None,
        fell_at_s=fell_at,
        upright_at_end=not bool(down[-1]),
        fall_direction_deg=direction,
    )


def _feet(trace: Trace) -> list[FootStats]:
    import numpy as np

    out = []
    dt = trace.control_step_s
    for f, name in enumerate(trace.feet):
        xy = trace.foot_pos[:, f, :2]
        touching = trace.foot_contact[:, f]
        moves = np.linalg.norm(np.diff(xy, axis=0), axis=1)
        both = touching[1:] & touching[:-1]
        away = np.linalg.norm(xy - xy[0], axis=1)
        out.append(
            FootStats(
                name=name,
                contact_s=float(touching[1:].sum() * dt),
                slip_m=float(moves[both].sum()),
                max_displacement_m=float(away.max()),
                final_displacement_m=float(away[-1]),
            )
        )
    return out


def _joints(scene: Scene, trace: Trace) -> list[JointStats]:
    import numpy as np

    lim = scene.limits
    dt = trace.control_step_s
    clipped = np.clip(trace.targets, lim.lower, lim.upper)
    error = clipped - trace.position[1:]
    at_velocity_cap = np.abs(trace.velocity_cmd) >= lim.max_velocity
    at_torque_cap = np.abs(trace.torque) >= TORQUE_CAP_FRACTION * lim.max_torque
    outside_target = (trace.targets < lim.lower) | (trace.targets > lim.upper)
    pos = trace.position[1:]
    beyond = (pos < lim.lower - LIMIT_TOLERANCE) | (pos > lim.upper + LIMIT_TOLERANCE)
    ever: npt.NDArray[np.bool_] = np.asarray(trace.commanded.any(axis=0))
    first = np.where(ever, trace.commanded.argmax(axis=0), 0)
    out = []
    for j, name in enumerate(trace.joints):
        e = error[first[j] :, j]
        unit = scene.robot.joint(name).unit
        out.append(
            JointStats(
                name=name,
                limb=scene.joint_limbs[j],
                unit=unit,
                commanded=bool(ever[j]),
                rms_error=float(np.sqrt(np.mean(e * e))) if len(e) else 0.0,
                max_error=float(np.abs(e).max()) if len(e) else 0.0,
                velocity_cap_s=float(at_velocity_cap[:, j].sum() * dt),
                torque_cap_s=float(at_torque_cap[:, j].sum() * dt),
                target_clipped_s=float(outside_target[:, j].sum() * dt),
                beyond_limits_s=float(beyond[:, j].sum() * dt),
            )
        )
    return out


def _counted(trace: Trace, kind: str, opts: PlayOptions) -> list[ContactEvent]:
    """The events of ``kind``; self-collisions: the probe's from the tolerance down, and every
    contact between robot bodies that the simulation itself collides."""
    if kind != "self":
        return [e for e in trace.events if e.kind == kind]
    floor = opts.collision_tolerance_mm / MM_PER_M
    return [
        e for e in trace.events if e.kind == "touch" or (e.kind == "self" and e.depth_m >= floor)
    ]


def _contact_summaries(trace: Trace, kind: str, opts: PlayOptions) -> list[ContactSummary]:
    """One summary per pair of bodies: first frame, frames seen (as a duration), deepest."""
    first: dict[tuple[str, str], int] = {}
    frames: dict[tuple[str, str], set[int]] = {}
    depth: dict[tuple[str, str], float] = {}
    for e in _counted(trace, kind, opts):
        key = (e.body_a, e.body_b)
        first[key] = min(first.get(key, e.frame), e.frame)
        frames.setdefault(key, set()).add(e.frame)
        depth[key] = max(depth.get(key, 0.0), e.depth_m)
    return [
        ContactSummary(
            key[0],
            key[1],
            float(trace.time_s[first[key]]),
            len(frames[key]) * trace.control_step_s,
            depth[key],
        )
        for key in sorted(first, key=lambda k: (first[k], k))
    ]


def _measure(
    run: _Run, options_doc: dict[str, Any], stamps: dict[str, Any], ignored: list[str]
) -> PlayReport:
    scene, trace, opts = run.scene, run.trace, run.opts
    return PlayReport(
        robot=scene.robot.name,
        files=run.files,
        options=options_doc,
        stamps=stamps,
        simulated_s=float(trace.time_s[-1]),
        control_steps=trace.steps_done,
        joints=_joints(scene, trace),
        base=_base(trace, opts) if scene.floating else None,
        feet=_feet(trace),
        self_collisions=_contact_summaries(trace, "self", opts),
        scene_contacts=_contact_summaries(trace, "scene", opts),
        ground_contacts=_contact_summaries(trace, "ground", opts),
        warnings=dict(trace.warnings),
        ignored_joints=ignored,
        error=trace.error,
    )


def _starts(flags: npt.NDArray[np.bool_]) -> npt.NDArray[np.intp]:
    """Indices where a boolean series turns true."""
    import numpy as np

    prev = np.concatenate([[False], flags[:-1]])
    return np.flatnonzero(flags & ~prev)


def _markers(run: _Run, report: PlayReport) -> list[Marker]:
    """Events of the run for the recording's timeline, in time order."""
    trace = run.trace
    out = [Marker(f.start_s, "INFO", f"start {Path(f.path).name}", "motion") for f in run.files]
    if report.base is not None:
        out += _fall_markers(trace, run.opts)
    out += _contact_markers(trace, run.opts)
    out += _limit_markers(trace, run.scene.limits)
    t_end = float(trace.time_s[-1])
    raised = {k: v for k, v in trace.warnings.items() if v}
    if raised:
        out.append(Marker(t_end, "ERROR", f"MuJoCo warnings: {raised}", "simulator"))
    if trace.error:
        out.append(Marker(t_end, "ERROR", trace.error, "simulator"))
    out.sort(key=lambda m: m.time_s)
    return out


def _fall_markers(trace: Trace, opts: PlayOptions) -> list[Marker]:
    """Where the robot goes down and gets up again (not at the start)."""
    t = trace.time_s
    down = _down(trace, opts)
    out = [
        Marker(float(t[k]), "ERROR", "fell (root low or tilted)", "fall")
        for k in _starts(down).tolist()
        if k
    ]
    out += [Marker(float(t[k]), "INFO", "upright", "fall") for k in _starts(~down).tolist() if k]
    return out


_CONTACT_WORDS = {"self": "self-collision", "scene": "contact", "ground": "on the floor"}
"""How the recording's event log names each kind of counted contact."""


def _contact_markers(trace: Trace, opts: PlayOptions) -> list[Marker]:
    """Where each pair of bodies starts touching, for each counted kind of contact."""
    import numpy as np

    t = trace.time_s
    frames: dict[tuple[str, str, str], list[int]] = {}
    for kind in _CONTACT_WORDS:
        for e in _counted(trace, kind, opts):
            frames.setdefault((kind, e.body_a, e.body_b), []).append(e.frame)
    out = []
    for (kind, a, b), ks in frames.items():
        flags = np.zeros(len(t), dtype=bool)
        flags[ks] = True
        level = "INFO" if kind == "ground" else "WARN"
        text = f"{_CONTACT_WORDS[kind]}: {a} / {b}"
        out += [Marker(float(t[k]), level, text, "collision") for k in _starts(flags).tolist()]
    return out


def _limit_markers(trace: Trace, lim: MotorLimits) -> list[Marker]:
    """Where a target starts to lie outside the limits (it is clipped), and where a position
    starts to lie past them by more than :data:`LIMIT_TOLERANCE`."""
    t = trace.time_s
    out = []
    for j, name in enumerate(trace.joints):
        lower, upper = lim.lower[j], lim.upper[j]
        target = trace.targets[:, j]
        for k in _starts((target < lower) | (target > upper)).tolist():
            text = f"{name} target {target[k]:.4g} outside [{lower:.4g}, {upper:.4g}]: clipped"
            out.append(Marker(float(t[k]), "WARN", text, "limit"))
        pos = trace.position[:, j]
        beyond = (pos < lower - LIMIT_TOLERANCE) | (pos > upper + LIMIT_TOLERANCE)
        for k in _starts(beyond).tolist():
            text = f"{name} at {pos[k]:.4g}, past its limits"
            out.append(Marker(float(t[k]), "WARN", text, "limit"))
    return out
