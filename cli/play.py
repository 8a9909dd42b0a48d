"""``motiontool play``: play motions headlessly in MuJoCo, as Webots would, and report the run."""

from __future__ import annotations

import math
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
from motiontool.motionfmt.units import MM_PER_M

if TYPE_CHECKING:
    from motiontool.sim.bag import BagTarget
    from motiontool.sim.play import PlayOptions
    from motiontool.sim.report import ContactSummary, PlayReport
    from motiontool.sim.robustness import Robustness
    from motiontool.sim.session import PlayPlan, PlayResult

__all__ = ["play_command"]


def _num(value: float | None, fmt: str, unit: str) -> str:
    return "n/a" if value is None or not math.isfinite(value) else f"{value:{fmt}} {unit}"


def _contacts(title: str, rows: list[ContactSummary], limit: int = 8) -> list[str]:
    if not rows:
        return [f"{title}: none"]
    lines = [f"{title}: {len(rows)}"]
    for c in rows[:limit]:
        lines.append(
            f"  {c.body_a} / {c.body_b}: from {c.first_s:.2f} s, {c.duration_s:.2f} s in all, "
            f"max depth {c.max_depth_m * MM_PER_M:.1f} mm"
        )
    if len(rows) > limit:
        lines.append(f"  ... and {len(rows) - limit} more (see --json)")
    return lines


