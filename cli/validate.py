"""``motiontool validate``: lint motion files exactly as Webots reads them, then against a robot."""

from __future__ import annotations

import sys
from functools import partial
from pathlib import Path
from typing import Annotated, Any

import typer

from motiontool import exit_codes
from motiontool.cli.color import color_enabled
from motiontool.cli.config import ConfigOption, IsolatedOption, Resolver, Settings
from motiontool.cli.fixing import fix_files
from motiontool.cli.jsontext import dumps
from motiontool.cli.lint_run import (
    Checked,
    LintRun,
    Overrides,
    collect,
    lint,
    robot_planner,
)
from motiontool.cli.options import (
    CLI_WORDING,
    NoCacheOption,
    ReportOutput,
    finite,
    robot_option,
    timestep_option,
)
from motiontool.cli.output import emit_pieces, refuse_overwrite, say_wrote
from motiontool.cli.progress import Step, progress
from motiontool.cli.reports import (
    DEFAULT_FORMAT,
    REPORTS,
    Context,
    FormatName,
    Order,
    render_pieces,
    summary,
)
from motiontool.cli.reports.statistics import render_statistics
from motiontool.cli.text import plural
from motiontool.errors import MotionToolError
from motiontool.extras import install_hint
from motiontool.kinematics.checks import (
    DEFAULT_CHECKS,
    DEFAULT_PENETRATION_TOLERANCE_MM,
    CheckUnavailableError,
    RobotChecks,
    parse_checks,
)
from motiontool.kinematics.checks.findings_cache import FindingsCache
from motiontool.kinematics.robots import RobotSpec
from motiontool.motionfmt.fileio import STDOUT, open_output
from motiontool.motionfmt.validate import ValidationReport
from motiontool.stamps import stamps

__all__ = ["validate_command"]

_CHECKS_OPTION = "--checks"


def _robots_used(checker: Checked) -> tuple[dict[str, tuple[RobotSpec, list[str]]], list[str]]:
    """{robot name: (spec, files checked against it)}, and the files no robot was found for."""
    used: dict[str, tuple[RobotSpec, list[str]]] = {}
    skipped = []
    for path, spec in checker.used.items():
        if spec is None:
            skipped.append(path)
        else:
            used.setdefault(spec.name, (spec, []))[1].append(path)
    return used, skipped


def _unchecked(report: ValidationReport, checker: Checked) -> tuple[list[str], list[str]]:
    """The files checked at syntax level only, in report order: all of them (Webots rejects
    them, or no robot was found: MT901), and those Webots rejects (no robot check reached them)."""
    skipped = {p for p, spec in checker.used.items() if spec is None}
    paths = report.files.paths
    rejected = [p for p in paths if p not in checker.used]
    every = [p for p in paths if p not in checker.used or p in skipped]
    return every, rejected


def _robot_line(checker: Checked | None, report: ValidationReport) -> str:
    """One line for people: which robot checked what, and how many files Webots rejects (they
    are not checked against a robot)."""
    if checker is None:
        return "robot: none (--robot none): Webots syntax checks only\n"
    rejected = _unchecked(report, checker)[1]
    unchecked = (
        f"not checked against a robot: {plural(len(rejected), 'file')} Webots rejects"
        if rejected
        else ""
    )
    used, skipped = _robots_used(checker)
    parts = []
    for name, (spec, files) in used.items():
        step = checker.timestep_ms or spec.default_timestep_ms
        count = f"{plural(len(files), 'file')}, " if len(used) + bool(skipped) > 1 else ""
        parts.append(
            f"{name} ({count}{step} ms controller step, model sha256 {spec.model_hash[:12]})"
        )
    if skipped:
        parts.append(f"none for {plural(len(skipped), 'file')} (MT901)")
    if not parts:  # no file reached the robot checks (Webots rejects them all)
        return f"robot: {unchecked}\n" if unchecked else ""
    named = []
    for name in checker.checks:
        if name in checker.skipped:
            missing = checker.skipped[name]
            named.append(f"{name} (skipped: {missing.library} is not installed)")
        elif name == "collision":
            named.append(f"{name} (overlaps under {checker.penetration_tolerance_mm:g} mm ignored)")
        else:
            named.append(name)
    checks = ", ".join(named)
    if unchecked:
        checks += f"; {unchecked}"
    return f"robot: {'; '.join(parts)}; checks: {checks}\n"


