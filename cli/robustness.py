"""``play --robustness N``: the run's verdicts replayed over N perturbed members
(:mod:`motiontool.sim.robustness`) on the batch executors, cached as batch runs are."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from motiontool import exit_codes
from motiontool.cli.options import MAX_COUNT
from motiontool.errors import MotionToolError
from motiontool.motionfmt.fileio import is_stdin
from motiontool.sim.executor import EXECUTORS, REGISTRY

if TYPE_CHECKING:
    from motiontool.sim.play import PlayOptions
    from motiontool.sim.robustness import Robustness
    from motiontool.sim.session import PlayPlan, PlayResult

__all__ = [
    "ExecutorOption",
    "JobsOption",
    "NoCacheOption",
    "RobustnessOption",
    "StrictOption",
    "check_robustness",
    "robustness_of",
    "strict_exit",
]

RobustnessOption = Annotated[
    int | None,
    typer.Option(
        "--robustness",
        min=1,
        max=MAX_COUNT,
        metavar="N",
        help="Replay every verdict (clean, each expectation) over N perturbed members (8 is "
        "a good start): friction x0.5-2, physics step 1/2/4 ms, mass x0.95-1.05, start yaw "
        "+-5 deg, start noise 0-0.01 rad, drawn from --seed; each verdict holds, is fragile "
        "(k of N disagree: a warning) or fails.",
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
    """``--robustness`` replays one motion file, on an executor that exists; ``--strict``
    needs it: exit 2 before the run."""
    if executor not in EXECUTORS:
        raise typer.BadParameter(
            f"{executor!r}: choose {' or '.join(EXECUTORS)}", param_hint="--executor"
        )
    if strict and n is None:
        raise MotionToolError("--strict fails on a fragile verdict: pass --robustness N")
    if n is not None and (len(files) != 1 or is_stdin(files[0])):
        raise MotionToolError(
            "--robustness replays one motion file (not standard input): play one file, or "
            "use batch --robustness"
        )


def robustness_of(
    result: PlayResult,
    planned: PlayPlan,
    options: PlayOptions,
    *,
    n: int,
    run: tuple[str, int, Path | None],
) -> Robustness | None:
    """The robustness of ``result``'s run over ``n`` members, each played as the run was
    (``options``, the plan's start and world) on the batch executors (``run``: executor, jobs,
    cache folder or None), judged as the run was; None when the run could not start."""
    report = result.report
    if report is None:
        return None
    import hashlib

    from motiontool.motionfmt.fileio import read_file
    from motiontool.sim.batch import RunSpec, run_batch
    from motiontool.sim.robustness import judge, member_specs
    from motiontool.sim.runs import run_spec

    executor, jobs, cache_dir = run
    path = planned.files[0]
    nominal = RunSpec(
        str(path),
        hashlib.sha256(read_file(path)).hexdigest(),
        report.robot,
        options=tuple(sorted(_member_options(planned, options, report.robot, report).items())),
        expect=planned.motion.expect,
    )
    control_step = int(report.stamps["control_step_ms"])
    specs = member_specs(nominal, n, seed=options.seed, control_step_ms=control_step)
    batch = run_batch(
        specs,
        run_spec,
        model_hash=lambda _robot: str(report.stamps.get("model_sha256") or ""),
        executor=executor,
        jobs=jobs,
        cache_dir=cache_dir,
    )
    return judge(report, batch.runs, seed=options.seed)


def _member_options(
    planned: PlayPlan, options: PlayOptions, robot: str, report: Any
) -> dict[str, Any]:
    """The run's options as a batch run carries them (its cache key): the control step it ran
    at, its start, physics, world and play options."""
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
    if planned.start.lying:
        out["start"] = str(planned.start)
    world, node = planned.world, planned.robot_node
    if world is None:
        world, node = planned.motion.world, planned.motion.robot_node
    out.update(world_run_options(world, node, [robot]))
    return out


def strict_exit(code: int, robustness: Robustness | None, strict: bool) -> int:
    """The run's exit code: ``code``, or 1 where ``strict`` and a verdict is fragile."""
    if strict and robustness is not None and robustness.fragile and code == exit_codes.CLEAN:
        return exit_codes.FINDINGS
    return code
