"""``motiontool play``: play motions headlessly in MuJoCo, as Webots would, and report the run."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from motiontool.cli.chain_options import (
    ChainOption,
    LoopOption,
    StartPoseOption,
    chain_options,
)
from motiontool.cli.config import ConfigOption, IsolatedOption, Resolver, Settings
from motiontool.cli.jsontext import dumps
from motiontool.cli.live import (
    ConnectOption,
    FastOption,
    HeadlessOption,
    SpeedOption,
    live_view,
    stopped,
)
from motiontool.cli.options import Timestep, finite, robot_option
from motiontool.cli.output import (
    emit,
    emit_stderr,
    refuse_overwrite,
    refuse_shared_outputs,
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
from motiontool.cli.play_bag import BagOption, BagStartOption, bag_target, check_bag, say_bag
from motiontool.cli.play_text import render_text
from motiontool.cli.progress import progress
from motiontool.cli.robustness import (
    ExecutorOption,
    JobsOption,
    NoCacheOption,
    RobustnessOption,
    StrictOption,
    check_robustness,
    robust_json,
    robustness_of,
    strict_exit,
)
from motiontool.cli.run_options import NO_SIDECAR, Start, expect_option, start_option
from motiontool.cli.text import file_name, plural, shown
from motiontool.errors import MotionToolError
from motiontool.extras import require
from motiontool.motionfmt.fileio import is_stdout
from motiontool.sim.live import LiveView, ViewerClosed

if TYPE_CHECKING:
    from motiontool.sim.play import PlayOptions
    from motiontool.sim.robustness import Robustness
    from motiontool.sim.session import PlayPlan, PlayResult

__all__ = ["play_command"]


_Files = Annotated[
    list[Path],
    typer.Argument(help="Motion files, played one after another ('-': stdin).", show_default=False),
]
_Json = Annotated[
    Path | None,
    typer.Option("--json", help="Write the full report as JSON (schema motiontool.play)."),
]
_Rrd = Annotated[
    Path | None, typer.Option("--rrd", help="Write a Rerun recording of the run (.rrd).")
]
_Reverse = Annotated[bool, typer.Option("--reverse", help="Play each motion backwards.")]
_Robot = Annotated[
    str | None,
    robot_option(
        "Robot to play on (default: the configuration's robot for the first file, else "
        "auto: of the joints of all the files)"
    ),
]
_Start = Annotated[Start | None, start_option("the sidecar's start")]
_Expect = Annotated[
    list[str] | None,
    expect_option("the run", "the motions.toml sidecar's, for a single file"),
]
_Hold = Annotated[
    float,
    typer.Option(
        "--hold",
        min=0.0,
        callback=finite,
        help="Seconds to keep simulating after the last motion.",
    ),
]
_Seed = Annotated[int, typer.Option("--seed", help="Seed of random draws (stamped).")]


def play_command(
    files: _Files,
    headless: HeadlessOption = False,
    connect: ConnectOption = None,
    speed: SpeedOption = None,
    fast: FastOption = False,
    json_path: _Json = None,
    rrd: _Rrd = None,
    bag: BagOption = None,
    bag_start: BagStartOption = None,
    loop: LoopOption = None,
    chain: ChainOption = False,
    start_pose: StartPoseOption = None,
    reverse: _Reverse = False,
    timestep: Timestep = None,
    robot: _Robot = None,
    start: _Start = None,
    expect: _Expect = None,
    no_sidecar: Annotated[bool, NO_SIDECAR] = False,
    hold: _Hold = 1.0,
    seed: _Seed = 0,
    physics_step: PhysicsStepOption = None,
    friction: FrictionOption = None,
    profile: ProfileOption = Profile.default,
    world: WorldOption = None,
    robot_node: RobotNodeOption = None,
    self_collision: SelfCollisionOption = None,
    robustness: RobustnessOption = None,
    strict: StrictOption = False,
    jobs: JobsOption = 2,
    executor: ExecutorOption = "local",
    no_cache: NoCacheOption = False,
    config: ConfigOption = None,
    isolated: IsolatedOption = False,
) -> None:
    """Play motion files in MuJoCo as a Webots controller would, live in a Rerun viewer or
    headless (--headless), and report the run.

    Live: a viewer is spawned (or --connect URL), paced at real time (--speed X, --fast).
    Motors follow Webots' law: the target clipped to the motor limits, a P controller (P = 10)
    makes a velocity command capped at maxVelocity, a velocity servo limited to maxTorque
    realises it. Exit 0 when the run is clean, 1 when the robot fell, collided, MuJoCo warned
    or an expectation (--expect, motions.toml) is not met, 2 on error. --json and --rrd are
    written in every case. --robustness N: each verdict holds, is fragile or fails.
    """
    live = live_view(headless, connect, speed, fast)
    inputs = _check_outputs(files, world, robot_node, json=json_path, rrd=rrd)
    check_robustness(robustness, files, strict, executor)
    check_bag(bag, inputs, {"--json": json_path, "--rrd": rrd})
    planned, robot, options = _plan(
        files,
        robot,
        config=(config, isolated),
        sidecar=(expect or [], start, not no_sidecar),
        world=(world, robot_node),
        chain=(loop, start_pose, chain),
        playback=(timestep, reverse, hold, seed),
        physics=(profile, physics_step, friction, self_collision),
    )
    result = _run(planned, robot, options, rrd=rrd, bag=(bag, bag_start), live=live)
    ensemble = robustness_of(result, planned, options, n=robustness, run=(executor, jobs, no_cache))
    _render(result, json_path, rrd, (ensemble, strict))


def _plan(
    files: list[Path],
    robot: str | None,
    *,
    config: tuple[Path | None, bool],
    sidecar: tuple[list[str], Start | None, bool],
    world: tuple[Path | None, str | None],
    chain: tuple[list[str] | None, str | None, bool],
    playback: tuple[int | None, bool, float, int],
    physics: tuple[Profile, float | None, float | None, bool | None],
) -> tuple[PlayPlan, str, PlayOptions]:
    """The run the options describe: what to play (:func:`motiontool.sim.session.plan_play`;
    ``sidecar``: the expectations, the start and whether the sidecar is read; ``world``: the
    Webots world and its robot node), on which robot (``robot``, else the configuration's for
    the first file; ``config``: --config and --isolated) and how
    (:class:`~motiontool.sim.play.PlayOptions`; ``chain``: --loop, --start-pose and --chain;
    ``playback``: the control step in ms (else the configuration's), --reverse, the hold in s
    and the seed; ``physics``: the profile, physics step in ms, friction and self-collision).
    A bad option, sidecar, world or configuration: exit 2 before anything runs."""
    from motiontool.sim.play import PlayOptions
    from motiontool.sim.session import plan_play

    expect, start, read_sidecar = sidecar
    world_path, robot_node = world
    planned = plan_play(
        files,
        expect=expect,
        start=start,
        sidecar=read_sidecar,
        world=world_path,
        robot_node=robot_node,
    )
    settings = Resolver(config=config[0], isolated=config[1]).for_file(files[0])
    in_sidecar = (planned.motion.world, planned.motion.robot_node)
    world_path, robot_node = chosen_world((world_path, robot_node), in_sidecar, settings)
    planned = replace(planned, world=world_path, robot_node=robot_node)  # or the configuration's
    loop, start_pose, chained = chain
    timestep, reverse, hold, seed = playback
    profile, physics_step, friction, self_collision = physics
    options = PlayOptions(
        timestep_ms=timestep if timestep is not None else _config_step(settings, planned),
        **chain_options(loop, start_pose, planned, chain=chained),
        reverse=reverse,
        hold_s=hold,
        seed=seed,
        physics_step_ms=physics_step,
        floor_friction=friction,
        profile=profile.value,
        self_collision=self_collision,
    )
    robot = robot if robot is not None else settings.robot_for(files[0])
    return planned, robot, options


def _config_step(settings: Settings, planned: PlayPlan) -> int | None:
    """The configuration's control step, ms; None in a world (--world, the sidecar's, the
    configuration's), whose basicTimeStep wins (the configuration's step stands for the robot's
    usual world; -t wins over both)."""
    return None if planned.world is not None else settings.timestep


def _run(
    planned: PlayPlan,
    robot: str,
    options: PlayOptions,
    *,
    rrd: Path | None,
    bag: tuple[Path | None, int | None],
    live: LiveView | None,
) -> PlayResult:
    """The run of ``planned``, its progress shown as it goes (``bag``: --bag and --bag-start,
    said after the run; ``live``: shown live, a viewer that closes ends the command)."""
    with progress("play") as step:
        names = ", ".join(file_name(f) for f in planned.files)
        cycles = sum(options.chain_loops) or options.loops * len(planned.files)
        label = f"{names}, {plural(cycles, 'cycle')} in MuJoCo"
        step(label)

        def simulated(done_s: float, total_s: float) -> None:
            step(f"{label}: {done_s:,.0f} of {total_s:,.0f} s simulated")

        try:
            result = planned.run(
                robot=robot,
                options=options,
                rrd=rrd,
                bag=bag_target(*bag),
                progress=simulated,
                live=live,
            )
        except ViewerClosed as exc:
            stopped(exc)
    say_bag(result, bag[0])
    return result


def _check_outputs(
    files: list[Path],
    world: Path | None,
    robot_node: str | None,
    *,
    json: Path | None,
    rrd: Path | None,
) -> list[Path]:
    """--robot-node only with --world, no output over an input (the motions,
    the world) or over another, the extras installed: exit 2 before anything runs. Returns the
    input files."""
    if robot_node is not None and world is None:
        raise MotionToolError("--robot-node names a robot node of --world: pass --world FILE.wbt")
    json_path = json
    files = files if world is None else [*files, world]
    refuse_overwrite(json_path, files, "--json")
    refuse_overwrite(rrd, files, "--rrd")
    refuse_shared_outputs({"--json": json_path, "--rrd": rrd})
    require("mujoco", "sim", "motiontool play")
    if rrd is not None:
        require("rerun", "rerun", "motiontool play --rrd")
    return files


def _render(
    result: PlayResult,
    json_path: Path | None,
    rrd: Path | None,
    robust: tuple[Robustness | None, bool] = (None, False),
) -> None:
    """The JSON report, the warnings and the text report (on stderr where --json or --rrd is
    standard output), a line for each file written; exit with the run's code (``robust``: the
    run's robustness and --strict: 1 on a fragile verdict), or raise the error that kept it
    from starting."""
    report = result.report
    if report is None:
        assert result.error is not None, "a result without a report has an error"
        if json_path is not None:
            emit(dumps(result.to_json(), indent=1), json_path)
        say_wrote(json_path, "play report, JSON: the run could not start")
        say_wrote(rrd, "Rerun recording: the run could not start")
        raise result.error
    for name in report.ignored_joints:
        typer.echo(
            shown(f"motiontool: warning: joint '{name}' is not a motor of {report.robot}: ignored"),
            err=True,
        )
    code = strict_exit(report.exit_code, *robust)
    if json_path is not None:
        emit(dumps(robust_json(result.to_json(), robust[0], code), indent=1), json_path)
    # Names keep the file's bytes (no UnicodeEncodeError); where --json or --rrd is '-' (stdout),
    # the text report goes to stderr.
    text = render_text(report) + ("" if robust[0] is None else robust[0].text())
    if is_stdout(json_path) or is_stdout(rrd):
        emit_stderr(text)
    else:
        emit(text, None)
    say_wrote(json_path, f"play report, JSON, {report.simulated_s:.2f} s simulated")
    say_wrote(rrd, f"Rerun recording, {report.simulated_s:.2f} s simulated")
    raise typer.Exit(code)