def _robot_json(
    checker: Checked | None, requested: str, report: ValidationReport
) -> dict[str, Any]:
    """The JSON report's ``robot`` section and the stamps with the model hash."""
    if checker is None:
        return {"stamps": stamps(), "robot": {"requested": requested, "checks": []}}
    used, _skipped = _robots_used(checker)
    robots = [
        {
            "name": name,
            "model_sha256": spec.model_hash,
            "model_file": spec.model_path.name,
            "timestep_ms": checker.timestep_ms or spec.default_timestep_ms,
            "files": files,
        }
        for name, (spec, files) in used.items()
    ]
    only = next(iter(used.values()))[0].model_hash if len(used) == 1 else None
    return {
        "stamps": stamps(only),
        "robot": {
            "requested": requested,
            "checks": list(checker.checks),
            "collision_tolerance_mm": checker.penetration_tolerance_mm,
            "robots": robots,
            "unchecked_files": _unchecked(report, checker)[0],
            "skipped_checks": [
                {
                    "check": name,
                    "library": exc.library,
                    "extra": exc.extra,
                    "install": install_hint(exc.extra),
                }
                for name, exc in checker.skipped.items()
            ],
        },
    }


_Paths = Annotated[
    list[Path],
    typer.Argument(
        help="Motion files, or directories searched recursively for *.motion ('-': stdin).",
        show_default=False,
    ),
]
_Format = Annotated[
    FormatName,
    typer.Option(
        "--format",
        "-f",
        help="; ".join(f"{name}: {entry.help}" for name, entry in REPORTS.items()) + ".",
    ),
]
_Timestep = Annotated[
    int | None,
    timestep_option(
        "the robot's, Nao 20",
        use="report pose times that are not a multiple of it, and check the command stream "
        "at that step",
    ),
]
_Robot = Annotated[
    str | None,
    robot_option(
        "Robot to check against, per file (default: the configuration's, else auto)",
        none="Webots syntax checks only",
    ),
]
_Checks = Annotated[
    str | None,
    typer.Option(
        _CHECKS_OPTION,
        help="Robot checks, comma-separated: limits, velocity, collision, balance (or all). "
        f"Default: {','.join(DEFAULT_CHECKS)}, each skipped with a note where the library "
        "it needs is not installed; a check named here fails the run instead.",
        show_default=False,
    ),
]
_CollisionTolerance = Annotated[
    float,
    typer.Option(
        "--collision-tolerance",
        min=0.0,
        callback=finite,
        help="Self-collisions shallower than this many mm are not reported (the robots' "
        "collision shapes are coarse); 0 reports every overlap.",
    ),
]
_Strict = Annotated[
    bool | None,
    typer.Option(
        "--strict/--no-strict",
        help="Fail (exit 1) on warnings too, not only on errors (default: the configuration's).",
        show_default=False,
    ),
]
_Group = Annotated[
    bool | None,
    typer.Option(
        "--group/--no-group",
        help="Report consecutive per-pose findings of one code and joint (a limit, a velocity) "
        "as one finding with a count, a line range and the worst value; --no-group: one "
        "finding per pose (default: the configuration's, else group).",
        show_default=False,
    ),
]
_ShowSettings = Annotated[
    bool,
    typer.Option(
        "--show-settings",
        help="Print the configuration file each path uses and the settings it gives (JSON), "
        "then exit.",
    ),
]
_Ignore = Annotated[
    list[str] | None,
    typer.Option(
        CLI_WORDING.ignore_option or "--ignore",
        help="Diagnostic code to leave out (repeat, or comma-separate).",
    ),
]
_Statistics = Annotated[
    bool,
    typer.Option(
        "--statistics",
        help="Print how many findings of each code (most frequent first) instead of each "
        "finding (text only).",
    ),
]
_Fix = Annotated[
    bool,
    typer.Option(
        "--fix",
        help="Apply the safe fixes (Webots then sends exactly the same commands) to the files, "
        "atomically, then report what remains.",
    ),
]
_UnsafeFixes = Annotated[
    bool,
    typer.Option(
        "--unsafe-fixes",
        help="With --fix or --diff, also the fixes that change what the robot does to what "
        "the file evidently means (a blank line that cuts the motion, ',,' cells).",
    ),
]
_Diff = Annotated[
    bool,
    typer.Option("--diff", help="Print the fixes as a unified diff; write nothing."),
]
_Sort = Annotated[
    Order,
    typer.Option(
        "--sort",
        help="file: file by file, by position; severity: errors first, then warnings, then "
        "notes (text, github and sarif; GitHub shows only the first 10 annotations of a kind "
        "per step).",
    ),
]


