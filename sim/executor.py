"""Executors: how the runs of a batch are carried out, behind one protocol.

An :class:`Executor` takes a runner (a picklable module-level function) and its tasks, and
yields one :class:`Outcome` per task as it ends, in any order. :data:`REGISTRY` is the one
table of them: ``local`` (:func:`motiontool.sim.pool.run_pool`, a process pool on this
machine) and ``ray`` (:func:`motiontool.sim._ray.run_ray`, a Ray cluster). Each calls the
runner through :func:`call_runner`, so a run that raises is reported the same way on any.

Adding an executor is a module with a function that satisfies :class:`Executor` and one row in
:data:`REGISTRY` (its extra, if it needs a library, in ``pyproject.toml`` and
:data:`motiontool.extras.EXTRAS`): ``batch --executor`` offers it, its help and its
missing-library message come from the row, and the executor tests iterate over the table.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any, Literal, Protocol

from motiontool.errors import MotionToolError, OutputError

__all__ = [
    "DEFAULT_JOBS",
    "EXECUTORS",
    "MAX_TIMEOUT_S",
    "REGISTRY",
    "ClusterSetupError",
    "Executor",
    "ExecutorInfo",
    "Outcome",
    "Parallelism",
    "Status",
    "call_runner",
    "error_reason",
    "executor_info",
    "get_executor",
    "session",
]

MAX_TIMEOUT_S = 7 * 24 * 3600.0
"""The longest wall-clock limit of one run, in s (a week): the process pool waits on its
workers with ``poll``, whose limit in ms is a C ``int`` (about 24 days)."""

Status = Literal["done", "error", "unwritten", "crashed", "timeout"]
"""How a task ended: ``done`` (the runner returned), ``error`` (it raised), ``unwritten`` (it
raised :class:`~motiontool.errors.OutputError`: a file it writes could not be written, a full
disk), ``crashed`` (its worker died) or ``timeout`` (it outlived the time limit; its worker was
killed)."""


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


class ClusterSetupError(MotionToolError):
    """A cluster whose workers cannot play the batch at all (they cannot import motiontool or
    its simulation libraries; Ray cannot set up their runtime environment): the batch stops.

    Attributes:
        problem: what is wrong, without the remedy.
        remedy: whether the remedy is to give the cluster motiontool (else the message is
            the problem alone).
    """

    def __init__(self, problem: str, *, remedy: bool = True):
        more = (
            ": install motiontool[sim] in the cluster's image, or ship it in a Ray runtime"
            " environment (docs/ray.md)"
        )
        super().__init__(problem + (more if remedy else ""))
        self.problem = problem
        self.remedy = remedy


@dataclass(frozen=True)
class Parallelism:
    """How many runs of a batch go at once, and why.

    Attributes:
        in_flight: the runs at once.
        cpus: the CPUs of the cluster (None: a process pool, on this machine).
        asked: the runs at once the caller asked for (None: the default).
    """

    in_flight: int
    cpus: int | None = None
    asked: int | None = None


DEFAULT_JOBS = 2
"""The local pool's workers when the caller names none."""


@contextmanager
def session(
    name: str,
    jobs: int | None,
    *,
    address: str | None = None,
    runtime_env: dict[str, object] | None = None,
) -> Iterator[Parallelism]:
    """Executor ``name`` made ready for a batch in the ``with`` block (Ray: connected, with
    ``runtime_env``), and its :class:`Parallelism`: the local pool's ``jobs`` workers
    (:data:`DEFAULT_JOBS` for None), a Ray cluster's CPUs at most ``jobs``.

    Raises:
        MotionToolError: an unknown name; a cluster that cannot be reached or refuses
            ``runtime_env``.
    """
    if not executor_info(name).takes_address:
        yield Parallelism(jobs or DEFAULT_JOBS, None, jobs)
        return
    from motiontool.sim._ray import ray_session

    with ray_session(address, jobs, runtime_env) as parallel:
        yield parallel


def error_reason(exc: BaseException) -> str:
    """One line for a report: the message the runner raised (a diagnostic such as
    ``wave.motion:3:14: expected ...``), never the exception class or a source location."""
    lines = str(exc).strip().splitlines()
    return lines[0] if lines else "the run stopped on an unexpected error (no message)"


def call_runner(runner: Callable[[Any], Any], task: Any) -> tuple[Status, Any, str]:
    """``("done", runner(task), "")``, or ``("error", None, reason)`` when the runner raises
    (``"unwritten"`` for an :class:`~motiontool.errors.OutputError`).

    Any exception: a worker reports every run's end to the batch, which goes on with the
    others (or stops, on a file it cannot write); the run's reason is the exception's message
    (:func:`error_reason`).
    """
    try:
        return "done", runner(task), ""
    except OutputError as exc:  # a full disk, not the run's fault: the batch stops
        return "unwritten", None, error_reason(exc)
    except Exception as exc:  # one run's failure, reported with the others: never lost
        return "error", None, error_reason(exc)


def _local(address: str | None) -> Executor:
    from motiontool.sim.pool import run_pool

    return run_pool


def _ray(address: str | None) -> Executor:
    from functools import partial

    from motiontool.sim._ray import run_ray

    return partial(run_ray, address=address)


@dataclass(frozen=True)
class ExecutorInfo:
    """One executor of :data:`REGISTRY`.

    Attributes:
        name: what ``batch --executor`` takes.
        summary: what it runs on, for the help (``a process pool on this machine``).
        factory: the executor for a cluster address (None: its default), importing lazily.
        extra: the ``motiontool`` extra that brings its library (None: the core has it).
        takes_address: whether it runs on a cluster named by an address (``--ray-address``).
    """

    name: str
    summary: str
    factory: Callable[[str | None], Executor]
    extra: str | None = None
    takes_address: bool = False


REGISTRY: tuple[ExecutorInfo, ...] = (
    ExecutorInfo("local", "a process pool on this machine", _local),
    ExecutorInfo("ray", "a Ray cluster", _ray, extra="ray", takes_address=True),
)
"""Every executor, the default first."""

EXECUTORS = tuple(e.name for e in REGISTRY)
"""Executor names for :func:`get_executor`."""


def executor_info(name: str) -> ExecutorInfo:
    """The row of executor ``name``.

    Raises:
        MotionToolError: an unknown name (the message lists the executors).
    """
    for info in REGISTRY:
        if info.name == name:
            return info
    raise MotionToolError(f"unknown executor {name!r}; choose {' or '.join(EXECUTORS)}")


def get_executor(name: str, *, ray_address: str | None = None) -> Executor:
    """The executor called ``name`` (:data:`EXECUTORS`); ``ray_address``: the cluster of an
    executor that takes one (Ray: ``auto``, ``ray://...``; None starts a local one).

    Raises:
        MotionToolError: an unknown name.
    """
    return executor_info(name).factory(ray_address)
