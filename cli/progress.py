"""Progress of a long single job on a terminal (``validate`` of a large file, ``play --loop``,
``mirror``): a spinner with what is being done and the elapsed time on standard error, drawn only
when standard error is a terminal and gone when the job ends; nothing in a pipe, a file or CI
logs, nor with ``NO_COLOR`` or ``--no-color`` (it draws with terminal escapes). ``batch`` has
its own bar, with its runs' outcomes."""

from __future__ import annotations

import contextlib
import sys
from collections.abc import Callable, Iterator

from motiontool.cli.color import color_enabled

__all__ = ["Step", "progress"]

Step = Callable[[str], None]
"""Says what the job is doing now (``big.motion: collision``)."""


def _quiet(label: str) -> None:
    """A :data:`Step` that shows nothing."""


@contextlib.contextmanager
def progress(title: str) -> Iterator[Step]:
    """A :data:`Step` for a job called ``title`` (``validate``): on a terminal, each call
    replaces the spinner's text with ``title: label``; elsewhere it does nothing."""
    if not (sys.stderr.isatty() and color_enabled(sys.stderr)):
        yield _quiet
        return
    from rich.console import Console
    from rich.progress import Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

    columns = (SpinnerColumn(), TextColumn("{task.description}"), TimeElapsedColumn())
    with Progress(*columns, console=Console(stderr=True), transient=True) as bar:
        task = bar.add_task(title, total=None)

        def step(label: str) -> None:
            bar.update(task, description=f"{title}: {label}")

        yield step
