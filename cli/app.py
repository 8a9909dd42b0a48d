"""The ``motiontool`` command line: one file per command, registered here."""

from __future__ import annotations

import contextvars
import functools
import sys
import traceback
from collections.abc import Callable
from typing import Annotated, Any, TypeVar

import typer

from motiontool import __version__
from motiontool.cli import (
    batch,
    codes,
    concat,
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
    sample,
    scale,
    trim,
    validate,
)
from motiontool.cli.color import set_no_color
from motiontool.cli.options import error_line
from motiontool.motionfmt.errors import MotionToolError

__all__ = ["app", "main"]

F = TypeVar("F", bound=Callable[..., Any])

_debug: contextvars.ContextVar[bool] = contextvars.ContextVar("motiontool_debug", default=False)

app = typer.Typer(
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
    """Turn a :class:`MotionToolError` into one line on stderr and exit code 2 (with
    ``--debug``, the traceback first, then the same line and exit code)."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except MotionToolError as exc:
            if _debug.get():
                traceback.print_exc(file=sys.stderr)
            typer.echo(f"motiontool: error: {error_line(exc)}", err=True)
            raise typer.Exit(2) from None

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
    ("generate", generate.generate_command),
    ("play", play.play_command),
    ("batch", batch.batch_command),
    ("expect", expect.expect_command),
    ("diff", diff.diff_command),
    ("resample", resample.resample_command),
    ("retime", retime.retime_command),
    ("mirror", mirror.mirror_command),
    ("concat", concat.concat_command),
    ("trim", trim.trim_command),
    ("scale", scale.scale_command),
    ("plot", plot.plot_command),
]
for _name, _command in _COMMANDS:
    app.command(_name)(_guard(_command))
app.add_typer(robots.build_app(_guard), name="robots")


def main() -> None:
    """Console entry point."""
    try:
        app(prog_name="motiontool")
    except MotionToolError as exc:  # raised outside a command (commands go through _guard)
        if _debug.get():
            traceback.print_exc(file=sys.stderr)
        typer.echo(f"motiontool: error: {error_line(exc)}", err=True)
        sys.exit(2)
