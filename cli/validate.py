"""``motiontool validate``: lint motion files exactly as Webots reads them, then against a robot."""

from __future__ import annotations

from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, NamedTuple

import typer

from motiontool import exit_codes
from motiontool.cli.config import (
    ConfigOption,
    IsolatedOption,
    Resolver,
    check_selectors,
)
from motiontool.cli.lint_run import (
    Overrides,
    collect,
    lint,
    reported,
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
from motiontool.cli.output import refuse_overwrite, say_wrote
from motiontool.cli.progress import progress
from motiontool.cli.reports import DEFAULT_FORMAT, REPORTS, FormatName, Order
from motiontool.cli.text import plural
from motiontool.cli.validate_report import Shown, check_and_report
from motiontool.errors import MotionToolError
from motiontool.kinematics.checks.registry import (
    CHECKS,
    DEFAULT_CHECKS,
    DEFAULT_PENETRATION_TOLERANCE_MM,
    parse_checks,
)
from motiontool.motionfmt.fileio import STDOUT, is_stdin, open_output

if TYPE_CHECKING:  # a syntax-level run imports no check
    from motiontool.kinematics.checks.findings_cache import FindingsCache
    from motiontool.kinematics.checks.runner import RobotChecks

__all__ = ["validate_command"]

_CHECKS_OPTION = "--checks"


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
        "the robot's, Nao 20 ms, UR5e 8 ms; none without a robot",
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
        help=f"Robot checks, comma-separated: {', '.join(CHECKS)} (or all). "
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
        help="Code, or prefix of codes (MT2), to leave out (repeat, or comma-separate).",
    ),
]
_Select = Annotated[
    list[str] | None,
    typer.Option(
        "--select",
        metavar="CODES",
        help="Report these codes or prefixes (MT2) only, instead of the configuration's "
        "selection; the most specific of --select, --extend-select and --ignore decides, as "
        "in ruff (repeat, or comma-separate).",
        show_default=False,
    ),
]
_ExtendSelect = Annotated[
    list[str] | None,
    typer.Option(
        "--extend-select",
        metavar="CODES",
        help="Report these codes or prefixes too, over the configuration's selection.",
        show_default=False,
    ),
]
_ForceExclude = Annotated[
    bool | None,
    typer.Option(
        "--force-exclude/--no-force-exclude",
        help="Leave out files named here that the configuration's exclude matches too (as the "
        "pre-commit hooks do; default: the configuration's force-exclude, else off).",
        show_default=False,
    ),
]
_RespectGitignore = Annotated[
    bool | None,
    typer.Option(
        "--respect-gitignore/--no-respect-gitignore",
        help="Folder searches leave out what .gitignore files ignore (in a git repository) "
        "and hidden folders (default: the configuration's respect-gitignore, else on).",
        show_default=False,
    ),
]
_ExitZero = Annotated[
    bool,
    typer.Option(
        "--exit-zero",
        help="Exit 0 even when findings fail the run (usage and I/O errors still exit 2).",
    ),
]
_Quiet = Annotated[
    bool,
    typer.Option(
        "--quiet",
        "-q",
        help="Print the findings only: no robot line, no summary, no 'fixed' line.",
    ),
]
_StdinFilename = Annotated[
    str | None,
    typer.Option(
        "--stdin-filename",
        metavar="NAME",
        help="The name to report standard input ('-') under, and to find its configuration "
        "by (robot per glob, per-file-ignores; it is never left out).",
        show_default=False,
    ),
]
_Statistics = Annotated[
    bool,
    typer.Option(
        "--statistics",
        help="Print how many findings of each code (most frequent first) instead of each "
        "finding (--format text or json).",
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
    select: _Select = None,
    extend_select: _ExtendSelect = None,
    force_exclude: _ForceExclude = None,
    respect_gitignore: _RespectGitignore = None,
    exit_zero: _ExitZero = False,
    quiet: _Quiet = False,
    stdin_filename: _StdinFilename = None,
) -> None:
    """Check motion files as Webots reads them, then against the robot; every problem, with
    file:line:col. Settings come from the closest pyproject.toml [tool.motiontool] or
    motiontool.toml (options here override them).

    Exit code 0 when no error is found (warnings allowed unless --strict), 1 on findings,
    2 on a usage or I/O error.
    """
    _refuse(paths, format, statistics=statistics, stdin_filename=stdin_filename)
    resolver = Resolver(config=config, isolated=isolated)
    if show_settings:
        typer.echo(_settings_text(paths, resolver), nl=False)
        return
    overrides = _overrides(robot, checks, timestep, strict, group, stdin_filename)
    overrides = overrides._replace(force_exclude=force_exclude)
    overrides = _selecting(overrides, ignore, select, extend_select, respect_gitignore)
    files = collect(paths, resolver, overrides)
    refuse_overwrite(output, files, "-o")
    fixes = _Fixes(fix=fix, diff=diff, unsafe=unsafe_fixes, quiet=quiet, exit_zero=exit_zero)
    stdin_fixed = _apply_fixes(files, resolver, overrides, fixes, output=output)
    checker = partial(_robot_checks, tolerance=collision_tolerance, cached=not no_cache)
    to_stderr = stdin_fixed is not None and output is None  # stdout: the fixed text
    shown = Shown(format, sort, statistics, quiet, output, strict, robot, to_stderr)
    with progress("validate") as step:
        run = lint(files, resolver, overrides, checker, on_step=step, stdin_data=stdin_fixed)
        # each file read and checked, then handed to the report, which is written as it goes
        check_and_report(run, resolver.for_file(Path(stdin_filename or "-")), shown, step)
    if run.failed() and not exit_zero:
        raise typer.Exit(exit_codes.FINDINGS)


def _refuse(
    paths: list[Path], format: FormatName, *, statistics: bool, stdin_filename: str | None
) -> None:
    """Refuse options that cannot go together, before anything is read."""
    if statistics and format.value not in ("text", "json"):
        raise MotionToolError("--statistics: --format text or json")
    if stdin_filename is not None and not any(is_stdin(p) for p in paths):
        raise MotionToolError("--stdin-filename names standard input: give '-' as the path")


def _overrides(
    robot: str | None,
    checks: str | None,
    timestep: int | None,
    strict: bool | None,
    group: bool | None,
    stdin_name: str | None,
) -> Overrides:
    """What the command line says over the configuration."""
    return Overrides(
        robot=robot,
        checks=None if checks is None else parse_checks(checks),
        timestep=timestep,
        strict=strict,
        group=group,
        stdin_name=stdin_name,
    )


def _selecting(
    overrides: Overrides,
    ignore: list[str] | None,
    select: list[str] | None,
    extend_select: list[str] | None,
    respect_gitignore: bool | None,
) -> Overrides:
    """``overrides`` with the codes the command line selects and ignores (codes or prefixes,
    each option repeated or comma-separated; an unknown one is an error before any file is
    read) and its choice of ``.gitignore``."""
    return overrides._replace(
        ignore=check_selectors(ignore or [], "--ignore"),
        select=None if select is None else check_selectors(select, "--select"),
        extend_select=check_selectors(extend_select or [], "--extend-select"),
        respect_gitignore=respect_gitignore,
    )


class _Fixes(NamedTuple):
    """``--fix``, ``--diff``, ``--unsafe-fixes``, and ``--quiet`` and ``--exit-zero`` for
    what they print and how they exit."""

    fix: bool
    diff: bool
    unsafe: bool
    quiet: bool
    exit_zero: bool


def _apply_fixes(
    files: list[Path],
    resolver: Resolver,
    overrides: Overrides,
    fixes: _Fixes,
    *,
    output: Path | None,
) -> bytes | None:
    """``--fix``: fix the files, say what was fixed on stderr (not ``quiet``); standard
    input's fixed text goes to stdout, as ruff prints it, and is returned (None: no standard
    input, or no ``--fix``). ``--diff``: print the fixes as a unified diff, then exit (1 if
    there is one, but with ``exit_zero``)."""
    if not (fixes.fix or fixes.diff):
        return None
    from motiontool.cli.fixing import fix_files  # imported where files are fixed

    unsafe, quiet, exit_zero = fixes.unsafe, fixes.quiet, fixes.exit_zero
    robot_fixes = partial(robot_planner, resolver=resolver, overrides=overrides)
    select = partial(reported, resolver=resolver, overrides=overrides)
    if fixes.diff:
        with open_output(STDOUT if output is None else output) as sink:
            changes = fix_files(
                files,
                unsafe=unsafe,
                write=False,
                robot=robot_fixes,
                diff=sink.write,
                named=overrides.named,
                select=select,
            )
        say_wrote(output, f"unified diff, the fixes of {plural(len(changes.files), 'file')}")
        failed = changes.files and not exit_zero
        raise typer.Exit(exit_codes.FINDINGS if failed else exit_codes.CLEAN)
    fixed = fix_files(files, unsafe=unsafe, write=True, robot=robot_fixes, select=select)
    if not quiet:
        typer.echo(f"motiontool: {fixed.line()}", err=True)
    return fixed.stdin


def _settings_text(paths: list[Path], resolver: Resolver) -> str:
    """``--show-settings``: for each path, the configuration file used and its settings."""
    from motiontool.cli.jsontext import dumps  # json: imported where JSON is written

    docs = []
    for p in paths:
        settings = resolver.for_file(p)
        doc = {"path": str(p), **settings.as_dict()}
        if not p.is_dir():
            doc["robot-for-this-file"] = settings.robot_for(p)
        docs.append(doc)
    return dumps(docs[0] if len(docs) == 1 else {"files": docs})


def _robot_checks(
    robot: str,
    checks: tuple[str, ...] | None,
    timestep: int | None,
    *,
    tolerance: float,
    cached: bool,
) -> RobotChecks:
    """:func:`robot_checks` with a findings cache of its own (``cached``; False:
    ``--no-cache``), made where files are checked against a robot: a syntax-level run imports
    no cache."""
    from motiontool.kinematics.checks.findings_cache import FindingsCache

    cache = FindingsCache() if cached else None
    return robot_checks(robot, checks, timestep, tolerance=tolerance, cache=cache)


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
    ones may be skipped; ``cache``: the findings cache (None: ``--no-cache``). The checks are
    imported here, where files are checked against a robot."""
    from motiontool.kinematics.checks.runner import CheckUnavailableError, RobotChecks

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
