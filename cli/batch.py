"""``motiontool batch``: play many files x robots x perturbations, locally or on a Ray cluster."""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from motiontool import exit_codes
from motiontool.cli.batch_progress import run_with_progress
from motiontool.cli.chain_options import AfterOption, StartPoseOption, start_pose_options
from motiontool.cli.config import ConfigOption, IsolatedOption, Resolver, Settings
from motiontool.cli.lint_run import collect
from motiontool.cli.options import MAX_COUNT, Timestep, finite, robot_option
from motiontool.cli.output import (
    emit,
    emit_pieces,
    refuse_overwrite,
    refuse_shared_outputs,
    require_folder,
    say_wrote,
)
from motiontool.cli.physics_options import (
    FrictionOption,
    PhysicsStepOption,
    Profile,
    ProfileOption,
    RobotNodeOption,
    SelfCollisionOption,
    WorldOption,
    chosen_world,
)
from motiontool.cli.ray_options import RayRuntimeEnvOption
from motiontool.cli.robustness import (
    RobustnessOption,
    StrictOption,
    robust_batch,
    with_robustness,
)
from motiontool.cli.run_options import NO_SIDECAR, Start, expect_option, start_option
from motiontool.cli.text import plural
from motiontool.errors import MotionToolError, OutputError
from motiontool.extras import EXTRAS, require
from motiontool.motionfmt.fileio import is_folder, is_stdin, output_kind, temporary_folder
from motiontool.sim.executor import EXECUTORS, REGISTRY, executor_info

if TYPE_CHECKING:
    from motiontool.sim.batch import BatchResult, RunSpec

__all__ = ["batch_command"]


def _timeout_range(value: float | None) -> float | None:
    """``--timeout``: finite and at most :data:`motiontool.sim.executor.MAX_TIMEOUT_S`."""
    if value is not None and finite(value) > _max_timeout_s():
        raise typer.BadParameter(f"{value:g} is more than {_max_timeout_s():g} s (a week)")
    return value


def _max_timeout_s() -> float:
    from motiontool.sim.executor import MAX_TIMEOUT_S

    return MAX_TIMEOUT_S


_Paths = Annotated[
    list[Path],
    typer.Argument(help="Motion files, or directories searched for *.motion.", show_default=False),
]
_Robots = Annotated[
    list[str] | None,
    robot_option(
        "Robot to play on, per file (default: auto)",
        more="Repeat to run every file on several robots.",
    ),
]
_Jobs = Annotated[
    int | None,
    typer.Option(
        "--jobs",
        "-j",
        min=1,
        max=MAX_COUNT,
        help="Runs in parallel (default: 2; on Ray, the cluster's CPUs, at most this).",
        show_default=False,
    ),
]
_Executor = Annotated[
    str,
    typer.Option("--executor", help=" or ".join(f"{e.name} ({e.summary})" for e in REGISTRY) + "."),
]
_RayAddress = Annotated[
    str | None,
    typer.Option(
        "--ray-address", help="Ray cluster to use (auto: the running one); default: start one."
    ),
]
_Timeout = Annotated[
    float | None,
    typer.Option(
        "--timeout", min=0.1, callback=_timeout_range, help="Wall-clock limit of one run, in s."
    ),
]
_Perturb = Annotated[
    list[str] | None,
    typer.Option(
        "--perturb",
        help="NAME=LOW:HIGH, uniform draws; NAME: friction, mass, motor-strength,"
        " start-yaw (deg), start-noise (rad), speed. Repeatable.",
    ),
]
_Samples = Annotated[
    int,
    typer.Option(
        "--samples", min=1, max=MAX_COUNT, help="Perturbation samples per file and robot."
    ),
]
_Seed = Annotated[int, typer.Option("--seed", help="Seed of the perturbation draws.")]
_Junit = Annotated[Path | None, typer.Option("--junit", help="Write JUnit XML here.")]
_Json = Annotated[Path | None, typer.Option("--json", help="Write every run's report (JSON) here.")]
_Markdown = Annotated[
    Path | None, typer.Option("--markdown", help="Write a Markdown summary here.")
]
_RrdDir = Annotated[
    Path | None,
    typer.Option("--rrd-dir", help="Keep a Rerun recording of every run in this folder."),
]
_Start = Annotated[Start | None, start_option("each motion's sidecar start")]
_Expect = Annotated[
    list[str] | None, expect_option("every run", "each motion's motions.toml sidecar")
]
_NoCache = Annotated[bool, typer.Option("--no-cache", help="Run everything again.")]
_CacheDir = Annotated[
    Path | None,
    typer.Option("--cache-dir", help="Result cache (default ~/.cache/motiontool/batch)."),
]
_CacheMaxMb = Annotated[
    float,
    typer.Option(
        "--cache-max-mb",
        min=0,
        callback=finite,
        help="After the batch, prune the cache to this many MB, least recently used results "
        "first ('motiontool cache clean' empties it).",
    ),
]


