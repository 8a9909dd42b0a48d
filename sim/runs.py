"""One batch run: a :class:`~motiontool.sim.batch.RunSpec` played in MuJoCo, as a JSON report.

This is the runner the batch executors ship to their workers (a module-level function, so it
pickles by reference). Perturbations map onto :class:`~motiontool.sim.play.PlayOptions`; the
``speed`` perturbation retimes the motion in memory (times only) before it is played.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from motiontool.sim.batch import RunSpec

if TYPE_CHECKING:
    from motiontool.kinematics.robots import RobotSpec
    from motiontool.motionfmt import Motion

__all__ = ["recording_path", "retimed", "run_outputs", "run_spec"]

_OPTION_OF = {
    "friction": "friction_scale",
    "mass": "mass_scale",
    "motor-strength": "torque_scale",
    "start-yaw": "start_yaw_deg",
    "start-noise": "start_noise_rad",
}

_PLAY = ("loops", "reverse", "hold_s")
"""Play options a batch does not set and ``play --robustness``'s members carry (their play's
``--loop``, ``--reverse``, ``--hold``): in the options, and so in the cache key, only there."""


def retimed(motion: Motion, speed: float) -> Motion:
    """``motion`` played ``speed`` times faster: pose times as ``retime --speed`` writes them
    (:func:`motiontool.motionfmt.retime.scale_times`, whole ms); values unchanged."""
    import numpy as np

    from motiontool.motionfmt.retime import scale_times

    times = scale_times(motion.times_ms.tolist(), speed).times_ms
    return replace(motion, times_ms=np.array(times, dtype=np.int64))


def recording_path(spec: RunSpec, robot: RobotSpec) -> Path | None:
    """Where the run of ``spec`` on ``robot`` keeps its recording
    (``<rrd_dir>/<name>.<robot>.<sample>.rrd``), or None when none is asked for."""
    options = dict(spec.options)
    if not options.get("rrd_dir"):
        return None
    stem = options.get("rrd_name") or Path(spec.path).stem
    return Path(options["rrd_dir"]) / f"{stem}.{robot.name}.{spec.sample}.rrd"


def run_outputs(spec: RunSpec) -> list[Path]:
    """The files the run of ``spec`` writes besides its report: its recording, if asked for
    (none for a file no robot fits: that run fails before it plays)."""
    from motiontool.kinematics.robots import AUTO, load_robot

    if spec.robot == AUTO:
        return []
    path = recording_path(spec, load_robot(spec.robot))
    return [] if path is None else [path]


def _play_options(spec: RunSpec) -> Any:
    """The :class:`~motiontool.sim.play.PlayOptions` of ``spec``: its options, its
    perturbation's factors, and its sample index as the seed."""
    from motiontool.sim.play import PlayOptions

    options = dict(spec.options)
    kwargs: dict[str, Any] = {_OPTION_OF[k]: v for k, v in spec.params if k in _OPTION_OF}
    if options.get("timestep_ms"):
        kwargs["timestep_ms"] = int(options["timestep_ms"])
    if options.get("start"):
        kwargs["start"] = str(options["start"])
    if options.get("start_pose"):  # batch --start-pose: the pose's joints, read by the driver
        kwargs["start_pose"] = str(options["start_pose"])
        kwargs["start_pose_joints"] = tuple(
            (str(k), float(v)) for k, v in options["start_pose_joints"]
        )
    for name in ("physics_step_ms", "floor_friction", "profile", "self_collision", "chain", *_PLAY):
        # sim.physics.physics_run_options; _PLAY: play --robustness's members
        if options.get(name) is not None:
            kwargs[name] = options[name]
    if options.get("chain_loops"):  # play --robustness's members: a chain's --loop NAME=N
        kwargs["chain_loops"] = tuple(int(n) for n in options["chain_loops"])
    return PlayOptions(**kwargs, seed=spec.sample)


def run_spec(spec: RunSpec) -> dict[str, Any]:
    """Play ``spec`` headless and return the play report as JSON (``clean``, ``reason``, ...)."""
    from motiontool.kinematics.robots import resolve_robot
    from motiontool.sim.play import play, read_playable
    from motiontool.sim.world_run import world_of
    from motiontool.stamps import stamps

    params = dict(spec.params)
    motion = read_playable(spec.path)
    # plan() has resolved "auto" where a built-in robot fits; where none does, this run fails
    # alone, NoRobotDetectedError saying why in one line.
    robot = resolve_robot(spec.robot, motion.joints)
    motions = [*(read_playable(p) for p in spec.chain), motion]  # a chain: the motions before
    if params.get("speed", 1.0) != 1.0:
        motions = [retimed(m, params["speed"]) for m in motions]
    report = play(
        motions,
        names=[*spec.chain, spec.path],
        robot=robot,
        options=_play_options(spec),
        rrd=recording_path(spec, robot),
        stamps=stamps(robot.model_hash),
        world=world_of(dict(spec.options), robot.name),
    )
    doc = report.to_json()
    doc["perturbation"] = params
    return doc
