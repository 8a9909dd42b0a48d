"""``motiontool expect --infer``: propose a ``motions.toml`` from motion names, for review.

The plays it makes to infer (a stand-up from both lying starts,
:mod:`motiontool.sim.infer_start`) are ``play``'s: in ``--world`` by its ``--robot-node``, with
``--[no-]self-collision``, from ``--start-pose``, each replayed with ``--robustness N`` over
play's ensemble on the batch executors (:func:`motiontool.cli.robustness.robustness_of`); the
options are play's, spelt once (:mod:`motiontool.cli.physics_options`,
:mod:`motiontool.cli.chain_options`, :mod:`motiontool.cli.robustness`).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from motiontool import exit_codes
from motiontool.cli.chain_options import StartPoseOption, start_pose_options
from motiontool.cli.config import ConfigOption, IsolatedOption, Resolver
from motiontool.cli.options import output_option
from motiontool.cli.output import emit, refuse_overwrite, say_wrote
from motiontool.cli.physics_options import (
    RobotNodeOption,
    SelfCollisionOption,
    WorldOption,
    chosen_world,
)
from motiontool.cli.robustness import (
    ExecutorOption,
    JobsOption,
    NoCacheOption,
    RobustnessOption,
    StrictOption,
    check_ensemble,
)
from motiontool.cli.text import plural
from motiontool.errors import MotionToolError
from motiontool.motionfmt.fileio import is_stdout

if TYPE_CHECKING:
    from motiontool.kinematics.robots import RobotSpec
    from motiontool.sim.infer import Inference
    from motiontool.sim.infer_start import ProbeResult
    from motiontool.sim.robustness import Robustness
    from motiontool.sim.start import StartState

__all__ = ["expect_command"]


def _robot(path: Path) -> RobotSpec | None:
    """The built-in robot ``path``'s joints belong to (None: no robot fits).

    Raises:
        MotionToolError: ``PATH:LINE:COL: not a motion file Webots loads: REASON`` for a file
            Webots rejects (nothing is proposed for it).
    """
    from motiontool.kinematics.robots import AUTO, pick_robot
    from motiontool.motionfmt import CODES, read_bytes, read_file

    result = read_bytes(read_file(path), str(path))
    if not result.accepted:
        first = next((d for d in result.diagnostics if CODES[d.code].rejects), None)
        where, why = (f"{first.line}:{first.column}", first.message) if first else ("1:1", "")
        raise MotionToolError(
            f"{path}:{where}: not a motion file Webots loads{': ' + why if why else ''}; "
            "expect --infer proposes expectations for motion files"
        )
    return pick_robot(AUTO, result.joints)


_Output = Annotated[Path | None, output_option("Write the motions.toml here (default: stdout).")]
_Names = Annotated[
    list[str],
    typer.Argument(
        help="Motion names (TurnLeft60), motion files or folders of them.", show_default=False
    ),
]
_Infer = Annotated[
    bool, typer.Option("--infer", help="Propose expectations from the names (the only mode).")
]
_Seed = Annotated[int, typer.Option("--seed", help="Seed of the --robustness draws.")]


def expect_command(
    names: _Names,
    infer: _Infer = False,
    output: _Output = None,
    world: WorldOption = None,
    robot_node: RobotNodeOption = None,
    self_collision: SelfCollisionOption = None,
    start_pose: StartPoseOption = None,
    robustness: RobustnessOption = None,
    seed: _Seed = 0,
    strict: StrictOption = False,
    jobs: JobsOption = 2,
    executor: ExecutorOption = "local",
    no_cache: NoCacheOption = False,
    config: ConfigOption = None,
    isolated: IsolatedOption = False,
) -> None:
    """Propose expectations (a motions.toml sidecar) from motion names, for people to review:
    Forwards -> dx>0, TurnLeft60 -> yaw=60±9, SideStepRight -> dy<0, StandUpFromFront ->
    upright from lying-front, DiveLeft -> fell to the left, KickSideLeft -> no-fall, HandWave
    -> feet-planted, else upright; a X_Start/X_Loop/X_Stop family is a chain (after). For a
    file, its robot counts too (an arm gets no-self-collision), and a stand-up that does not
    say front or back is played from both to find the start it needs: in --world (each
    proposal then plays there: world, robot-node; else the configuration's world), from
    --start-pose, and with --robustness N over play's ensemble (a start is proposed only
    where every member agrees; fragile: a comment and a warning, exit 1 with --strict).
    Review it."""
    if not infer:
        raise MotionToolError("expect needs --infer (propose expectations from the names)")
    if robot_node is not None and world is None:
        raise MotionToolError("--robot-node names a robot node of --world: pass --world FILE.wbt")
    check_ensemble(robustness, strict, executor)
    from motiontool.sim.infer import propose_chains, render_toml

    entries = _entries(names)
    inputs = [f for _name, f in entries if f is not None]
    refuse_overwrite(output, [*inputs, *([world] if world is not None else [])], "--output")
    robots = {f: _robot(f) for f in inputs}  # every file read before anything plays
    where = _where((world, robot_node), robots, Resolver(config=config, isolated=isolated))
    options = {"seed": seed, "self_collision": self_collision, **start_pose_options(start_pose)}
    probe = _Probe(where, options, (robustness, executor, jobs, no_cache))
    inferences = [_infer(name, file, robots, probe) for name, file in entries]
    propose_chains(inferences)
    folder = _sidecar_folder(output, inputs)
    text = render_toml(
        inferences,
        world=None if world is None else _relative(world, folder),
        robot_node=robot_node,
        header=_header(world, folder, output, self_collision, start_pose),
    )
    emit(text, output)
    say_wrote(output, f"TOML, expectations of {plural(len(inferences), 'motion')}")
    raise typer.Exit(_fragile_exit([i for i in inferences if i.fragile], strict))


def _entries(names: list[str]) -> list[tuple[str, Path | None]]:
    """Each motion to propose for, once: (its name, its file or None for a bare name)."""
    from motiontool.motionfmt.fileio import collect_motion_files

    entries: dict[str, Path | None] = {}
    for raw in names:
        path = Path(raw)
        if path.exists():
            for f in collect_motion_files([path]):
                entries.setdefault(f.stem, f)
        elif raw.endswith(".motion") or "/" in raw:
            raise MotionToolError(f"cannot read '{raw}': No such file or directory")
        else:
            entries.setdefault(raw, None)
    return list(entries.items())


def _infer(
    name: str, file: Path | None, robots: dict[Path, RobotSpec | None], probe: _Probe
) -> Inference:
    """What ``name`` suggests; for a file, on its robot, a stand-up's start found by ``probe``."""
    from motiontool.sim.infer import infer
    from motiontool.sim.infer_start import find_start

    robot = None if file is None else robots[file]
    inference = infer(name, floating_base=None if robot is None else robot.floating_base)
    if file is not None and robot is None:
        inference.notes.append("no built-in robot fits its joints: batch it with --robot")
    if file is not None and robot is not None:
        find_start(inference, file, robot, probe)
    return inference


