"""The ``motiontool`` command line: one file per command, registered here."""

from __future__ import annotations

import contextlib
import contextvars
import functools
import importlib
import sys
import traceback
from collections.abc import Callable, Iterator, MutableMapping, Sequence
from typing import Annotated, Any, NoReturn, TypeVar

import typer
from typer._click.core import Command, Context
from typer._click.exceptions import (  # typer >= 0.26 carries its own Click
    ClickException,
    NoArgsIsHelpError,
    UsageError,
)
from typer._click.formatting import HelpFormatter
from typer._click.utils import make_default_short_help
from typer.core import TyperGroup
from typer.models import CommandInfo, TyperInfo

from motiontool import exit_codes
from motiontool.cli import process
from motiontool.cli.color import set_no_color
from motiontool.errors import MotionToolError

__all__ = ["app", "main"]

F = TypeVar("F", bound=Callable[..., Any])

_debug: contextvars.ContextVar[bool] = contextvars.ContextVar("motiontool_debug", default=False)


class _Group(TyperGroup):
    """The root command group: a mistake in the options (a value out of range, a missing
    argument, an unknown option) is one ``motiontool: error:`` line naming what is wrong and the
    ``--help`` to read, like every other error of the tool (Click prints a usage block).

    Its commands are :data:`_COMMANDS`, each imported when it is first used."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.commands = _LazyCommands(self.commands)

    def list_commands(self, ctx: Context) -> list[str]:
        """The command names in :data:`_COMMANDS` order (Typer's lists them by building
        each)."""
        return list(self.commands)

    def format_commands(self, ctx: Context, formatter: HelpFormatter) -> None:
        """The list of commands in ``--help``, from their summaries: nothing is imported."""
        commands = self.commands
        assert isinstance(commands, _LazyCommands)
        names = [name for name in self.list_commands(ctx) if not commands.hidden(name)]
        if names:
            limit = formatter.width - 6 - max(len(name) for name in names)
            with formatter.section("Commands"):
                formatter.write_dl([(name, commands.summary(name, limit)) for name in names])

    def main(
        self,
        args: Sequence[str] | None = None,
        prog_name: str | None = None,
        complete_var: str | None = None,
        standalone_mode: bool = True,
        windows_expand_args: bool = True,
        **extra: Any,
    ) -> Any:
        try:
            code = super().main(
                args,
                prog_name,
                complete_var,
                standalone_mode=False,
                windows_expand_args=windows_expand_args,
                **extra,
            )
        except NoArgsIsHelpError as exc:
            exc.show()
            code = exc.exit_code
        except UsageError as exc:
            where = exc.ctx.command_path if exc.ctx is not None else "motiontool"
            what = exc.format_message().rstrip(".")
            what = what[:1].lower() + what[1:]
            sep = " " if what.endswith("?") else "; "
            _say(f"{what}{sep}see '{where} --help'")
            code = exc.exit_code
        except ClickException as exc:
            _say(exc.format_message())
            code = exc.exit_code
        except typer.Abort:  # end of input at a prompt (there is none) or Ctrl-C outside a command
            typer.echo("motiontool: error: interrupted", err=True)
            code = exit_codes.INTERRUPTED
        code = code if isinstance(code, int) else 0
        if standalone_mode:
            sys.exit(code)
        return code


app = typer.Typer(
    cls=_Group,
    name="motiontool",
    help=f"Lint, transform and simulate Webots .motion files.\n\n{exit_codes.SUMMARY}",
    no_args_is_help=True,
    add_completion=True,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
    context_settings={"help_option_names": ["-h", "--help"]},
)


def _guard(func: F) -> F:
    """Turn a :class:`MotionToolError` (and running out of memory) into one line on stderr and
    exit code 2, Ctrl-C into ``interrupted`` and 130, a closed pipe on stdout into a quiet 141
    (with ``--debug``, the traceback first, then the same line and exit code)."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        process.started()
        try:
            return func(*args, **kwargs)
        except MotionToolError as exc:
            if _debug.get():
                traceback.print_exc(file=sys.stderr)
            _say(_error_line(exc))
            raise typer.Exit(exit_codes.ERROR) from None
        except BrokenPipeError:  # the reader went away (| head): quiet, as a SIGPIPE ends it
            process.quiet_stdout()
            raise typer.Exit(exit_codes.BROKEN_PIPE) from None
        except MemoryError:  # what no guard foresaw: one line, never a traceback
            if _debug.get():
                traceback.print_exc(file=sys.stderr)
            typer.echo(
                "motiontool: error: out of memory: the input is too large for this machine",
                err=True,
            )
            raise typer.Exit(exit_codes.ERROR) from None
        except KeyboardInterrupt:  # before Click turns it into 'Aborted!' and exit 1
            if _debug.get():
                traceback.print_exc(file=sys.stderr)
            typer.echo("motiontool: error: interrupted", err=True)
            raise typer.Exit(exit_codes.INTERRUPTED) from None

    return wrapper  # type: ignore[return-value]


