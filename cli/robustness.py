"""``play --robustness N`` and ``batch --robustness N``: each run's verdicts replayed over N
perturbed members (:mod:`motiontool.sim.robustness`) on the batch executors, cached as batch
runs are; ``--strict`` fails on a fragile verdict."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from motiontool import exit_codes
from motiontool.cli.options import MAX_COUNT
from motiontool.errors import MotionToolError
from motiontool.motionfmt.fileio import is_stdin
from motiontool.sim.executor import EXECUTORS, REGISTRY
from motiontool.sim.robustness import DEFAULT_MEMBERS, describe

if TYPE_CHECKING:
    from motiontool.sim.batch import RunSpec
    from motiontool.sim.batch_results import BatchResult
    from motiontool.sim.play import PlayOptions
    from motiontool.sim.robustness import Robustness
    from motiontool.sim.session import PlayPlan, PlayResult

__all__ = [
    "ExecutorOption",
    "JobsOption",
    "NoCacheOption",
    "RobustnessOption",
    "StrictOption",
    "check_ensemble",
    "check_robustness",
    "robust_batch",
    "robust_json",
    "robustness_of",
    "strict_exit",
    "with_robustness",
]

RobustnessOption = Annotated[
    int | None,
    typer.Option(
        "--robustness",
        min=1,
        max=MAX_COUNT,
        metavar="N",
        help="Replay every verdict (clean, each expectation) over N perturbed members "
        f"({DEFAULT_MEMBERS} is a good start): {describe()}, drawn from --seed; each verdict "
        "holds, is fragile (k of N disagree: a warning) or fails.",
    ),
]
StrictOption = Annotated[
    bool, typer.Option("--strict", help="A fragile verdict (--robustness) fails the run (exit 1).")
]

JobsOption = Annotated[
    int,
    typer.Option("--jobs", "-j", min=1, max=MAX_COUNT, help="--robustness members in parallel."),
]
ExecutorOption = Annotated[
    str,
    typer.Option(
        "--executor",
        help="Where --robustness members run: "
        + " or ".join(f"{e.name} ({e.summary})" for e in REGISTRY)
        + ".",
    ),
]
NoCacheOption = Annotated[
    bool,
    typer.Option("--no-cache", help="Play every --robustness member again (batch's cache)."),
]


def check_robustness(n: int | None, files: list[Path], strict: bool, executor: str) -> None:
    """``--robustness`` replays motion files (a chain too), not standard input (its members
    read the files again); ``executor`` must exist and ``--strict`` needs ``--robustness``:
    exit 2 before the run."""
    check_ensemble(n, strict, executor)
    if n is not None and any(is_stdin(f) for f in files):
        raise MotionToolError(
            "--robustness replays motion files, not standard input: play the file by its path"
        )


def check_ensemble(n: int | None, strict: bool, executor: str) -> None:
    """What ``play`` and ``expect`` check of ``--robustness``: the executor exists,
    ``--strict`` needs ``--robustness``: exit 2 before the run."""
    if executor not in EXECUTORS:
        raise typer.BadParameter(
            f"{executor!r}: choose {' or '.join(EXECUTORS)}", param_hint="--executor"
        )
    if strict and n is None:
        raise MotionToolError("--strict fails on a fragile verdict: pass --robustness N")


def robustness_of(
    result: PlayResult,
    planned: PlayPlan,
    options: PlayOptions,
    *,
    n: int | None,
    run: tuple[str, int, bool],
) -> Robustness | None:
    """The robustness of ``result``'s run over ``n`` members, each played as the run was
    (``options``, the plan's start and world; a chain's elements, their loops, a start pose) on
    the batch executors (``run``: executor, jobs, --no-cache: else batch's cache), judged as
    the run was; None without ``n`` or when the run could not start."""
    report = result.report
    if report is None or n is None:
        return None
    from motiontool.sim.batch import default_cache_dir, run_batch
    from motiontool.sim.robustness import judge, member_specs
    from motiontool.sim.runs import run_spec

    executor, jobs, no_cache = run
    nominal = _nominal(planned, options, report)
    control_step = int(report.stamps["control_step_ms"])
    specs = member_specs(nominal, n, seed=options.seed, control_step_ms=control_step)
    batch = run_batch(
        specs,
        run_spec,
        model_hash=lambda _robot: str(report.stamps.get("model_sha256") or ""),
        executor=executor,
        jobs=jobs,
        cache_dir=None if no_cache else default_cache_dir(),
    )
    return judge(report, batch.runs, seed=options.seed)


def _nominal(planned: PlayPlan, options: PlayOptions, report: Any) -> RunSpec:
    """The run as a batch run: its last motion, played after the others (a chain: ``--chain``,
    a sidecar's ``after``, several files), each file's bytes hashed into its cache key."""
    import hashlib

    from motiontool.motionfmt.fileio import read_file
    from motiontool.sim.batch import RunSpec

    *before, last = planned.files
    sha = [hashlib.sha256(read_file(p)).hexdigest() for p in planned.files]
    return RunSpec(
        str(last),
        sha[-1],
        report.robot,
        options=tuple(sorted(_member_options(planned, options, report.robot, report).items())),
        expect=planned.motion.expect,
        chain=tuple(str(p) for p in before),
        chain_sha256=tuple(sha[:-1]),
    )


def _member_options(
    planned: PlayPlan, options: PlayOptions, robot: str, report: Any
) -> dict[str, Any]:
    """The run's options as a batch run carries them (its cache key): the control step it ran
    at, its start (a lying start, a start pose's joints), physics, world, play and chain
    options."""
    from motiontool.sim.physics import physics_run_options
    from motiontool.sim.world_run import world_run_options

    out: dict[str, Any] = {
        "timestep_ms": int(report.stamps["control_step_ms"]),
        **physics_run_options(
            options.profile, None, options.floor_friction, options.self_collision
        ),
        "loops": options.loops,
        "reverse": options.reverse,
        "hold_s": options.hold_s,
    }
    if options.chain:
        out["chain"] = True
    if options.chain_loops:
        out["chain_loops"] = options.chain_loops
    if planned.start.lying:
        out["start"] = str(planned.start)
    if options.start_pose is not None:
        out["start_pose"] = options.start_pose
        out["start_pose_joints"] = options.start_pose_joints
    world, node = planned.world, planned.robot_node
    if world is None:
        world, node = planned.motion.world, planned.motion.robot_node
    out.update(world_run_options(world, node, [robot]))
    return out


def strict_exit(code: int, robustness: Robustness | None, strict: bool) -> int:
    """The run's exit code: ``code``, or 1 where ``strict`` and a verdict is fragile; a fragile
    verdict is said on stderr as a warning."""
    if robustness is None or not robustness.fragile:
        return code
    more = " (--strict: exit 1)" if strict else ""
    typer.echo(f"motiontool: warning: a verdict is fragile under --robustness{more}", err=True)
    return exit_codes.FINDINGS if strict and code == exit_codes.CLEAN else code


def robust_json(doc: dict[str, Any], robustness: Robustness | None, code: int) -> dict[str, Any]:
    """The play report ``doc`` with its ``robustness`` and the exit code (``--strict``)."""
    if robustness is not None:
        doc.update(robustness=robustness.to_json(), exit_code=code)
    return doc


def with_robustness(
    specs: list[RunSpec], n: int | None, *, seed: int, perturbed: bool, strict: bool
) -> list[RunSpec]:
    """``batch --robustness N``: ``specs``, then each run's N members
    (:func:`motiontool.sim.robustness.with_members`, at its control step: ``-t``, its world's
    basicTimeStep, else its robot's). Not with ``--perturb`` (a run of its own ensemble is
    not a perturbation sample); ``--strict`` needs it: exit 2 before any run."""
    if strict and n is None:
        raise MotionToolError("--strict fails on a fragile verdict: pass --robustness N")
    if n is None:
        return specs
    if perturbed:
        raise MotionToolError(
            "--robustness replays each run over its own perturbed members: not with --perturb "
            "or --samples"
        )
    from motiontool.sim.robustness import with_members

    return with_members(specs, n, seed=seed, control_step_ms=_control_step)


def _control_step(spec: RunSpec) -> int | None:
    """The control step of a batch run, ms (None: a run no robot fits, which fails alone)."""
    from motiontool.kinematics.robots import AUTO, load_robot
    from motiontool.sim.world import read_world

    if spec.robot == AUTO:
        return None
    options = dict(spec.options)
    if options.get("timestep_ms"):
        return int(options["timestep_ms"])
    if options.get("world"):
        world = read_world(Path(options["world"]), options.get("robot_node"), spec.robot)
        return int(world.basic_time_step_ms)
    return load_robot(spec.robot).default_timestep_ms


def robust_batch(batch: BatchResult, n: int | None, *, seed: int, strict: bool) -> BatchResult:
    """The batch's runs (not its members), each with its robustness over its members
    (:func:`motiontool.sim.robustness.regroup`); with ``strict``, a run with a fragile verdict
    is not clean (``failed``, the verdicts its reason), else a warning on stderr says how many
    have one."""
    if n is None:
        return batch
    from dataclasses import replace

    from motiontool.sim.robustness import regroup

    batch = regroup(batch, seed=seed)
    fragile = [r for r in batch.runs if r.robustness is not None and r.robustness.fragile]
    if not fragile:
        return batch
    if not strict:
        typer.echo(
            f"motiontool: warning: {len(fragile)} of {len(batch.runs)} runs have a fragile "
            "verdict under --robustness (--strict fails on it)",
            err=True,
        )
        return batch
    out = []
    for r in batch.runs:
        if r in fragile and r.robustness is not None:
            names = [v.name for v in r.robustness.verdicts if v.status == "fragile"]
            why = "fragile under --robustness: " + ", ".join(names)
            r = replace(r, status="failed", reason=f"{r.reason}; {why}" if r.reason else why)
        out.append(r)
    return replace(batch, runs=out)