_Where = tuple[Path | None, str | None, int | None]
"""Where and how a file's probes play: the world, its robot node, the control step (ms)."""


def _where(
    given: tuple[Path | None, str | None],
    robots: dict[Path, RobotSpec | None],
    resolver: Resolver,
) -> dict[Path, _Where]:
    """Where each file's probes play, as ``play`` would play it: ``--world`` (``given``), else
    its configuration's ``world``; outside a world, at its configuration's control step. Each
    world is read for the robot of the files (for bare names, read): one line, exit 2, before
    anything plays."""
    from motiontool.sim.world import read_world

    out: dict[Path, _Where] = {}
    checked = set()
    for path, robot in robots.items():
        settings = resolver.for_file(path)
        world, node = chosen_world(given, (None, None), settings)
        out[path] = (world, node, None if world is not None else settings.timestep)
        if world is not None and robot is not None and (world, node, robot.name) not in checked:
            read_world(world, node, robot.name)
            checked.add((world, node, robot.name))
    if given[0] is not None and not any(w == given[0] for w, _n, _r in checked):
        read_world(given[0], given[1], "")
    return out


def _sidecar_folder(output: Path | None, inputs: list[Path]) -> Path:
    """Where the proposed motions.toml goes: ``--output``'s folder, else (stdout) the folder
    of the motion files (the one above them all), else the current one."""
    import os

    if output is not None and not is_stdout(output):
        return output.parent
    if inputs:
        return Path(os.path.commonpath([f.resolve().parent for f in inputs]))
    return Path.cwd()