def validate_command(
    paths: _Paths,
    format: _Format = DEFAULT_FORMAT,
    output: ReportOutput = None,
    timestep: _Timestep = None,
    robot: _Robot = None,
    checks: _Checks = None,
    collision_tolerance: _CollisionTolerance = DEFAULT_PENETRATION_TOLERANCE_MM,
    strict: _Strict = None,
    ignore: _Ignore = None,
    sort: _Sort = Order.file,
    statistics: _Statistics = False,
    group: _Group = None,
    config: ConfigOption = None,
    isolated: IsolatedOption = False,
    show_settings: _ShowSettings = False,
    fix: _Fix = False,
    unsafe_fixes: _UnsafeFixes = False,
    diff: _Diff = False,
    no_cache: NoCacheOption = False,
) -> None:
    """Check motion files as Webots reads them, then against the robot; every problem, with
    file:line:col. Settings come from the closest pyproject.toml [tool.motiontool] or
    motiontool.toml (options here override them).

    Exit code 0 when no error is found (warnings allowed unless --strict), 1 on findings,
    2 on a usage or I/O error.
    """
    if statistics and format.value != "text":
        raise MotionToolError("--statistics is a text report: leave out --format")
    resolver = Resolver(config=config, isolated=isolated)
    if show_settings:
        typer.echo(_settings_text(paths, resolver), nl=False)
        return
    overrides = _overrides(robot, checks, timestep, strict, ignore, group)
    files = collect(paths, resolver)
    refuse_overwrite(output, files, "-o")
    if diff or fix:
        _apply_fixes(files, resolver, overrides, unsafe=unsafe_fixes, write=not diff, output=output)
    cache = None if no_cache else FindingsCache()
    checker = partial(robot_checks, tolerance=collision_tolerance, cache=cache)
    with progress("validate") as step:  # the files are validated as the report is written
        run = lint(files, resolver, overrides, checker, on_step=step)
        _print_report(
            run,
            resolver.for_file(Path("-")),
            format,
            sort,
            strict=strict,
            statistics=statistics,
            robot=robot,
            output=output,
            step=step,
        )
    if run.failed():
        raise typer.Exit(exit_codes.FINDINGS)


def _overrides(
    robot: str | None,
    checks: str | None,
    timestep: int | None,
    strict: bool | None,
    ignore: list[str] | None,
    group: bool | None,
) -> Overrides:
    """What the command line says over the configuration (``--ignore`` repeated or
    comma-separated)."""
    return Overrides(
        robot=robot,
        checks=None if checks is None else parse_checks(checks),
        timestep=timestep,
        strict=strict,
        ignore=tuple(c for item in ignore or [] for c in item.split(",")),
        group=group,
    )


