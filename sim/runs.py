"""One batch run: a :class:`~motiontool.sim.batch.RunSpec` played in MuJoCo, as a JSON report.

This is the runner the batch executors ship to their workers (a module-level function, so it
pickles by reference). Perturbations map onto :class:`~motiontool.sim.play.PlayOptions`; the
``speed`` perturbation retimes the motion (times only) before it is played.
"""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Any

from motiontool.sim.batch import RunSpec

__all__ = ["run_spec"]

_OPTION_OF = {
    "friction": "friction_scale",
    "mass": "mass_scale",
    "motor-strength": "torque_scale",
    "start-yaw": "start_yaw_deg",
    "start-noise": "start_noise_rad",
}


def _retimed_copy(path: str, speed: float, directory: str) -> str:
    """The motion played ``speed`` times faster: pose times as ``retime --speed`` writes them
    (:func:`motiontool.motionfmt.transform.scale_times`, whole ms)."""
    from motiontool.motionfmt import load
    from motiontool.motionfmt.transform import scale_times

    doc = load(path)
    doc.set_times(list(scale_times(doc.motion.times_ms.tolist(), speed).times_ms))
    out = Path(directory) / Path(path).name
    out.write_bytes(doc.to_bytes())
    return str(out)


def run_spec(spec: RunSpec) -> dict[str, Any]:
    """Play ``spec`` headless and return the play report as JSON (``clean``, ``reason``, ...)."""
    from motiontool.kinematics.robots import AUTO, resolve_robot
    from motiontool.motionfmt import read_motion
    from motiontool.sim.play import PlayOptions, play
    from motiontool.stamps import stamps

    params = dict(spec.params)
    options = dict(spec.options)
    kwargs: dict[str, Any] = {_OPTION_OF[k]: v for k, v in params.items() if k in _OPTION_OF}
    if options.get("timestep_ms"):
        kwargs["timestep_ms"] = int(options["timestep_ms"])
    if options.get("start"):
        kwargs["start"] = str(options["start"])
    for name in ("physics_step_ms", "floor_friction", "profile"):  # sim.physics.physics_run_options
        if options.get(name) is not None:
            kwargs[name] = options[name]
    kwargs["seed"] = spec.sample
    # plan() has resolved "auto" where a built-in robot fits; where none does, this run fails
    # alone, NoRobotDetectedError saying why in one line.
    joints = read_motion(spec.path).joints if spec.robot == AUTO else ()
    robot = resolve_robot(spec.robot, joints)
    rrd = None
    if options.get("rrd_dir"):
        stem = options.get("rrd_name") or Path(spec.path).stem
        rrd = Path(options["rrd_dir"]) / f"{stem}.{robot.name}.{spec.sample}.rrd"
    with tempfile.TemporaryDirectory() as tmp:
        path = spec.path
        if "speed" in params and params["speed"] != 1.0:
            path = _retimed_copy(spec.path, params["speed"], tmp)
        report = play([path], robot=robot, options=PlayOptions(**kwargs), rrd=rrd,
                      stamps=stamps(robot.model_hash))  # fmt: skip
    doc = report.to_json()
    doc["files"][0]["path"] = spec.path
    doc["perturbation"] = params
    return doc
