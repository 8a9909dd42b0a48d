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


class Step:
    """Says what the job is doing now (``step("big.motion: collision")``); :meth:`stop` ends
    the display early (before a report is written to the same terminal). Shows nothing unless
    made by :func:`progress` on a terminal."""

    def __init__(
        self,
        show: Callable[[str], None] | None = None,
        stop: Callable[[], None] | None = None,
    ) -> None:
        self._show = show
        self._stop = stop

    def __call__(self, label: str) -> None:
        if self._show is not None:
            self._show(label)

    def stop(self) -> None:
        """Take the display off the terminal; what the job says from now on is not shown."""
        if self._stop is not None:
            self._stop()
        self._show = self._stop = None


@contextlib.contextmanager
def progress(title: str) -> Iterator[Step]:
    """A :class:`Step` for a job called ``title`` (``validate``): on a terminal, each call
    replaces the spinner's text with ``title: label``; elsewhere it does nothing."""
    if not (sys.stderr.isatty() and color_enabled(sys.stderr)):
        yield Step()
        return
    from rich.console import Console
    from rich.progress import Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

    columns = (SpinnerColumn(), TextColumn("{task.description}"), TimeElapsedColumn())
    with Progress(*columns, console=Console(stderr=True), transient=True) as bar:
        task = bar.add_task(title, total=None)
        yield Step(lambda label: bar.update(task, description=f"{title}: {label}"), bar.stop)
