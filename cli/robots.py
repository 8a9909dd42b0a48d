"""``motiontool robots``: the built-in robots, their joint tables, and their model files."""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any

import typer

from motiontool.cli import jsontext
from motiontool.cli.options import TextOrJson, TextOrJsonOption
from motiontool.cli.output import refuse_overwrite, refuse_shared_outputs, say_wrote
from motiontool.errors import MotionToolError
from motiontool.extras import require
from motiontool.kinematics.builtin_robots import describe
from motiontool.kinematics.robots import RobotSpec, builtin_robots, load_robot, robot_choices
from motiontool.motionfmt.fileio import atomic_write
from motiontool.stamps import stamps

__all__ = ["build_app", "export_command", "list_robots", "show_command"]

_OTHERS = (
    "Other robots: --robot path/to/robot.urdf, --robot path/to/robot.xml (MJCF), or\n"
    "--robot erd:<name> for a robot of example-robot-data (e.g. erd:ur5, erd:panda, erd:talos)."
)

_RobotArgument = Annotated[str, typer.Argument(help=f"{robot_choices()}.", show_default=False)]


def _torque_unit(spec: RobotSpec) -> str:
    kinds = {j.kind for j in spec.joints}
    return "N·m" if kinds == {"hinge"} else "N" if kinds == {"slide"} else "N·m or N"


def list_robots() -> str:
    """The built-in robots, one line each, and how to name the others."""
    rows = []
    for name in builtin_robots():
        spec = load_robot(name)
        base = "floating base" if spec.floating_base else "fixed base"
        rows.append(
            (
                name,
                f"{len(spec.joints)} motors, {base}, {spec.default_timestep_ms} ms step: "
                f"{describe(name)}",
            )
        )
    width = max(len(n) for n, _ in rows)
    lines = [f"{n:<{width}}  {text}" for n, text in rows]
    lines += [
        "",
        _OTHERS,
        "'motiontool robots show <robot>' prints a robot's joints and limits.",
    ]
    return "\n".join(lines) + "\n"


def _finite(x: float) -> float | None:
    return x if math.isfinite(x) else None


def _num(x: float) -> str:
    return f"{x:g}" if math.isfinite(x) else ("none" if x > 0 else "-inf")


def _show_json(spec: RobotSpec) -> str:
    doc: dict[str, Any] = {
        "schema": "motiontool.robot",
        "schema_version": 1,
        "stamps": stamps(spec.model_hash),
        "name": spec.name,
        "model_file": str(spec.model_path),
        "model_format": spec.model_format,
        "model_sha256": spec.model_hash,
        "overrides_file": str(spec.overrides_path) if spec.overrides_path else None,
        "floating_base": spec.floating_base,
        "default_timestep_ms": spec.default_timestep_ms,
        "feet": list(spec.feet),
        "units": {
            "lower": "rad (m for slide joints)",
            "upper": "rad (m for slide joints)",
            "max_velocity": "rad/s (m/s for slide joints)",
            "max_torque": "N·m (N for slide joints)",
            "default_timestep_ms": "ms",
            "head_pitch_envelope": "rad: rows (HeadYaw, HeadPitch min, HeadPitch max)",
        },
        "joints": [
            {
                "name": j.name,
                "kind": j.kind,
                "unit": j.unit,
                "lower": _finite(j.lower),
                "upper": _finite(j.upper),
                "max_velocity": _finite(j.max_velocity),
                "max_torque": _finite(j.max_torque),
            }
            for j in spec.joints
        ],
        "head_pitch_envelope": [list(row) for row in spec.head_pitch_envelope],
        "coupled_joints": [list(pair) for pair in spec.coupled_joints],
    }
    return jsontext.dumps(doc)


def _coupled(spec: RobotSpec) -> str:
    """``LHipYawPitch = RHipYawPitch; LPhalanx1..8`` (joints one real motor drives)."""
    groups: dict[str, list[str]] = {}
    for leader, follower in spec.coupled_joints:
        groups.setdefault(leader, [leader]).append(follower)
    parts = []
    for members in groups.values():
        stem = members[0].rstrip("0123456789")
        numbered = all(m.startswith(stem) and m[len(stem) :].isdigit() for m in members)
        if len(members) > 2 and numbered:
            parts.append(f"{members[0]}..{members[-1][len(stem) :]}")
        else:
            parts.append(" = ".join(members))
    return "; ".join(parts)


