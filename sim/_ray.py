"""The Ray executor (the only module importing ray): the same runs, on a Ray cluster.

Ray is an optional extra (``pip install 'motiontool[ray]'``). Each run is one Ray task; at most
``jobs`` are in flight; a task that exceeds the timeout is cancelled (its worker is killed) and
reported as ``timeout``; a task whose worker dies is reported as ``crashed``. Ray ships its own
types (``py.typed``): the module is imported directly (lazily), so mypy checks every call.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator, Sequence
from typing import TYPE_CHECKING, TypeVar

from motiontool.errors import MotionToolError
from motiontool.extras import require
from motiontool.sim.executor import Outcome, Status, call_runner

if TYPE_CHECKING:
    from ray import ObjectRef

    #: A task in flight: what :func:`~motiontool.sim.executor.call_runner` returns, once ready.
    _Ref = ObjectRef[tuple[Status, object, str]]

__all__ = ["run_ray"]

_LOST = "the Ray task failed: its worker died or its result was lost"

Task = TypeVar("Task")
Result = TypeVar("Result")


def run_ray(
    runner: Callable[[Task], Result],
    tasks: Sequence[Task],
    *,
    jobs: int = 2,
    timeout_s: float | None = None,
    address: str | None = None,
) -> Iterator[Outcome]:
    """Run ``runner(task)`` for every task as Ray tasks, at most ``jobs`` in flight; yield
    outcomes as they end (an :class:`~motiontool.sim.executor.Executor`).

    Connects to ``address`` (``auto`` finds a running cluster) or, when None, starts a local
    Ray instance for the duration of the call.
    """
    require("ray", "ray", "the Ray executor")
    import ray

    started_here = not ray.is_initialized()
    if started_here:
        try:
            if address is None:
                ray.init(num_cpus=max(jobs, 1), include_dashboard=False, log_to_driver=False)
            else:
                ray.init(address=address, include_dashboard=False, log_to_driver=False)
        except (ConnectionError, RuntimeError, ValueError) as exc:
            raise MotionToolError(f"cannot reach the Ray cluster at {address!r}: {exc}") from exc
    remote = ray.remote(max_retries=0)(call_runner)
    try:
        pending = list(range(len(tasks)))
        in_flight: dict[_Ref, tuple[int, float]] = {}
        while pending or in_flight:
            while pending and len(in_flight) < jobs:
                i = pending.pop(0)
                in_flight[remote.remote(runner, tasks[i])] = (i, time.monotonic())
            yield from _collect(in_flight, timeout_s)
    finally:
        if started_here:
            ray.shutdown()


def _collect(
    in_flight: dict[_Ref, tuple[int, float]], timeout_s: float | None
) -> Iterator[Outcome]:
    """Wait for the first task in flight to end or time out; yield (and drop) every task that
    has ended, and cancel those past the timeout."""
    import ray

    wait_s = None
    if timeout_s is not None:
        first = min(t for _, t in in_flight.values())
        wait_s = max(0.0, first + timeout_s - time.monotonic())
    ready, _ = ray.wait(list(in_flight), num_returns=1, timeout=wait_s)
    now = time.monotonic()
    for ref in ready:
        i, t0 = in_flight.pop(ref)
        try:
            status, value, reason = ray.get(ref)
        except ray.exceptions.RayError:
            status, value, reason = "crashed", None, _LOST
        yield Outcome(i, status, value, reason, now - t0)
    if timeout_s is None:
        return
    for ref, (i, t0) in list(in_flight.items()):
        if now - t0 >= timeout_s:
            ray.cancel(ref, force=True)
            del in_flight[ref]
            yield Outcome(i, "timeout", None, f"exceeded the {timeout_s:g} s timeout", now - t0)
