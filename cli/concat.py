"""``motiontool concat``: motions one after another, with transitions within maxVelocity."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from motiontool import exit_codes
from motiontool.cli import jsontext
from motiontool.cli._authoring import (
    destination,
    findings_json,
    findings_lines,
    load_input,
    output_target,
    read_result,
    say,
    write_result,
)
from motiontool.cli.options import (
    MAX_MS,
    Format,
    FormatOption,
    InPlace,
    Output,
    ResultTimestep,
    RobotOption,
    finite,
)
from motiontool.cli.output import refuse_overwrite
from motiontool.cli.text import num
from motiontool.errors import MotionToolError
from motiontool.kinematics.checks import Velocity
from motiontool.kinematics.robots import AUTO, RobotSpec, pick_robot
from motiontool.motionfmt.diagnostics import Diagnostic
from motiontool.motionfmt.fileio import source_name
from motiontool.motionfmt.ops.concat import Concatenated, Transition, concat
from motiontool.motionfmt.retime import DEFAULT_MARGIN
from motiontool.stamps import stamps

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["concat_command"]


def _in_transitions(
    times_ms: npt.NDArray[np.int64], transitions: tuple[Transition, ...], step_ms: int
) -> npt.NDArray[np.bool_]:
    """Which of the times (ms) of velocity findings lie in a transition (within one
    controller step after it)."""
    import numpy as np

    inside = np.zeros(times_ms.shape, dtype=np.bool_)
    for t in transitions:
        inside |= (t.start_ms < times_ms) & (times_ms <= t.start_ms + t.duration_ms + step_ms)
    return inside


_Paths = Annotated[list[Path], typer.Argument(help="Two or more motion files, in playing order.")]
_Margin = Annotated[
    float,
    typer.Option(
        "--margin",
        callback=finite,
        help="Fraction of maxVelocity a transition may use, in (0, 1].",
    ),
]
_Transition = Annotated[
    int | None,
    typer.Option(
        "--transition",
        min=1,
        max=MAX_MS,
        help="Transition time in ms, instead of fitting the shortest one within the "
        "robot's maxVelocity x margin.",
    ),
]


def concat_command(
    paths: _Paths,
    robot: RobotOption = AUTO,
    margin: _Margin = DEFAULT_MARGIN,
    transition: _Transition = None,
    timestep: ResultTimestep = None,
    output: Output = None,
    in_place: InPlace = False,
    format: FormatOption = Format.text,
) -> None:
    """Join motions one after another, each transition as short as the robot's limits allow.

    Every motion needs the same joints (any column order: later files are put in the first
    one's order, cell by cell). Between two motions, the first's last pose moves to the next
    one's first pose in the shortest time within maxVelocity x margin for every joint both
    command, in whole controller steps (-t, else the robot's; retime --fit-limits' logic), or
    in --transition ms; the next one's times are shifted to follow. The first file's lines
    keep their spelling, the others' too but for their times. --in-place replaces the first
    file. Exits 1 if validate's velocity check finds a transition too fast (only possible with
    --transition, or after a '*').
    """
    if len(paths) < 2:
        raise MotionToolError("concat needs two motion files or more")
    target = output_target(paths[0], output, in_place)
    if not in_place:
        refuse_overwrite(target, paths[1:], "-o", "write to a file that is not an input")
    docs = [load_input(p) for p in paths]
    spec = pick_robot(robot, docs[0].joints)
    if spec is None and transition is None:
        raise MotionToolError(
            "fitting the transitions needs a robot's velocity limits: give --robot "
            "(none detected), or a fixed --transition MS"
        )
    limits = None if spec is None else {j.name: j.max_velocity for j in spec.joints}
    step = None if spec is None else timestep or spec.default_timestep_ms
    result = concat(
        docs, transition_ms=transition, max_velocity=limits, margin=margin, step_ms=step
    )
    del docs  # the inputs go before the result is read (its memory is theirs again)
    step, findings = _transition_findings(result, spec, timestep)
    write_result(result.document, target)
    if format is Format.json:
        say(_json(result, paths, target, spec, margin, findings), target)
    else:
        say(_text(result, paths, target, spec, margin, findings, step), target)
    if findings:
        raise typer.Exit(exit_codes.FINDINGS)


def _transition_findings(
    result: Concatenated, spec: RobotSpec | None, timestep: int | None
) -> tuple[int, list[Diagnostic]]:
    """The controller step, ms (0 without a robot), and validate's velocity findings in the
    transitions of ``result`` at that step (none without a robot)."""
    if spec is None:
        return 0, []
    step = timestep or spec.default_timestep_ms
    found = Velocity(spec, timestep).at_times(
        read_result(result.document), lambda t: _in_transitions(t, result.transitions, step)
    )
    return step, list(found)


def _text(
    r: Concatenated,
    paths: list[Path],
    target: Path | None,
    spec: RobotSpec | None,
    margin: float,
    findings: list[Diagnostic],
    step: int,
) -> str:
    dest = destination(target)
    names = " + ".join(source_name(p) for p in paths)
    motion = r.document.motion
    lines = [f"joined {names} -> {dest}: {motion.n_poses} poses, {motion.duration_ms} ms"]
    if spec is not None:
        lines.append(
            f"robot: {spec.name} (model {spec.model_hash[:12]}); transitions within "
            f"{num(margin * 100)}% of maxVelocity"
        )
    for t in r.transitions:
        why = (
            f"fitted, limited by {t.joint}"
            if t.fitted and t.joint
            else ("fitted: no joint moves, 1 ms" if t.fitted else "given")
        )
        lines.append(f"transition into {t.into}: {t.duration_ms} ms from {t.start_ms} ms ({why})")
    if r.reordered:
        lines.append("columns put in the first file's order: " + ", ".join(r.reordered))
    if r.dropped_lines:
        lines.append(f"left out {r.dropped_lines} lines after a blank line (Webots ignores them)")
    if r.unconstrained and spec is not None:
        lines.append(f"not motors of {spec.name}, not constrained: " + ", ".join(r.unconstrained))
    if spec is not None:
        lines += findings_lines(
            findings,
            f"velocity check ({step} ms controller step): {len(findings)} warnings in the "
            "transitions:",
            f"velocity check ({step} ms controller step): no warning in the transitions",
        )
    return "\n".join(lines) + "\n"


def _json(
    r: Concatenated,
    paths: list[Path],
    target: Path | None,
    spec: RobotSpec | None,
    margin: float,
    findings: list[Diagnostic],
) -> str:
    doc = {
        "schema": "motiontool.concat",
        "schema_version": 1,
        "stamps": stamps(None if spec is None else spec.model_hash),
        "inputs": [source_name(p) for p in paths],
        "output": None if target is None else str(target),
        "units": {"start_ms": "ms", "duration_ms": "ms"},
        "robot": None if spec is None else spec.name,
        "margin": margin if spec is not None else None,
        "duration_ms": r.document.motion.duration_ms,
        "transitions": [
            {
                "into": t.into,
                "start_ms": t.start_ms,
                "duration_ms": t.duration_ms,
                "joint": t.joint or None,
                "fitted": t.fitted,
            }
            for t in r.transitions
        ],
        "reordered": list(r.reordered),
        "dropped_lines": r.dropped_lines,
        "unconstrained": list(r.unconstrained),
        "transition_velocity_findings": findings_json(findings),
    }
    return jsontext.dumps(doc)