def _say(line: str) -> None:
    """``motiontool: error: LINE`` on stderr, with what it echoes of the input shown safely
    (:func:`motiontool.cli.text.shown`: control characters escaped, a long name or value cut;
    imported here, only when there is an error to say)."""
    from motiontool.cli.text import shown

    typer.echo(f"motiontool: error: {shown(line)}", err=True)


def _error_line(exc: MotionToolError) -> str:
    """The one line for ``exc``, in the CLI's words (:func:`motiontool.cli.options.error_line`,
    imported here: it brings the robots, which ``--help`` does not need)."""
    from motiontool.cli.options import error_line

    return error_line(exc)


def _version(value: bool) -> None:
    if value:
        from motiontool import __version__

        typer.echo(f"motiontool {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    ctx: typer.Context,
    debug: Annotated[
        bool,
        typer.Option("--debug", help="Print an error's traceback before its one-line message."),
    ] = False,
    version: Annotated[
        bool,
        typer.Option(
            "--version",
            "-V",
            callback=_version,
            is_eager=True,
            help="Print the version and exit.",
        ),
    ] = False,
    no_color: Annotated[
        bool,
        typer.Option(
            "--no-color",
            help="No ANSI colours, even on a terminal (also: the NO_COLOR environment variable). "
            "Files and pipes never get colours.",
        ),
    ] = False,
) -> None:
    _debug.set(debug)
    set_no_color(no_color)  # see motiontool.cli.color
    if no_color:
        ctx.color = False  # and typer.echo strips colour in the sub-command's context too


_COMMANDS: dict[str, tuple[str, str, str]] = {
    # name: (module of motiontool.cli, its command function (robots: the sub-app's builder),
    #        the start of the function's docstring: what 'motiontool --help' lists)
    "validate": (
        "validate",
        "validate_command",
        "Check motion files as Webots reads them, then against the robot; every problem, with",
    ),
    "info": (
        "info",
        "info_command",
        "Joints, poses, duration, pose spacing and undefined cells of a motion file, and the",
    ),
    "sample": (
        "sample",
        "sample_command",
        "Print the targets a Webots controller stepping every --timestep ms sends, step by",
    ),
    "codes": (
        "rule",
        "codes_command",
        "List every diagnostic code with its default severity and meaning.",
    ),
    "rule": (
        "rule",
        "rule_command",
        "Explain a diagnostic code: its severity, what Webots does, an example that triggers",
    ),
    "generate": (
        "generate",
        "generate_command",
        "Generate a motion of the project's library (joint values from inverse kinematics",
    ),
    "play": (
        "play",
        "play_command",
        "Play motion files in MuJoCo as a Webots controller would, live in a Rerun viewer or",
    ),
    "watch": (
        "watch",
        "watch_command",
        "Validate motion files on every save and play each clean one live as a new take.",
    ),
    "batch": (
        "batch",
        "batch_command",
        "Play every file headless on every robot and perturbation sample; exit 1 if any run",
    ),
    "cache": (
        "cache",
        "cache_command",
        "The result caches: 'info' prints each one's folder, results and size; 'clean' removes",
    ),
    "expect": (
        "expect",
        "expect_command",
        "Propose expectations (a motions.toml sidecar) from motion names, for people to review:",
    ),
    "diff": (
        "diff",
        "diff_command",
        "Compare what two motion files command, joint by joint (matched by name).",
    ),
    "resample": (
        "resample",
        "resample_command",
        "Put keyframes on a uniform time grid, or drop the ones the motion does not need.",
    ),
    "retime": (
        "retime",
        "retime_command",
        "Change pose times only, never values: --speed, --duration or --fit-limits.",
    ),
    "mirror": (
        "mirror",
        "mirror_command",
        "Mirror a motion left/right: swap each L/R pair, negate the joints whose mirror image",
    ),
    "concat": (
        "concat",
        "concat_command",
        "Join motions one after another, each transition as short as the robot's limits allow.",
    ),
    "trim": (
        "trim",
        "trim_command",
        "Keep the part of a motion between --from and --to (playback times).",
    ),
    "scale": (
        "scale",
        "scale_command",
        "Scale a motion's amplitude about a reference pose, clipping to the robot's limits.",
    ),
    "plot": (
        "plot",
        "plot_command",
        "Draw every joint over time into a PNG: grouped by limb (head, arms, legs, hands for",
    ),
    "convert": (
        "convert",
        "convert_command",
        "Convert a motion to CSV, NPZ, NAOqi, URScript, a ROS 2 trajectory or bag, or a CSV,",
    ),
    "server": (
        "server",
        "server_command",
        "Run the Language Server on stdin/stdout, for editors: the findings of ``validate``",
    ),
    "robots": (
        "robots",
        "build_app",
        "The built-in robots (listed without a sub-command), their joints and models.",
    ),
}
"""Every command, imported only when it runs or its help is shown (``motiontool --help`` and
``motiontool validate`` import nothing of ``play``, ``convert``, ...): a registry, one line a
command. The summaries are checked against the docstrings (``tests/cli/test_startup.py``)."""


