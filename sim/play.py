"""Play motion files headlessly in MuJoCo as a Webots controller would, and measure the run.

A run: the motions' command streams (:func:`motiontool.motionfmt.sample`, the exact targets a
Webots controller sends) are played one after another, each starting at the control step after
the previous one is over (``wbu_motion_is_over``), then the last targets are held for
``hold_s``. Every control step the Webots motor law (:mod:`motiontool.sim.motor`) turns targets
into velocity commands that MuJoCo realises with bounded-force velocity constraints
(:mod:`motiontool.sim._mujoco`). The trace is then measured into a :class:`PlayReport` and, on
request, recorded to a Rerun ``.rrd`` (:mod:`motiontool.sim.recording`).

This module drives the run; one module per step: the options (:mod:`motiontool.sim.play_options`),
the command stream (:mod:`motiontool.sim.commands`), measuring the trace
(:mod:`motiontool.sim.measure`) and the recording's event log (:mod:`motiontool.sim.markers`).
Their public names are importable from here as before.
"""

from __future__ import annotations

import contextlib
import logging
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import asdict
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

from motiontool.errors import MotionSyntaxError, MotionToolError
from motiontool.kinematics.robots import RobotSpec, resolve_robot
from motiontool.motionfmt import Motion, iter_commands, read_bytes, read_file
from motiontool.motionfmt.fileio import open_output, source_name
from motiontool.motionfmt.units import MS_PER_S
from motiontool.sim.arm import ToolMeter
from motiontool.sim.bag import BagTarget, RunBag, scene_bag
from motiontool.sim.chain import ElementMeter, posed
from motiontool.sim.commands import CommandChunks, command_matrix, command_stream, each_loops
from motiontool.sim.markers import Marker, MarkerMeter
from motiontool.sim.measure import LIMIT_TOLERANCE, TORQUE_CAP_FRACTION, RunMeter
from motiontool.sim.physics import read_back, resolve_physics
from motiontool.sim.play_options import PlayOptions
from motiontool.sim.report import FileRun, PlayReport
from motiontool.sim.self_collision import self_collision, self_collision_doc
from motiontool.sim.start import StartState
from motiontool.sim.trace import Trace

if TYPE_CHECKING:
    from motiontool.sim._mujoco import Scene
    from motiontool.sim.live import LiveView
    from motiontool.sim.physics import Physics
    from motiontool.sim.recording import RunRecorder
    from motiontool.sim.world_run import WorldRun

__all__ = [
    "LIMIT_TOLERANCE",
    "TORQUE_CAP_FRACTION",
    "Marker",
    "PlayOptions",
    "Progress",
    "command_matrix",
    "command_stream",
    "play",
    "read_playable",
]

log = logging.getLogger("motiontool")


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