def _apply_fixes(
    files: list[Path],
    resolver: Resolver,
    overrides: Overrides,
    *,
    unsafe: bool,
    write: bool,
    output: Path | None,
) -> None:
    """``--fix`` (``write``): fix the files, say what was fixed on stderr. ``--diff`` (not
    ``write``): print the fixes as a unified diff, then exit (1 if there is one)."""
    robot_fixes = partial(robot_planner, resolver=resolver, overrides=overrides)
    if not write:
        with open_output(STDOUT if output is None else output) as sink:
            changes = fix_files(
                files, unsafe=unsafe, write=False, robot=robot_fixes, diff=sink.write
            )
        say_wrote(output, f"unified diff, the fixes of {plural(len(changes.files), 'file')}")
        raise typer.Exit(exit_codes.FINDINGS if changes.files else exit_codes.CLEAN)
    fixed = fix_files(files, unsafe=unsafe, write=True, robot=robot_fixes)
    typer.echo(f"motiontool: {fixed.line()}", err=True)


def _print_report(
    run: LintRun,
    project: Settings,
    format: FormatName,
    sort: Order,
    *,
    strict: bool | None,
    statistics: bool,
    robot: str | None,
    output: Path | None,
    step: Step,
) -> None:
    """The report of ``run`` in ``format`` (or ``--statistics``), in color where the format
    has colors and the terminal takes them, to ``output`` (None or '-': stdout); ``strict``
    and ``robot`` as given, else the ``project``'s settings; the progress display (``step``)
    ends before the first byte written to a terminal."""
    run.report.limit = project.max_findings  # the others are counted, not shown
    to_stdout = output is None or str(output) == "-"
    color = REPORTS[format.value].colors and color_enabled(sys.stdout, to_file=not to_stdout)
    requested = robot if robot is not None else project.robot
    context = Context(
        color=color,
        order=sort,
        strict=strict if strict is not None else project.strict,
        robot_line=lambda: _robot_line(run.surveyed(), run.report),
        robot_json=lambda: _robot_json(run.surveyed(), requested, run.report),
    )
    report = run.report
    pieces = (
        iter((render_statistics(report, context),))
        if statistics
        else render_pieces(report, format.value, context)
    )
    before_writing = step.stop if _to_terminal(output) else None
    emit_pieces(pieces, output, color=color, before_writing=before_writing)
    label = "statistics" if statistics else REPORTS[format.value].label
    say_wrote(output, f"{label} report of {summary(report).removeprefix('checked ')}")


def _to_terminal(output: Path | None) -> bool:
    """Whether the report goes to a terminal (where a progress display must end first)."""
    return (output is None or str(output) == "-") and sys.stdout.isatty()


def _settings_text(paths: list[Path], resolver: Resolver) -> str:
    """``--show-settings``: for each path, the configuration file used and its settings."""
    docs = []
    for p in paths:
        settings = resolver.for_file(p)
        doc = {"path": str(p), **settings.as_dict()}
        if not p.is_dir():
            doc["robot-for-this-file"] = settings.robot_for(p)
        docs.append(doc)
    return dumps(docs[0] if len(docs) == 1 else {"files": docs})


def robot_checks(
    robot: str,
    checks: tuple[str, ...] | None,
    timestep: int | None,
    *,
    tolerance: float,
    cache: FindingsCache | None,
) -> RobotChecks:
    """The robot checks of ``validate``, their hints in the CLI's words; checks named (with
    --checks or in the configuration) must run (a missing library is an error), the default
    ones may be skipped; ``cache``: the findings cache (None: ``--no-cache``)."""
    try:
        return RobotChecks(
            robot,
            DEFAULT_CHECKS if checks is None else parse_checks(checks),
            skip_missing=checks is None,
            timestep_ms=timestep,
            penetration_tolerance_mm=tolerance,
            wording=CLI_WORDING,
            cache=cache,
        )
    except CheckUnavailableError as exc:
        raise MotionToolError(f"{exc}; leave '{exc.check}' out of {_CHECKS_OPTION}") from exc