def _relative(path: Path, folder: Path) -> str:
    """``path`` as the sidecar names it: from ``folder`` (absolute across drives)."""
    import os

    try:
        return Path(os.path.relpath(path.resolve(), folder.resolve())).as_posix()
    except ValueError:
        return path.resolve().as_posix()


def _header(
    world: Path | None,
    folder: Path,
    output: Path | None,
    self_collision: bool | None,
    start_pose: str | None,
) -> list[str]:
    """The header's lines on how the motions were played, and where the file belongs."""
    how = []
    if world is not None:
        how.append(f"in the world {world}")
    if self_collision is not None:
        how.append(f"self-collision physics {'on' if self_collision else 'off'}")
    if start_pose is not None:
        how.append(f"from the start pose {start_pose}")
    lines = [f"A stand-up played to find its lying start plays {', '.join(how)}."] if how else []
    if world is not None and (output is None or is_stdout(output)):
        lines.append(f"world is a path from {folder}: save this file there.")
    return lines


def _fragile_exit(fragile: list[Inference], strict: bool) -> int:
    """Warn on stderr of each proposal whose start is fragile; 1 with ``strict``, else 0."""
    more = " (--strict: exit 1)" if strict else ""
    for inference in fragile:
        typer.echo(
            f"motiontool: warning: {inference.name}: the lying start it needs is fragile under "
            f"--robustness: no start proposed{more}",
            err=True,
        )
    return exit_codes.FINDINGS if fragile and strict else exit_codes.CLEAN


class _Probe:
    """A stand-up played from a lying start as ``play`` plays it
    (:data:`motiontool.sim.infer_start.Probe`): where ``where`` says (each file's world, robot
    node and control step, :func:`_where`), with ``options``
    (:class:`~motiontool.sim.play.PlayOptions` keywords), judged ``upright``, replayed over
    ``--robustness`` members (``robust``: N, executor, jobs, --no-cache) when asked."""

    def __init__(
        self,
        where: dict[Path, _Where],
        options: dict[str, Any],
        robust: tuple[int | None, str, int, bool],
    ) -> None:
        self.where, self.options, self.robust = where, options, robust

    def __call__(self, path: Path, robot: RobotSpec, start: StartState) -> ProbeResult:
        from motiontool.cli.robustness import robustness_of
        from motiontool.sim.infer_start import UPRIGHT, ProbeResult
        from motiontool.sim.play_options import PlayOptions
        from motiontool.sim.session import plan_play

        world, node, timestep = self.where[path]
        planned = plan_play(
            [path], expect=[UPRIGHT], start=start, sidecar=False, world=world, robot_node=node
        )
        options = PlayOptions(timestep_ms=timestep, **self.options)
        result = planned.run(robot=robot.name, options=options)
        if result.report is None:
            assert result.error is not None, "a result without a report has an error"
            raise result.error
        (upright,) = result.report.expectations
        n, executor, jobs, no_cache = self.robust

        def replay() -> Robustness | None:
            return robustness_of(result, planned, options, n=n, run=(executor, jobs, no_cache))

        return ProbeResult(upright.passed, replay)