def _load(name: str) -> Command:
    """Command ``name`` of :data:`_COMMANDS`, imported and built as Typer builds it."""
    module_name, attr, _summary = _COMMANDS[name]
    module = importlib.import_module(f"motiontool.cli.{module_name}")
    if name == "robots":
        return typer.main.get_group_from_info(
            TyperInfo(module.build_app(_guard), name=name),
            pretty_exceptions_short=app.pretty_exceptions_short,
            suggest_commands=True,
            rich_markup_mode=app.rich_markup_mode,
        )
    return typer.main.get_command_from_info(
        CommandInfo(name=name, callback=_guard(getattr(module, attr))),
        pretty_exceptions_short=app.pretty_exceptions_short,
        rich_markup_mode=app.rich_markup_mode,
    )


class _LazyCommands(MutableMapping[str, Command]):
    """The root group's commands: those of :data:`_COMMANDS` built on first use, in its
    order, then any added."""

    def __init__(self, added: MutableMapping[str, Command]) -> None:
        self.built: dict[str, Command] = dict(added)

    def __getitem__(self, name: str) -> Command:
        if name not in self.built and name in _COMMANDS:
            self.built[name] = _load(name)
        return self.built[name]

    def __setitem__(self, name: str, command: Command) -> None:
        self.built[name] = command

    def __delitem__(self, name: str) -> None:
        del self.built[name]

    def __iter__(self) -> Iterator[str]:
        yield from _COMMANDS
        yield from (name for name in self.built if name not in _COMMANDS)

    def __len__(self) -> int:
        return len(_COMMANDS) + sum(1 for name in self.built if name not in _COMMANDS)

    def hidden(self, name: str) -> bool:
        """Whether ``--help`` leaves the command out (none of :data:`_COMMANDS` is hidden)."""
        return name not in _COMMANDS and self.built[name].hidden

    def summary(self, name: str, limit: int) -> str:
        """What ``--help`` says of the command in ``limit`` characters, as Click shortens its
        help, without importing it."""
        if name not in _COMMANDS:
            return self.built[name].get_short_help_str(limit)
        return make_default_short_help(_COMMANDS[name][2], limit)


def _report(exc: BaseException, line: str, code: int) -> NoReturn:
    if _debug.get():
        traceback.print_exception(exc, file=sys.stderr)
    if line:
        with contextlib.suppress(OSError):
            _say(line)
    sys.exit(code)


def main() -> None:
    """Console entry point: every failure ends as one ``motiontool: error:`` line (a traceback
    too with ``--debug``) and a non-zero exit code.

    - :class:`MotionToolError` raised outside a command (commands go through ``_guard``): 2;
    - standard output that cannot be written (``> /dev/full``, ``>&-``): 2, naming the reason;
    - a reader that went away (``| head -1``): quiet, 141 as for a process that SIGPIPE ends;
    - Ctrl-C: ``interrupted``, 130; SIGTERM: ``terminated``, 143; SIGHUP: ``hangup``, 129
      (temporary files removed first).
    """
    process.skip_exit_collection()
    process.hold_standard_streams()
    process.catch_endings(_debug.get)
    try:
        try:
            app(prog_name="motiontool")
        finally:
            process.flush_stdout()
    except MotionToolError as exc:
        _report(exc, _error_line(exc), exit_codes.ERROR)
    except BrokenPipeError as exc:
        process.quiet_stdout()
        _report(exc, "", exit_codes.BROKEN_PIPE)
    except KeyboardInterrupt as exc:
        _report(exc, "interrupted", exit_codes.INTERRUPTED)
    except process.Ended as exc:
        process.caught(exc)
        _report(exc, process.ENDINGS[exc.signum], exit_codes.BY_SIGNAL[exc.signum])
    except OSError as exc:  # a stream write (standard output), or what no command foresaw
        process.quiet_stdout()
        what = f"access '{exc.filename}'" if exc.filename else "write to standard output"
        _report(exc, f"cannot {what}: {exc.strerror or exc}", exit_codes.ERROR)
