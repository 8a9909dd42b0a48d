"""The ``motiontool`` command line: one file per command, registered here."""

from __future__ import annotations

import contextlib
import contextvars
import functools
import os
import signal
import sys
import traceback
from collections.abc import Callable, Sequence
from typing import Annotated, Any, NoReturn, TypeVar

import typer
from typer._click.exceptions import (  # typer >= 0.26 carries its own Click
    ClickException,
    NoArgsIsHelpError,
    UsageError,
)
from typer.core import TyperGroup

from motiontool import __version__
from motiontool.cli import (
    batch,
    cache,
    codes,
    concat,
    convert,
    diff,
    expect,
    generate,
    info,
    mirror,
    play,
    plot,
    resample,
    retime,
    robots,
    rule,
    sample,
    scale,
    server,
    trim,
    validate,
)
from motiontool.cli.color import set_no_color
from motiontool.cli.options import error_line
from motiontool.motionfmt.errors import MotionToolError

__all__ = ["app", "main"]

F = TypeVar("F", bound=Callable[..., Any])

_debug: contextvars.ContextVar[bool] = contextvars.ContextVar("motiontool_debug", default=False)


class _Group(TyperGroup):
    """The root command group: a mistake in the options (a value out of range, a missing
    argument, an unknown option) is one ``motiontool: error:`` line naming what is wrong and the
    ``--help`` to read, like every other error of the tool (Click prints a usage block)."""

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
            typer.echo(f"motiontool: error: {what}{sep}see '{where} --help'", err=True)
            code = exc.exit_code
        except ClickException as exc:
            typer.echo(f"motiontool: error: {exc.format_message()}", err=True)
            code = exc.exit_code
        except typer.Abort:  # end of input at a prompt (there is none) or Ctrl-C outside a command
            typer.echo("motiontool: error: interrupted", err=True)
            code = 128 + signal.SIGINT
        code = code if isinstance(code, int) else 0
        if standalone_mode:
            sys.exit(code)
        return code


app = typer.Typer(
    cls=_Group,
    name="motiontool",
    help=(
        "Lint, transform and simulate Webots .motion files.\n\n"
        "Exit codes: 0 clean, 1 findings (or a failed run), 2 usage or I/O error."
    ),
    no_args_is_help=True,
    add_completion=True,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
    context_settings={"help_option_names": ["-h", "--help"]},
)


def _guard(func: F) -> F:
    """Turn a :class:`MotionToolError` into one line on stderr and exit code 2, Ctrl-C into
    ``interrupted`` and 130, a closed pipe on stdout into a quiet 141 (with ``--debug``, the
    traceback first, then the same line and exit code)."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except MotionToolError as exc:
            if _debug.get():
                traceback.print_exc(file=sys.stderr)
            typer.echo(f"motiontool: error: {error_line(exc)}", err=True)
            raise typer.Exit(2) from None
        except BrokenPipeError:  # the reader went away (| head): quiet, as a SIGPIPE ends it
            _quiet_stdout()
            raise typer.Exit(128 + signal.SIGPIPE) from None
        except KeyboardInterrupt:  # before Click turns it into 'Aborted!' and exit 1
            if _debug.get():
                traceback.print_exc(file=sys.stderr)
            typer.echo("motiontool: error: interrupted", err=True)
            raise typer.Exit(128 + signal.SIGINT) from None

    return wrapper  # type: ignore[return-value]


def _version(value: bool) -> None:
    if value:
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


_COMMANDS: list[tuple[str, Callable[..., Any]]] = [
    ("validate", validate.validate_command),
    ("info", info.info_command),
    ("sample", sample.sample_command),
    ("codes", codes.codes_command),
    ("rule", rule.rule_command),
    ("generate", generate.generate_command),
    ("play", play.play_command),
    ("batch", batch.batch_command),
    ("cache", cache.cache_command),
    ("expect", expect.expect_command),
    ("diff", diff.diff_command),
    ("resample", resample.resample_command),
    ("retime", retime.retime_command),
    ("mirror", mirror.mirror_command),
    ("concat", concat.concat_command),
    ("trim", trim.trim_command),
    ("scale", scale.scale_command),
    ("plot", plot.plot_command),
    ("convert", convert.convert_command),
    ("server", server.server_command),
]
for _name, _command in _COMMANDS:
    app.command(_name)(_guard(_command))
app.add_typer(robots.build_app(_guard), name="robots")


def _report(exc: BaseException, line: str, code: int) -> NoReturn:
    if _debug.get():
        traceback.print_exception(exc, file=sys.stderr)
    if line:
        with contextlib.suppress(OSError):
            typer.echo(f"motiontool: error: {line}", err=True)
    sys.exit(code)


def _quiet_stdout() -> None:
    """Point standard output at the null device, so that the interpreter's last flush of what
    could not be written raises nothing more."""
    with contextlib.suppress(OSError, ValueError):
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, sys.stdout.fileno())
        os.close(null)


def main() -> None:
    """Console entry point: every failure ends as one ``motiontool: error:`` line (a traceback
    too with ``--debug``) and a non-zero exit code.

    - :class:`MotionToolError` raised outside a command (commands go through ``_guard``): 2;
    - standard output that cannot be written (``> /dev/full``): 2, naming the reason;
    - a reader that went away (``| head -1``): quiet, 141 as for a process that SIGPIPE ends;
    - Ctrl-C: ``interrupted``, 130.
    """
    try:
        try:
            app(prog_name="motiontool")
        finally:
            sys.stdout.flush()  # a failed write surfaces here, not in the interpreter's exit
    except MotionToolError as exc:
        _report(exc, error_line(exc), 2)
    except BrokenPipeError as exc:
        _quiet_stdout()
        _report(exc, "", 128 + signal.SIGPIPE)
    except KeyboardInterrupt as exc:
        _report(exc, "interrupted", 128 + signal.SIGINT)
    except OSError as exc:  # a stream write: standard output or error
        _quiet_stdout()
        where = f"'{exc.filename}'" if exc.filename else "to standard output"
        _report(exc, f"cannot write {where}: {exc.strerror or exc}", 2)