def _show_text(spec: RobotSpec) -> str:
    facts = [
        ("robot", spec.name),
        ("model", f"{spec.model_path} ({spec.model_format.upper()}, sha256 {spec.model_hash})"),
    ]
    if spec.overrides_path:
        facts.append(("limits from", str(spec.overrides_path)))
    facts += [
        ("base", "floating (free-flying root)" if spec.floating_base else "fixed"),
        ("time step", f"{spec.default_timestep_ms} ms (controller step for motion playback)"),
        ("motors", str(len(spec.joints))),
    ]
    if spec.feet:
        facts.append(("feet", ", ".join(spec.feet)))
    if spec.coupled_joints:
        facts.append(("one motor for", _coupled(spec)))
    if spec.head_pitch_envelope:
        facts.append(
            (
                "HeadPitch",
                f"range depends on HeadYaw ({len(spec.head_pitch_envelope)} rows; "
                "--format json lists them)",
            )
        )
    width = max(len(k) for k, _ in facts)
    lines = [f"{k:<{width}}  {v}" for k, v in facts]
    header = ("joint", "kind", "lower", "upper", "unit", "max velocity", "max torque")
    rows = [header]
    for j in spec.joints:
        torque = "N·m" if j.kind == "hinge" else "N"
        rows.append(
            (
                j.name,
                j.kind,
                _num(j.lower),
                _num(j.upper),
                j.unit,
                f"{_num(j.max_velocity)} {j.unit}/s",
                f"{_num(j.max_torque)} {torque}",
            )
        )
    widths = [max(len(r[i]) for r in rows) for i in range(len(header))]
    lines.append("")
    for r in rows:
        lines.append("  ".join(cell.ljust(w) for cell, w in zip(r, widths, strict=True)).rstrip())
    return "\n".join(lines) + "\n"


def show_command(
    robot: _RobotArgument,
    format: TextOrJsonOption = TextOrJson.text,
) -> None:
    """A robot's joints: limits, maximum velocities and torques, with their units."""
    spec = load_robot(robot)
    typer.echo(_show_json(spec) if format is TextOrJson.json else _show_text(spec), nl=False)


def export_command(
    robot: _RobotArgument,
    mjcf: Annotated[
        Path | None, typer.Option("--mjcf", help="Write the model as MJCF to this file.")
    ] = None,
    urdf: Annotated[
        Path | None,
        typer.Option(
            "--urdf",
            help="Write the model as URDF to this file (capsules become a cylinder and two "
            "spheres; a floating root must be loaded with a free-flyer joint).",
        ),
    ] = None,
) -> None:
    """Write a robot's model file, for MuJoCo or Pinocchio (each file written atomically)."""
    from motiontool.kinematics.export import mjcf_bytes, urdf_bytes

    if mjcf is None and urdf is None:
        raise MotionToolError("robots export: name an output with --mjcf FILE and/or --urdf FILE")
    source = [Path(robot)] if Path(robot).suffix.lower() in (".urdf", ".xml") else []
    refuse_overwrite(mjcf, source, "--mjcf")
    refuse_overwrite(urdf, source, "--urdf")
    if urdf is not None:
        require("pinocchio", "kinematics", "motiontool robots export --urdf")
    spec = load_robot(robot)
    outputs: list[tuple[Path | None, Callable[[RobotSpec], bytes]]] = [
        (mjcf, mjcf_bytes),
        (urdf, urdf_bytes),
    ]
    blobs = [(path, make(spec)) for path, make in outputs if path is not None]
    refuse_shared_outputs({"--mjcf": mjcf, "--urdf": urdf})
    for path, data in blobs:
        atomic_write(path, data)
        kind = "MJCF" if path is mjcf else "URDF"
        say_wrote(path, f"{kind}, {len(data)} bytes, robot {spec.name}")


def build_app(guard: Callable[[Callable[..., Any]], Callable[..., Any]]) -> typer.Typer:
    """The ``robots`` sub-app; ``guard`` turns a MotionToolError into one line and exit 2."""
    robots = typer.Typer(
        name="robots",
        help="The built-in robots (listed without a sub-command), their joints and models.",
        invoke_without_command=True,
        no_args_is_help=False,
        add_completion=False,
        rich_markup_mode=None,
        context_settings={"help_option_names": ["-h", "--help"]},
    )

    def _list(ctx: typer.Context) -> None:
        """List the built-in robots and how to name other ones."""
        if ctx.invoked_subcommand is None:
            typer.echo(list_robots(), nl=False)

    robots.callback(invoke_without_command=True)(guard(_list))
    robots.command("show")(guard(show_command))
    robots.command("export")(guard(export_command))
    return robots