def play(
    motions: Sequence[str | Path | Motion],
    *,
    names: Sequence[str] | None = None,
    robot: str | RobotSpec = "auto",
    options: PlayOptions | None = None,
    rrd: str | Path | None = None,
    stamps: Mapping[str, Any] | None = None,
    bag: str | Path | BagTarget | None = None,
    progress: Progress | None = None,
    world: WorldRun | None = None,
    live: LiveView | None = None,
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
        bag: write the run there as a ROS 2 bag (:func:`motiontool.sim.bag.scene_bag`).
        stamps: versions to stamp the report and the recording with (tool, libraries, model
            hash; :func:`motiontool.stamps.stamps`); the time steps and seed are added.
        progress: called after each chunk of the run with the simulated seconds done and in
            all (for a progress display).
        world: what the run takes of a Webots world (:mod:`motiontool.sim.world_run`).
        live: show the run live as it is recorded, paced (:mod:`motiontool.sim.live`; raises
            its :class:`~motiontool.sim.live.ViewerClosed` when the viewer goes away).

    Raises:
        MotionToolError: a file Webots would reject, a bad option, or no robot
            (:class:`~motiontool.kinematics.robots.RobotError`: unknown, or none fits). A run
            that fails (falls, collides, raises a warning, stops on a MuJoCo error) is reported,
            not raised.
    """

    opts = options or PlayOptions()
    opts.check()
    if not motions:
        raise MotionToolError("no motion file to play")
    loaded = [m if isinstance(m, Motion) else read_playable(m) for m in motions]
    labels = _names(motions, names)
    spec = robot if isinstance(robot, RobotSpec) else resolve_robot(robot, _columns(loaded))
    timestep, physics, scene = _setup(spec, opts, loaded[0], world)
    stream = _commands(
        loaded, scene, timestep, opts, None if live is None else live.chunk_steps(timestep)
    )
    meter, elements = RunMeter(scene, opts), _elements(labels, stream, timestep, opts, scene)
    tool = _tool_meter(scene, loaded, stream.lengths, timestep, opts)
    all_stamps = _all_stamps(stamps, scene, timestep, opts)
    with _recorder(rrd, live, scene, all_stamps, labels) as recorder, _bag(bag, scene) as run_bag:
        events = _markers(scene, opts) if recorder else None
        pacer = None if live is None else live.pacer()  # before the recorder: shown when due
        takers = (meter, tool, events, pacer, recorder, run_bag, elements)
        told = _Progress.of(progress, stream, scene)
        _simulate(scene, stream, (*takers, told), record=(recorder, run_bag) != (None, None))
        report = _report(meter, elements.files(), loaded, physics, all_stamps, stream.ignored)
        report.world = None if world is None else _world_doc(world, opts, timestep, physics)
        report.self_collision = self_collision_doc(scene, opts, world, meter)
        report.end_effector = None if tool is None else tool.stats()
        if recorder is not None and events is not None:
            recorder.finish(events.markers(report.files), report.end_effector, report.world)
    return report


def _markers(scene: Scene, opts: PlayOptions) -> MarkerMeter:
    """The recording's event markers of a run, its self-collisions counted as the run's."""
    return MarkerMeter(scene.limits, opts, floating=scene.floating, touches=scene.touch_counts)


def _setup(
    spec: RobotSpec, opts: PlayOptions, first: Motion, world: WorldRun | None
) -> tuple[int, Physics, Scene]:
    """The control step (ms: the options', the world's, the robot's), the physics and the
    scene of a run."""
    timestep = opts.timestep_ms or (world and world.control_step_ms) or spec.default_timestep_ms
    physics = _physics(timestep, opts, world)
    return timestep, physics, _scene(spec, timestep, physics, opts, first, world)


def _world_doc(
    placed: WorldRun, opts: PlayOptions, timestep_ms: int, physics: Physics
) -> dict[str, Any]:
    """The report's ``world``: what the run took from the world, and what it did not."""
    return placed.report(
        control_step_ms=timestep_ms,
        timestep_given=opts.timestep_ms is not None,
        physics_step_ms=physics.timestep_ms,
        friction_given=opts.floor_friction is not None,
        self_collision_given=opts.self_collision is not None,
    )


def _physics(timestep_ms: int, opts: PlayOptions, placed: WorldRun | None) -> Physics:
    """The physics settings of a run at control step ``timestep_ms`` with ``opts`` (the
    friction: ``--friction``, else the world's, else the profile's)."""
    friction = opts.floor_friction
    if friction is None and placed is not None:
        friction = placed.friction(None)
    return resolve_physics(
        timestep_ms,
        profile=opts.profile,
        physics_step_ms=opts.physics_step_ms,
        friction=friction,
        friction_scale=opts.friction_scale,
    )


class _Measures(Protocol):
    """What takes a run's chunks as they are simulated."""

    def add(self, chunk: Trace) -> None: ...


Progress = Callable[[float, float], None]
"""Told the simulated seconds done and in all, after each chunk of a run."""


class _Progress:
    """Tells a :data:`Progress` how far the run is, a chunk at a time."""

    def __init__(self, tell: Progress, total_s: float) -> None:
        self.tell, self.total_s = tell, total_s

    @classmethod
    def of(cls, tell: Progress | None, stream: CommandChunks, scene: Scene) -> _Progress | None:
        if tell is None:
            return None
        return cls(tell, stream.steps * scene.control_step_s)

    def add(self, chunk: Trace) -> None:
        self.tell(float(chunk.time_s[-1]), self.total_s)


def _simulate(
    scene: Scene, stream: CommandChunks, takers: Sequence[_Measures | None], *, record: bool
) -> None:
    """Play ``stream`` in ``scene`` a chunk at a time, each given to the ``takers`` (but None)
    as it comes (``record``: with every body's pose, for a recording or a bag); nothing of a
    chunk is kept here."""
    from motiontool.sim import _mujoco

    present = [m for m in takers if m is not None]
    for chunk in _mujoco.run_chunks(scene, stream.chunks, record_bodies=record):
        for taker in present:
            taker.add(chunk)


@contextlib.contextmanager
def _bag(target: str | Path | BagTarget | None, scene: Scene) -> Iterator[RunBag | None]:
    """The ROS 2 bag of the run, to ``target`` (None: no bag)
    (:func:`motiontool.sim.bag.scene_bag`), written as every output is
    (:func:`motiontool.motionfmt.fileio.open_output`): whole, or not at all when the run
    fails to end."""
    if target is None:
        yield None
        return
    target = target if isinstance(target, BagTarget) else BagTarget(target)
    with open_output(target.path) as sink:
        bag = scene_bag(sink, scene, target.start_ns)
        yield bag
        bag.finish()


@contextlib.contextmanager
def _recorder(
    rrd: str | Path | None,
    live: LiveView | None,
    scene: Scene,
    stamps: dict[str, Any],
    names: Sequence[str],
) -> Iterator[RunRecorder | None]:
    """The Rerun recording of the run, to ``rrd`` and ``live`` (both None: no recording)
    (:class:`motiontool.sim.recording.RunRecorder`): its temporary file is removed however
    the run ends."""
    if rrd is None and live is None:
        yield None
        return
    from motiontool.sim import _mujoco, recording

    with recording.RunRecorder(
        None if rrd is None else Path(rrd),
        _mujoco.scene_shapes(scene),
        limits=scene.limits,
        joints=scene.joints,
        joint_limbs=scene.joint_limbs,
        properties={k: "" if v is None else str(v) for k, v in stamps.items()},
        name=" + ".join(Path(n).name for n in names) + f" on {scene.robot.name}",
        live=live,
    ) as recorder:
        yield recorder


def _commands(
    motions: Sequence[Motion],
    scene: Scene,
    timestep_ms: int,
    opts: PlayOptions,
    chunk_steps: int | None = None,
) -> CommandChunks:
    """The command stream of ``motions`` on the scene's motors (:func:`command_stream`, from
    the positions the scene starts at, then ``opts.hold_s`` of holding, in chunks of
    ``chunk_steps``, else the usual ones); the columns that are no motor are logged, as Webots
    warns of them."""
    stream = command_stream(
        motions,
        scene.joints,
        timestep_ms,
        scene.data.qpos[scene.qpos_adr].copy(),
        reverse=opts.reverse,
        loops=_loops(opts, len(motions)),
        hold_steps=round(opts.hold_s * MS_PER_S / timestep_ms),
        chunk_steps=chunk_steps,
    )
    for name in stream.ignored:
        log.info(
            "joint %r is not a motor of robot %s: ignored (as Webots does)", name, scene.robot.name
        )
    return stream


def _tool_meter(
    scene: Scene,
    motions: Sequence[Motion],
    lengths: Sequence[int],
    timestep_ms: int,
    opts: PlayOptions,
) -> ToolMeter | None:
    """What measures the end effector of an arm (None: the robot has none)."""
    if scene.tool is None:
        return None
    return ToolMeter(
        scene,
        motions,
        lengths,
        timestep_ms,
        reverse=opts.reverse,
        loops=_loops(opts, len(motions)),
        reach_tolerance_mm=opts.reach_tolerance_mm,
    )


def _elements(
    names: Sequence[str], stream: CommandChunks, timestep_ms: int, opts: PlayOptions, scene: Scene
) -> ElementMeter:
    """What places each motion in the run and measures what the base did during it."""
    loops = _loops(opts, len(names))
    return ElementMeter(names, stream.lengths, timestep_ms, loops, floating=scene.floating)


def _loops(opts: PlayOptions, count: int) -> list[int]:
    """The cycles of each of the ``count`` motions: the chain's, else ``opts.loops`` each."""
    return each_loops(opts.chain_loops or opts.loops, count)


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
    the start pose (``--start-pose``), then the start noise (drawn from the seed)."""
    import numpy as np

    start_joints = {j: 0.0 for j in spec.joint_names}
    if StartState(opts.start).lying:  # lying: the joints at the first motion's first pose
        stream = next(iter_commands(first, timestep_ms, reverse=opts.reverse, max_steps=1))
        for name, value, sent in zip(
            stream.joints, stream.targets[0].tolist(), stream.commanded[0].tolist(), strict=True
        ):
            if name in start_joints and sent:
                start_joints[name] = value
    start_joints.update(posed(opts.start_pose, opts.start_pose_joints, spec))
    if opts.start_noise_rad > 0:
        rng = np.random.default_rng(opts.seed)
        noise = rng.normal(0.0, opts.start_noise_rad, len(start_joints))
        start_joints = {
            k: v + float(e) for (k, v), e in zip(start_joints.items(), noise, strict=True)
        }
    return start_joints


def _scene(
    spec: RobotSpec,
    timestep_ms: int,
    physics: Physics,
    opts: PlayOptions,
    first: Motion,
    placed: WorldRun | None,
) -> Scene:
    """The scene at its start state (:func:`motiontool.sim._mujoco.build_scene`), in the
    world ``placed`` (None: a floor plane)."""
    from motiontool.sim import _mujoco

    if placed is not None and spec.floating_base:
        world_scene: dict[str, Any] = {
            "ground": placed.ground_for(opts.floor_friction, opts.friction_scale),
            "gravity": placed.gravity,
            "start_xy": placed.start_xy,
        }
        yaw = opts.start_yaw_deg + placed.start_yaw_deg
    else:
        world_scene, yaw = {}, opts.start_yaw_deg

    return _mujoco.build_scene(
        spec,
        timestep_ms,
        physics_step_ms=physics.timestep_ms,
        start=opts.start,
        start_joints=_start_joints(spec, opts, first, timestep_ms),
        floor_friction=physics.friction,
        mass_scale=opts.mass_scale,
        torque_scale=opts.torque_scale,
        start_yaw_deg=yaw,
        p_gain=opts.p_gain,
        self_collision=self_collision(opts, placed),
        **world_scene,
    )


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
        k: v
        for k, v in asdict(opts).items()
        if k not in ("timestep_ms", "physics_step_ms", "seed", "start_pose_joints")
    }
    doc["p_gain_per_s"] = doc.pop("p_gain")
    doc["floor_friction"] = physics.friction
    return doc


def _report(
    meter: RunMeter,
    files: list[FileRun],
    motions: Sequence[Motion],
    physics: Physics,
    stamps: dict[str, Any],
    ignored: list[str],
) -> PlayReport:
    """The report of the run ``meter`` measured."""
    scene, opts = meter.scene, meter.opts
    report = meter.report(files, _options_doc(opts, physics), stamps, ignored)
    report.unplayed_files = [
        f.path
        for f, m in zip(files, motions, strict=True)
        if not any(j in scene.robot for j in m.joints)
    ]
    timestep_ms, friction = read_back(scene)  # what the compiled model really has
    report.physics = {**physics.to_json(), "timestep_ms": timestep_ms, "friction": friction}
    return report