def _end_effector(report: PlayReport, limit: int = 32) -> list[str]:
    """An arm's tool: the largest deviation, then a table of keyframes (time, position error,
    lag); past ``limit`` keyframes, the ``limit // 2`` worst, in the order first played."""
    ee = report.end_effector
    if ee is None:
        return []
    lines = [
        f"end effector {ee.frame}: largest deviation from the commanded path "
        f"{ee.max_deviation_mm:.1f} mm at {ee.max_deviation_at_s:.2f} s; lag: time to come "
        f"within {ee.reach_tolerance_mm:g} mm of a keyframe (- : not before the next one)"
    ]
    rows = list(enumerate(ee.keyframes))
    if len(rows) > limit:
        worst = sorted(rows, key=lambda r: -r[1].position_error_mm)[: limit // 2]
        rows = sorted(worst, key=lambda r: r[0])
    if not rows:
        return lines
    folded = any(k.visits > 1 for k in ee.keyframes)
    if folded:
        lines[0] += "; a keyframe reached several times: its worst visit, its longest lag"
    wn = max(8, *(len(k.name) for _i, k in rows))
    visits = f" {'visits':>6}" if folded else ""
    lines.append(f"  {'keyframe':<{wn}} {'time':>9} {'error':>10} {'lag':>8}{visits}")
    for _i, k in rows:
        lag = "-" if k.lag_ms is None else f"{k.lag_ms:.0f} ms"
        row = f"  {k.name:<{wn}} {k.time_s:>7.3f} s {k.position_error_mm:>7.1f} mm {lag:>8}"
        lines.append(row + (f" {k.visits:>6}" if folded else ""))
    if len(rows) < len(ee.keyframes):
        lines.append(
            f"  ... {len(ee.keyframes) - len(rows)} more keyframes with smaller errors (see --json)"
        )
    return lines


def _joint_table(report: PlayReport) -> list[str]:
    """One row per commanded joint: tracking errors and time at the caps; none without one."""
    rows = [j for j in report.joints if j.commanded]
    if not rows:
        return []
    wj = max(5, *(len(j.name) for j in rows))
    wl = max(4, *(len(j.limb) for j in rows))
    lines = [
        f"{'joint':<{wj}} {'limb':<{wl}} {'rms error':>11} {'max error':>11} "
        f"{'at vel cap':>10} {'at torque cap':>13} {'clipped':>8}"
    ]
    for j in rows:
        lines.append(
            f"{j.name:<{wj}} {j.limb:<{wl}} {j.rms_error:>7.4f} {j.unit:<3} "
            f"{j.max_error:>7.4f} {j.unit:<3} {j.velocity_cap_s:>8.2f} s "
            f"{j.torque_cap_s:>11.2f} s {j.target_clipped_s:>6.2f} s"
        )
    return lines


def _world(report: PlayReport) -> list[str]:
    """What ``--world`` applied and what it did not, one line each."""
    world = report.world
    if world is None:
        return []
    node = world["robot_node"]
    lines = [
        f"world: {world['path']}, robot node {node['name']!r}"
        + (f" (DEF {node['def']})" if node["def"] else "")
    ]
    for entry in world["applied"]:
        unit = f" {entry['unit']}" if entry["unit"] else ""
        lines.append(f"  applied: {entry['field']} {_value(entry['value'])}{unit}: "
                     f"{entry['applied_as']}")  # fmt: skip
    for entry in world["not_applied"]:
        unit = f" {entry['unit']}" if entry["unit"] else ""
        lines.append(f"  not applied: {entry['field']} {_value(entry['value'])}{unit}: "
                     f"{entry['reason']}")  # fmt: skip
    lines += [f"  skipped: {line}" for line in world["skipped_nodes"]]
    return lines


def _self_collision(report: PlayReport) -> list[str]:
    """Whether the robot's parts collided with each other, why, how many pairs touched (not
    said of a run as the robot's model has it, without self-collision physics)."""
    doc = report.self_collision
    if doc is None or (doc["source"] == "robot model" and not doc["physics"]):
        return []
    why = doc["why"]
    if doc["source"] == "option":  # the library's words; the flag is the command line's
        why = "--self-collision" if doc["physics"] else "--no-self-collision"
    if not doc["physics"]:
        return [f"self-collision physics: off ({why})"]
    return [
        f"self-collision physics: on ({why}); {doc['touching_pairs']} pairs of bodies "
        f"touched, {doc['touching_s']:.2f} s in all"
    ]


def _chain(report: PlayReport) -> list[str]:
    """A chain's elements, one line each: cycles, time in the run, what the base did."""
    if not report.options.get("chain"):
        return []
    lines = [f"chain: {plural(len(report.files), 'element')}"]
    for k, f in enumerate(report.files, 1):
        cycles = f" x{f.loops}" if f.loops > 1 else ""
        line = (
            f"  {k}. {file_name(f.path)}{cycles}: {f.start_s:.2f}-{f.start_s + f.duration_s:.2f} s"
        )
        if f.dx_m is not None and f.dy_m is not None and f.yaw_change_deg is not None:
            line += f", dx {f.dx_m:+.3f} m, dy {f.dy_m:+.3f} m, turn {f.yaw_change_deg:+.1f} deg"
        lines.append(line)
    return lines


def _value(value: object) -> str:
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if isinstance(value, list):
        return " ".join(f"{v:g}" for v in value)
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


def render_text(report: PlayReport) -> str:
    """The summary for people: the outcome, the robot, the feet, contacts, then one row per
    commanded joint."""
    stamps_ = report.stamps
    names = " + ".join(file_name(f.path) for f in report.files)
    lines = [
        f"{names} on {report.robot}: {report.simulated_s:.2f} s simulated "
        f"({report.control_steps} control steps of {stamps_.get('control_step_ms')} ms, "
        f"physics step {stamps_.get('physics_step_ms'):g} ms"
        + (f", floor friction {report.physics['friction']:g}" if report.physics else "")
        + ")",
        *([f"note: {report.physics['profile_note']}"] if "profile_note" in report.physics else []),
        *_world(report),
        *_self_collision(report),
        *_chain(report),
        "result: " + ("clean" if report.clean else "; ".join(report.problems)),
    ]
    if report.expectations:
        lines.append(f"expectations: {sum(r.passed for r in report.expectations)} of "
                     f"{len(report.expectations)} met")  # fmt: skip
        lines += [f"  {r.summary()}" for r in report.expectations]
    base = report.base
    if base is not None:
        lines.append(
            f"base: dx {base.dx_m:+.3f} m, dy {base.dy_m:+.3f} m, "
            f"yaw {_num(base.yaw_change_deg, '+.1f', 'deg')}, "
            f"max tilt {base.max_tilt_deg:.1f} deg, final tilt {base.final_tilt_deg:.1f} deg, "
            f"height {base.final_height_m:.3f} m (min {base.min_height_m:.3f} m)"
            + (f", fell at {base.fell_at_s:.2f} s" if base.fell_at_s is not None else "")
        )
    for foot in report.feet:
        lines.append(
            f"foot {foot.name}: on the floor {foot.contact_s:.2f} s, "
            f"slip {foot.slip_m * MM_PER_M:.1f} mm, "
            f"moved {foot.max_displacement_m * MM_PER_M:.1f} mm at most, "
            f"{foot.final_displacement_m * MM_PER_M:.1f} mm at the end"
        )
    lines += _end_effector(report)
    lines += _contacts("self-collisions", report.self_collisions)
    lines += _contacts("contacts with anything but the floor", report.scene_contacts)
    if report.ground_contacts:
        lines += _contacts("other body parts on the floor", report.ground_contacts, limit=4)
    raised = {k: v for k, v in report.warnings.items() if v}
    lines.append(
        "MuJoCo warnings: " + (", ".join(f"{k} x{v}" for k, v in raised.items()) or "none")
    )
    if report.ignored_joints:
        lines.append("ignored (not motors of the robot): " + ", ".join(report.ignored_joints))
    lines += _joint_table(report)
    if report.error:
        lines.append(f"error: {report.error}")
    return "\n".join(lines) + "\n"


_Files = Annotated[
    list[Path],
    typer.Argument(help="Motion files, played one after another ('-': stdin).", show_default=False),
]
_Headless = Annotated[
    bool, typer.Option("--headless", help="Run without a viewer (the only mode there is).")
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
    headless: _Headless = False,
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
    """Play motion files headlessly in MuJoCo as a Webots controller would, and report the run.

    Motors follow Webots' law: the target is clipped to the motor limits, a P controller
    (P = 10) makes a velocity command capped at maxVelocity, a velocity servo limited to
    maxTorque realises it. Exit code 0 when the run is clean, 1 when the robot fell, collided,
    MuJoCo raised a warning or an expectation (--expect, motions.toml) is not met, 2 on error.
    --json and --rrd are written in every case. With --robustness N, each verdict holds,
    is fragile (a warning; exit 1 with --strict) or fails.
    """
    inputs = _check_outputs(files, world, robot_node, headless=headless, json=json_path, rrd=rrd)
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
    result = _run(planned, robot, options, rrd=rrd, bag=bag_target(bag, bag_start))
    say_bag(result, bag)
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
    planned: PlayPlan, robot: str, options: PlayOptions, *, rrd: Path | None, bag: BagTarget | None
) -> PlayResult:
    """The run of ``planned``, its progress shown as it goes."""
    with progress("play") as step:
        names = ", ".join(file_name(f) for f in planned.files)
        cycles = sum(options.chain_loops) or options.loops * len(planned.files)
        label = f"{names}, {plural(cycles, 'cycle')} in MuJoCo"
        step(label)

        def simulated(done_s: float, total_s: float) -> None:
            step(f"{label}: {done_s:,.0f} of {total_s:,.0f} s simulated")

        return planned.run(robot=robot, options=options, rrd=rrd, bag=bag, progress=simulated)


def _check_outputs(
    files: list[Path],
    world: Path | None,
    robot_node: str | None,
    *,
    headless: bool,
    json: Path | None,
    rrd: Path | None,
) -> list[Path]:
    """Only headless, --robot-node only with --world, no output over an input (the motions,
    the world) or over another, the extras installed: exit 2 before anything runs. Returns the
    input files."""
    if robot_node is not None and world is None:
        raise MotionToolError("--robot-node names a robot node of --world: pass --world FILE.wbt")
    json_path = json
    files = files if world is None else [*files, world]
    if not headless:
        raise MotionToolError(
            "only headless playback exists (there is no viewer); pass --headless, and --rrd "
            "to look at the run in Rerun"
        )
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
