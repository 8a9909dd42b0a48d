"""``motiontool expect --infer``: propose a ``motions.toml`` from motion names, for review."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from motiontool.cli.options import output_option
from motiontool.cli.output import emit, refuse_overwrite, say_wrote
from motiontool.cli.text import plural
from motiontool.errors import MotionToolError

if TYPE_CHECKING:
    from motiontool.kinematics.robots import RobotSpec

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


def expect_command(
    names: Annotated[
        list[str],
        typer.Argument(
            help="Motion names (TurnLeft60), motion files or folders of them.",
            show_default=False,
        ),
    ],
    infer: Annotated[
        bool,
        typer.Option("--infer", help="Propose expectations from the names (the only mode)."),
    ] = False,
    output: _Output = None,
) -> None:
    """Propose expectations (a motions.toml sidecar) from motion names, for people to review:
    Forwards -> dx>0, TurnLeft60 -> yaw=60±9, SideStepRight -> dy<0, StandUpFromFront ->
    upright from lying-front, DiveLeft -> fell to the left, KickSideLeft -> no-fall, HandWave
    -> feet-planted, else upright. For a file, its robot counts too (an arm gets
    no-self-collision), and a stand-up that does not say front or back is played from both to
    find the start it needs. Review it."""
    if not infer:
        raise MotionToolError("expect needs --infer (propose expectations from the names)")
    from motiontool.motionfmt.fileio import collect_motion_files
    from motiontool.sim.infer import infer as infer_name
    from motiontool.sim.infer import propose_chains, render_toml
    from motiontool.sim.infer_start import find_start

    inputs: list[Path] = []
    entries: list[tuple[str, Path | None]] = []
    for raw in names:
        path = Path(raw)
        if path.exists():
            for f in collect_motion_files([path]):
                inputs.append(f)
                entries.append((f.stem, f))
        elif raw.endswith(".motion") or "/" in raw:
            raise MotionToolError(f"cannot read '{raw}': No such file or directory")
        else:
            entries.append((raw, None))
    refuse_overwrite(output, inputs, "--output")
    seen: dict[str, object] = {}
    inferences = []
    for name, file in entries:
        if name in seen:
            continue
        seen[name] = file
        robot = _robot(file) if file is not None else None
        inference = infer_name(name, floating_base=None if robot is None else robot.floating_base)
        if file is not None and robot is None:
            inference.notes.append("no built-in robot fits its joints: batch it with --robot")
        if file is not None and robot is not None:
            find_start(inference, file, robot)
        inferences.append(inference)
    propose_chains(inferences)
    emit(render_toml(inferences), output)
    say_wrote(output, f"TOML, expectations of {plural(len(inferences), 'motion')}")