def batch_command(
    paths: _Paths,
    robot: _Robots = None,
    jobs: _Jobs = None,
    executor: _Executor = "local",
    ray_address: _RayAddress = None,
    ray_runtime_env: RayRuntimeEnvOption = None,
    timeout: _Timeout = None,
    perturb: _Perturb = None,
    samples: _Samples = 1,
    seed: _Seed = 0,
    timestep: Timestep = None,
    physics_step: PhysicsStepOption = None,
    friction: FrictionOption = None,
    profile: ProfileOption = Profile.default,
    world: WorldOption = None,
    robot_node: RobotNodeOption = None,
    self_collision: SelfCollisionOption = None,
    robustness: RobustnessOption = None,
    strict: StrictOption = False,
    junit: _Junit = None,
    json_out: _Json = None,
    markdown: _Markdown = None,
    rrd_dir: _RrdDir = None,
    start: _Start = None,
    start_pose: StartPoseOption = None,
    after: AfterOption = None,
    expect: _Expect = None,
    no_sidecar: Annotated[bool, NO_SIDECAR] = False,
    no_cache: _NoCache = False,
    cache_dir: _CacheDir = None,
    cache_max_mb: _CacheMaxMb = 500.0,
    config: ConfigOption = None,
    isolated: IsolatedOption = False,
) -> None:
    """Play every file headless on every robot and perturbation sample; exit 1 if any run is
    not clean: fell, collided, simulator warning, expectation not met, error, crash, timeout."""
    resolver = Resolver(config=config, isolated=isolated)
    files = _inputs(paths, resolver, executor=executor, ray=(ray_address, ray_runtime_env))
    outputs = {"--json": json_out, "--markdown": markdown, "--junit": junit, "--rrd-dir": rrd_dir}
    _check_outputs(files, outputs, cache_dir=cache_dir, executor=executor)
    specs = _plan(
        files,
        resolver,
        roots=[p for p in paths if is_folder(p)],
        robot=robot,
        timestep=timestep,
        physics=(profile, physics_step, friction, self_collision, world, robot_node),
        sampling=(perturb or [], samples, seed, robustness, strict),
        sidecar=(expect or [], start, not no_sidecar, start_pose, after),
        rrd_dir=rrd_dir,
    )
    _run_and_report(
        specs,
        outputs,
        profile=profile,
        execution=(executor, jobs, timeout, (ray_address, ray_runtime_env)),
        cache=(cache_dir, no_cache, cache_max_mb),
        robustness=(robustness, seed, strict),
    )


def _inputs(
    paths: list[Path],
    resolver: Resolver,
    *,
    executor: str,
    ray: tuple[str | None, dict[str, object] | None],
) -> list[Path]:
    """The motion files to play; an executor that does not exist, ``-`` or --ray-address (or
    --ray-runtime-env) with an executor that takes no cluster: exit 2 before anything runs."""
    if executor not in EXECUTORS:
        raise typer.BadParameter(
            f"{executor!r}: choose {' or '.join(EXECUTORS)}", param_hint="--executor"
        )
    if any(is_stdin(p) for p in paths):
        raise MotionToolError("batch reads motion files, not standard input ('-'): name files")
    files = collect(paths, resolver)  # folders searched, less the configuration's exclude
    for f in files:  # one that cannot be read (a folder nobody may search): exit 2 now
        try:
            os.close(os.open(f, os.O_RDONLY | os.O_NONBLOCK))
        except OSError as exc:
            raise MotionToolError(f"cannot read '{f}': {exc.strerror or exc}") from exc
    for option, given in zip(("--ray-address", "--ray-runtime-env"), ray, strict=True):
        if given is not None and not executor_info(executor).takes_address:
            takes = " or ".join(e.name for e in REGISTRY if e.takes_address)
            raise MotionToolError(
                f"{option} is for a cluster: use it with --executor {takes}, not {executor}"
            )
    return files


def _check_outputs(
    files: list[Path], outputs: dict[str, Path | None], *, cache_dir: Path | None, executor: str
) -> None:
    """No output over an input, no two reports on one file, folders that can be written, the
    extras the options need installed."""
    for option, out in outputs.items():
        refuse_overwrite(out, files, option)
    refuse_shared_outputs({k: v for k, v in outputs.items() if k != "--rrd-dir"})
    require_folder(outputs["--rrd-dir"], "--rrd-dir")
    require_folder(cache_dir, "--cache-dir")
    _require_extras(junit=outputs["--junit"], rrd_dir=outputs["--rrd-dir"], executor=executor)


