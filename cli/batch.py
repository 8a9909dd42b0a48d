"""``motiontool batch``: play many files x robots x perturbations, locally or on a Ray cluster."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from motiontool.cli.color import rich_no_color
from motiontool.cli.options import Timestep, robot_option
from motiontool.cli.output import emit, refuse_overwrite
from motiontool.cli.physics_options import (
    FrictionOption,
    PhysicsStepOption,
    Profile,
    ProfileOption,
)
from motiontool.cli.play import Start
from motiontool.motionfmt.errors import MotionToolError
from motiontool.motionfmt.extras import require
from motiontool.motionfmt.fileio import collect_motion_files, is_stdin

__all__ = ["batch_command"]


def batch_command(
    paths: Annotated[
        list[Path],
        typer.Argument(
            help="Motion files, or directories searched for *.motion.", show_default=False
        ),
    ],
    robot: Annotated[
        list[str] | None,
        robot_option(
            "Robot to play on, per file (default: auto)",
            more="Repeat to run every file on several robots.",
        ),
    ] = None,
    jobs: Annotated[int, typer.Option("--jobs", "-j", min=1, help="Runs in parallel.")] = 2,
    executor: Annotated[
        str, typer.Option("--executor", help="local (a process pool) or ray.")
    ] = "local",
    ray_address: Annotated[
        str | None,
        typer.Option(
            "--ray-address", help="Ray cluster to use (auto: the running one); default: start one."
        ),
    ] = None,
    timeout: Annotated[
        float | None, typer.Option("--timeout", min=0.1, help="Wall-clock limit of one run, in s.")
    ] = None,
    perturb: Annotated[
        list[str] | None,
        typer.Option(
            "--perturb",
            help="NAME=LOW:HIGH, uniform draws; NAME: friction, mass, motor-strength,"
            " start-yaw (deg), start-noise (rad), speed. Repeatable.",
        ),
    ] = None,
    samples: Annotated[
        int, typer.Option("--samples", min=1, help="Perturbation samples per file and robot.")
    ] = 1,
    seed: Annotated[int, typer.Option("--seed", help="Seed of the perturbation draws.")] = 0,
    timestep: Timestep = None,
    physics_step: PhysicsStepOption = None,
    friction: FrictionOption = None,
    profile: ProfileOption = Profile.default,
    junit: Annotated[Path | None, typer.Option("--junit", help="Write JUnit XML here.")] = None,
    json_out: Annotated[
        Path | None, typer.Option("--json", help="Write every run's report (JSON) here.")
    ] = None,
    markdown: Annotated[
        Path | None, typer.Option("--markdown", help="Write a Markdown summary here.")
    ] = None,
    rrd_dir: Annotated[
        Path | None,
        typer.Option("--rrd-dir", help="Keep a Rerun recording of every run in this folder."),
    ] = None,
    start: Annotated[
        Start | None,
        typer.Option(
            "--start",
            help="Start standing, lying face down or lying face up (default: each motion's"
            " sidecar start, else standing).",
            show_default=False,
        ),
    ] = None,
    expect: Annotated[
        list[str] | None,
        typer.Option(
            "--expect",
            help="What every run must do, e.g. 'dx>=0.3', 'yaw=60±10', upright (repeatable;"
            " in addition to each motion's motions.toml sidecar).",
            show_default=False,
        ),
    ] = None,
    no_sidecar: Annotated[
        bool, typer.Option("--no-sidecar", help="Ignore motions.toml sidecars.")
    ] = False,
    no_cache: Annotated[bool, typer.Option("--no-cache", help="Run everything again.")] = False,
    cache_dir: Annotated[
        Path | None,
        typer.Option("--cache-dir", help="Result cache (default ~/.cache/motiontool/batch)."),
    ] = None,
) -> None:
    """Play every file headless on every robot and perturbation sample; exit 1 if any run is not
    clean (fell, collided, simulator warning, an expectation not met, error, crash or
    timeout)."""
    from motiontool.cli.batch_reports import (
        render_json,
        render_markdown,
        render_summary,
        write_junit,
    )
    from motiontool.kinematics.robots import AUTO, load_robot
    from motiontool.sim.batch import (
        check_robots,
        default_cache_dir,
        parse_perturbation,
        plan,
        recording_stems,
        run_batch,
    )
    from motiontool.sim.expect import parse_expectations
    from motiontool.sim.physics import physics_run_options, resolve_physics
    from motiontool.sim.runs import run_spec
    from motiontool.sim.sidecar import Sidecar, expectations_for

    if executor not in ("local", "ray"):
        raise typer.BadParameter(f"{executor!r}: choose local or ray", param_hint="--executor")
    if any(is_stdin(p) for p in paths):
        raise MotionToolError("batch reads motion files, not standard input ('-'): name files")
    files = collect_motion_files(paths)
    for option, out in [
        ("--json", json_out),
        ("--markdown", markdown),
        ("--junit", junit),
        ("--rrd-dir", rrd_dir),
    ]:
        refuse_overwrite(out, files, option)
    require("mujoco", "sim", "motiontool batch")
    if junit is not None:
        require("junitparser", "sim", "motiontool batch --junit")
    if rrd_dir is not None:
        require("rerun", "rerun", "motiontool batch --rrd-dir")
    if executor == "ray":
        require("ray", "ray", "motiontool batch --executor ray")
    perturbations = [parse_perturbation(p) for p in perturb or []]
    physics_options = physics_run_options(profile.value, physics_step, friction)
    robots = robot or [AUTO]
    check_robots(robots)  # an unknown robot: exit 2 before anything runs
    rrd_names = recording_stems(files)
    parse_expectations(expect or [])  # a bad --expect: exit 2 before anything runs
    roots = [p for p in paths if p.is_dir()]
    sidecars: dict[Path, Sidecar] = {}
    specs = []
    for f in files:
        expected, sidecar_start = expectations_for(
            f, expect or [], sidecar=not no_sidecar, roots=roots, cache=sidecars
        )
        start_state = start.value if start is not None else sidecar_start
        options: dict[str, object] = {"timestep_ms": timestep, **physics_options}
        if start_state not in (None, "standing"):
            options["start"] = start_state
        if rrd_dir is not None:
            rrd_dir.mkdir(parents=True, exist_ok=True)
            options["rrd_dir"] = str(rrd_dir)
            options["rrd_name"] = rrd_names[str(f)]
        specs += plan(
            [f],
            robots,
            perturbations=perturbations,
            samples=samples,
            seed=seed,
            options=options,
            expect=expected,
        )

    for name in dict.fromkeys(s.robot for s in specs if s.robot != AUTO):
        # a physics step that does not divide a robot's control step: exit 2 before anything runs
        resolve_physics(
            timestep or load_robot(name).default_timestep_ms,
            profile=profile.value,
            physics_step_ms=physics_step,
            friction=friction,
        )

    def model_hash(name: str) -> str:
        return "" if name == AUTO else load_robot(name).model_hash

    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeRemainingColumn,
    )

    # Colour: rich follows NO_COLOR / FORCE_COLOR itself; --no-color is the root option.
    console = Console(stderr=True, no_color=rich_no_color())
    failures = 0
    with Progress(
        TextColumn("[progress.description]{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("{task.fields[rate]:.2f} runs/s, {task.fields[failures]} not clean"),
        TimeRemainingColumn(),
        console=console,
        transient=True,
        disable=not console.is_terminal,
    ) as bar:
        task = bar.add_task("batch", total=len(specs), rate=0.0, failures=0)

        def progress(result: object, done: int, total: int) -> None:
            nonlocal failures
            failures += not getattr(result, "ok", False)
            elapsed = bar.tasks[0].elapsed or 1e-9
            bar.update(task, completed=done, rate=done / elapsed, failures=failures)

        batch = run_batch(
            specs,
            run_spec,
            model_hash=model_hash,
            executor=executor,
            jobs=jobs,
            timeout_s=timeout,
            cache_dir=None if no_cache else (cache_dir or default_cache_dir()),
            ray_address=ray_address,
            progress=progress,
        )
    if profile is Profile.webots:
        from motiontool.sim.physics import WEBOTS_PROFILE_NOTE

        typer.echo(f"note: {WEBOTS_PROFILE_NOTE}")
    typer.echo(render_summary(batch), nl=False)
    if json_out is not None:
        emit(render_json(batch), json_out)
    if markdown is not None:
        emit(render_markdown(batch), markdown)
    if junit is not None:
        write_junit(batch, junit)
    if batch.failures:
        raise typer.Exit(1)
