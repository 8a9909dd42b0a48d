"""Executors: how the runs of a batch are carried out, behind one protocol.

An :class:`Executor` takes a runner (a picklable module-level function) and its tasks, and
yields one :class:`Outcome` per task as it ends, in any order. Two exist: ``local``
(:func:`motiontool.sim.pool.run_pool`, a process pool on this machine) and ``ray``
(:func:`motiontool.sim._ray.run_ray`, a Ray cluster). Both call the runner through
:func:`call_runner`, so a run that raises is reported the same way on either.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from typing import Any, Literal, Protocol

from motiontool.motionfmt.errors import MotionToolError

__all__ = [
    "EXECUTORS",
    "MAX_TIMEOUT_S",
    "Executor",
    "Outcome",
    "Status",
    "call_runner",
    "error_reason",
    "get_executor",
]

MAX_TIMEOUT_S = 7 * 24 * 3600.0
"""The longest wall-clock limit of one run, in s (a week): the process pool waits on its
workers with ``poll``, whose limit in ms is a C ``int`` (about 24 days)."""

Status = Literal["done", "error", "crashed", "timeout"]
"""How a task ended: ``done`` (the runner returned), ``error`` (it raised), ``crashed`` (its
worker died) or ``timeout`` (it outlived the time limit; its worker was killed)."""


@dataclass(frozen=True)
class Outcome:
    """How one task ended.

    Attributes:
        index: the task's position in the input.
        status: see :data:`Status`.
        value: the runner's return value when ``done``, else None.
        reason: a one-line explanation otherwise.
        wall_s: wall-clock seconds the task took.
    """

    index: int
    status: Status
    value: Any = None
    reason: str = ""
    wall_s: float = 0.0


class Executor(Protocol):
    """Runs ``runner(task)`` for every task, at most ``jobs`` at a time, each within
    ``timeout_s`` wall-clock seconds (None: no limit); yields the outcomes as they end."""

    def __call__(
        self,
        runner: Callable[[Any], Any],
        tasks: Sequence[Any],
        *,
        jobs: int,
        timeout_s: float | None,
    ) -> Iterator[Outcome]: ...


def error_reason(exc: BaseException) -> str:
    """One line for a report: the message the runner raised (a diagnostic such as
    ``wave.motion:3:14: expected ...``), never the exception class or a source location."""
    lines = str(exc).strip().splitlines()
    return lines[0] if lines else "the run stopped on an unexpected error (no message)"


def call_runner(runner: Callable[[Any], Any], task: Any) -> tuple[Status, Any, str]:
    """``("done", runner(task), "")``, or ``("error", None, reason)`` when the runner raises.

    Any exception: a worker reports every run's end to the batch, which goes on with the
    others; the run's reason is the exception's message (:func:`error_reason`).
    """
    try:
        return "done", runner(task), ""
    except Exception as exc:  # one run's failure, reported with the others: never lost
        return "error", None, error_reason(exc)


def _local(ray_address: str | None) -> Executor:
    from motiontool.sim.pool import run_pool

    return run_pool


def _ray(ray_address: str | None) -> Executor:
    from functools import partial

    from motiontool.sim._ray import run_ray

    return partial(run_ray, address=ray_address)


_FACTORIES: dict[str, Callable[[str | None], Executor]] = {"local": _local, "ray": _ray}
"""Executor name -> factory (imports lazily). A new executor is a module with a function that
satisfies :class:`Executor`, and one entry here."""

EXECUTORS = tuple(_FACTORIES)
"""Executor names for :func:`get_executor`."""


def get_executor(name: str, *, ray_address: str | None = None) -> Executor:
    """The executor called ``name`` (:data:`EXECUTORS`); ``ray_address``: the Ray cluster
    (``auto``, ``ray://...``; None starts a local one).

    Raises:
        MotionToolError: an unknown name.
    """
    factory = _FACTORIES.get(name)
    if factory is None:
        raise MotionToolError(f"unknown executor {name!r}; choose {' or '.join(EXECUTORS)}")
    return factory(ray_address)