def _make_recordings_folder(specs: list[RunSpec], outputs: dict[str, Path | None]) -> None:
    """The ``--rrd-dir`` folder made (with its parents), once no report (``--json``,
    ``--markdown``, ``--junit``) is on the file where it keeps a run's recording, named or
    through a symlink (a report replaced the recording and said "wrote"): that is refused,
    exit 2, before anything runs or is written."""
    import os

    from motiontool.sim.runs import run_outputs

    rrd_dir = outputs["--rrd-dir"]
    if rrd_dir is None:
        return
    reports = {
        os.path.realpath(path): option
        for option, path in outputs.items()
        if option != "--rrd-dir" and path is not None and output_kind(path) == "file"
    }
    for spec in specs if reports else []:
        for recording in run_outputs(spec):
            option = reports.get(os.path.realpath(recording))
            if option is not None:
                raise MotionToolError(
                    f"{option} and --rrd-dir both write '{recording}' (the recording of "
                    f"{spec.path} on {spec.robot}, sample {spec.sample}); give each its own file"
                )
    try:
        rrd_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"cannot write in '{rrd_dir}': {exc.strerror or exc}") from exc


def _require_extras(*, junit: Path | None, rrd_dir: Path | None, executor: str) -> None:
    """Stop (one line, exit 2) when an extra the options need is missing."""
    require("mujoco", "sim", "motiontool batch")
    if junit is not None:
        require("junitparser", "sim", "motiontool batch --junit")
    if rrd_dir is not None:
        require("rerun", "rerun", "motiontool batch --rrd-dir")
    extra = executor_info(executor).extra
    if extra is not None:
        for module in EXTRAS[extra][0]:
            require(module, extra, f"motiontool batch --executor {executor}")


def _plan(
    files: list[Path],
    resolver: Resolver,
    *,
    roots: list[Path],
    robot: list[str] | None,
    timestep: int | None,
    physics: tuple[Profile, float | None, float | None, bool | None, Path | None, str | None],
    sampling: tuple[list[str], int, int, int | None, bool],
    sidecar: tuple[list[str], Start | None, bool, str | None, Path | None],
    rrd_dir: Path | None,
) -> list[RunSpec]:
    """Every run of the batch (:func:`motiontool.sim.batch.plan_batch`): the options parsed,
    each file's robots and time step from the configuration unless given; ``physics`` is the
    profile, physics step (ms), friction, self-collision, and the Webots world and its robot
    node (:func:`_in_world`), ``sampling`` the perturbations, the samples, the seed,
    ``--robustness`` and ``--strict`` (each run's members follow the runs:
    :func:`motiontool.cli.robustness.with_robustness`), ``sidecar`` the expectations, the start,
    whether each motion's sidecar is read, --start-pose (:func:`_chain_options`) and --after. A
    bad option, robot, expectation, sidecar, world or physics step: exit 2 before anything runs."""
    from motiontool.sim.batch import check_robots, parse_perturbation, plan_batch
    from motiontool.sim.physics import physics_run_options

    perturb, samples, seed, robustness, strict = sampling
    expect, start, read_sidecar, start_pose, after = sidecar
    perturbations = [parse_perturbation(p) for p in perturb]
    profile, physics_step, friction, self_collision, world, robot_node = physics
    options = {
        "timestep_ms": timestep,
        **physics_run_options(profile.value, physics_step, friction, self_collision),
        **_chain_options(start_pose),
    }
    settings = {f: resolver.for_file(f) for f in files}
    robots = {f: robot or [settings[f].robot_for(f)] for f in files}
    check_robots([r for rs in robots.values() for r in rs])  # an unknown robot: exit 2 now
    specs = plan_batch(
        files,
        robots,
        options=options,
        timesteps={f: timestep or settings[f].timestep for f in files},
        expect=expect,
        start=start,
        sidecar=read_sidecar,
        roots=roots,
        rrd_dir=rrd_dir,
        perturbations=perturbations,
        samples=samples,
        seed=seed,
        after=after,
    )
    _check_physics(specs, profile, physics_step, friction)
    by_path = {str(f): s for f, s in settings.items()}
    in_world = _in_world(specs, world, robot_node, by_path, timestep_given=timestep is not None)
    perturbed = bool(perturb) or samples > 1
    return with_robustness(in_world, robustness, seed=seed, perturbed=perturbed, strict=strict)


def _chain_options(start_pose: str | None) -> dict[str, object]:
    """The options --start-pose gives every run (its pose's joints, read now: in the cache
    key); none without it. A bad --start-pose: exit 2 before anything runs."""
    return {} if start_pose is None else start_pose_options(start_pose)


def _in_world(
    specs: list[RunSpec],
    world: Path | None,
    robot_node: str | None,
    settings: dict[str, Settings],
    *,
    timestep_given: bool,
) -> list[RunSpec]:
    """``specs`` with their world's options (in their cache key): --world, else the sidecar's
    world, else the configuration's (``settings``: each file's, by its path), and its
    basicTimeStep as the control step unless -t gave one (``timestep_given``: the
    configuration's stands for the robot's usual world); a world without a robot node for a
    run's robot: exit 2 before anything runs."""
    from dataclasses import replace

    from motiontool.kinematics.robots import AUTO
    from motiontool.sim.world_run import world_run_options

    world_run_options(world, robot_node, ())  # --robot-node without --world: exit 2
    found: dict[tuple[str, str | None, str], dict[str, object]] = {}
    out = []
    for spec in specs:
        options = dict(spec.options)
        in_sidecar = options.get("world"), options.get("robot_node")
        path, node = chosen_world((world, robot_node), in_sidecar, settings[spec.path])
        if path is None or spec.robot == AUTO:
            out.append(spec)
            continue
        if not timestep_given:
            options["timestep_ms"] = None
        key = (str(path), node, spec.robot)
        if key not in found:
            found[key] = world_run_options(Path(path), node, [spec.robot])
        out.append(replace(spec, options=tuple(sorted({**options, **found[key]}.items()))))
    return out


def _check_physics(
    specs: list[RunSpec],
    profile: Profile,
    physics_step: float | None,
    friction: float | None,
) -> None:
    """A physics step that does not divide a robot's control step: exit 2 before anything runs."""
    from motiontool.kinematics.robots import AUTO, load_robot
    from motiontool.sim.physics import resolve_physics

    steps = {(s.robot, dict(s.options).get("timestep_ms")) for s in specs if s.robot != AUTO}
    for name, timestep in sorted(steps, key=str):
        resolve_physics(
            timestep or load_robot(name).default_timestep_ms,
            profile=profile.value,
            physics_step_ms=physics_step,
            friction=friction,
        )


def _run_and_report(
    specs: list[RunSpec],
    outputs: dict[str, Path | None],
    *,
    profile: Profile,
    execution: tuple[str, int | None, float | None, tuple[str | None, dict[str, object] | None]],
    cache: tuple[Path | None, bool, float],
    robustness: tuple[int | None, int, bool],
) -> None:
    """The recordings' folder made (:func:`_make_recordings_folder`), the batch run
    (:func:`~motiontool.cli.batch_progress.run_with_progress`; ``execution``: the executor,
    jobs (None: its default), timeout in s, and the Ray address and runtime environment), each
    run judged over its members
    (``robustness``: --robustness, --seed, --strict;
    :func:`motiontool.cli.robustness.robust_batch`), then its reports written
    (:func:`_write_reports`; the runs' reports wait in a temporary folder until then, not in
    memory); exit 1 if a run is not clean."""
    executor, jobs, timeout, ray = execution
    members, seed, strict = robustness
    _make_recordings_folder(specs, outputs)
    with temporary_folder("motiontool-batch-") as spool:
        batch = run_with_progress(
            specs,
            executor=executor,
            jobs=jobs,
            timeout=timeout,
            cache=cache,
            ray=ray,
            spool_dir=Path(spool),
        )
        batch = robust_batch(batch, members, seed=seed, strict=strict)
        _write_reports(batch, profile, outputs)
    if batch.failures:
        raise typer.Exit(exit_codes.FINDINGS)


def _write_reports(batch: BatchResult, profile: Profile, outputs: dict[str, Path | None]) -> None:
    """The summary on stdout, then the reports asked for (``outputs``: option -> path, None
    where not asked for), each said in one line on stderr."""
    from motiontool.cli.batch_reports import (
        render_json,
        render_markdown,
        render_summary,
        write_junit,
    )

    json_out, markdown = outputs["--json"], outputs["--markdown"]
    junit, rrd_dir = outputs["--junit"], outputs["--rrd-dir"]
    if profile is Profile.webots:
        from motiontool.sim.physics import WEBOTS_PROFILE_NOTE

        typer.echo(f"note: {WEBOTS_PROFILE_NOTE}")
    typer.echo(render_summary(batch), nl=False)
    if json_out is not None:
        emit_pieces(render_json(batch), json_out)
    if markdown is not None:
        emit(render_markdown(batch), markdown)
    if junit is not None:
        write_junit(batch, junit)
    runs = plural(len(batch.runs), "run")
    say_wrote(json_out, f"batch report, JSON, {runs}")
    say_wrote(markdown, f"Markdown summary, {runs}")
    say_wrote(junit, f"JUnit XML, {runs}")
    say_wrote(rrd_dir, f"a folder of Rerun recordings, one per run: {runs}")
