"""The Ray executor (the only module importing ray): the same runs, on a Ray cluster.

Ray is an optional extra (``pip install 'motiontool[ray]'``). Each run is one Ray task; at most
``jobs`` are in flight; a task that exceeds the timeout is cancelled (its worker is killed) and
reported as ``timeout``; a task whose worker dies is reported as ``crashed``. A batch run travels
as bytes (:mod:`motiontool.sim.shipped`): packed when it is sent, so the driver holds only the
runs in flight; its recordings come back through Ray's object store, fetched and written one at
a time. With no ``jobs``, the cluster's CPUs are the runs in flight. Ray ships its own
types (``py.typed``): the module is imported directly (lazily), so mypy checks every call.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator, Sequence
from functools import partial
from typing import TYPE_CHECKING, Never, TypeVar

from motiontool.errors import MotionToolError, OutputError
from motiontool.extras import require
from motiontool.sim.executor import Outcome, Status, call_runner, error_reason
from motiontool.sim.shipped import land, open_parcel, pack

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
    jobs: int | None = None,
    timeout_s: float | None = None,
    address: str | None = None,
) -> Iterator[Outcome]:
    """Run ``runner(task)`` for every task as Ray tasks, at most ``jobs`` in flight; yield
    outcomes as they end (an :class:`~motiontool.sim.executor.Executor`).

    Connects to ``address`` (``auto`` finds a running cluster) or, when None, starts a local
    Ray instance for the duration of the call. ``jobs``: at most this many runs in flight
    (None: the cluster's CPUs).

    Raises:
        MotionToolError: the cluster cannot be reached (within :data:`CONNECT_TIMEOUT_S`); a
            run that cannot be packed (its file cannot be read).
    """
    require("ray", "ray", "the Ray executor")
    import ray

    started_here = not ray.is_initialized()
    if started_here:
        _connect(address, jobs)
    if jobs is None:
        jobs = max(1, int(ray.cluster_resources().get("CPU", 1)))  # type: ignore[no-untyped-call]
    remote = ray.remote(max_retries=0)(_call_on_worker)
    try:
        pending = list(range(len(tasks)))
        in_flight: dict[_Ref, tuple[int, float]] = {}
        while pending or in_flight:
            while pending and len(in_flight) < jobs:
                i = pending.pop(0)
                in_flight[remote.remote(runner, pack(tasks[i]))] = (i, time.monotonic())
            yield from _collect(in_flight, timeout_s)
    finally:
        if started_here:
            ray.shutdown()


CONNECT_TIMEOUT_S = 10.0
"""How long the driver waits for a cluster's head to answer on its port before it gives up, s
(Ray itself retries an unreachable head for minutes)."""


def _connect(address: str | None, jobs: int | None) -> None:
    """Connect to the cluster at ``address`` (None: start a local one with ``jobs`` CPUs)."""
    import os

    import ray

    if address is None:
        cpus = jobs if jobs is not None else os.cpu_count() or 1
        ray.init(num_cpus=max(cpus, 1), include_dashboard=False, log_to_driver=False)
        return
    _probe(address)
    try:
        ray.init(address=address, include_dashboard=False, log_to_driver=False)
    except (ConnectionError, RuntimeError, ValueError, TimeoutError) as exc:
        raise MotionToolError(
            f"cannot reach the Ray cluster at {address!r}: {error_reason(exc)}"
        ) from None


def _probe(address: str) -> None:
    """``address``'s host answers on its port within :data:`CONNECT_TIMEOUT_S` (``auto``, or
    an address without a port, is left to Ray).

    Raises:
        MotionToolError: it does not.
    """
    import socket

    host, _, port = address.removeprefix("ray://").rpartition(":")
    if not host or not port.isdigit():
        return
    try:
        socket.create_connection((host.strip("[]"), int(port)), CONNECT_TIMEOUT_S).close()
    except OSError as exc:
        raise MotionToolError(
            f"cannot reach the Ray cluster at {address!r}: {exc.strerror or exc}"
            f" (nothing answered within {CONNECT_TIMEOUT_S:g} s)"
        ) from None


def _call_on_worker(runner: Callable[[Never], object], task: object) -> tuple[Status, object, str]:
    """:func:`call_runner` of ``task`` as :func:`motiontool.sim.shipped.pack` made it, on the
    worker: its recordings kept in the object store."""
    import ray

    return call_runner(partial(open_parcel, runner, store=ray.put), task)


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
        if status == "done":
            try:
                value = land(value, ray.get)
            except OutputError as exc:
                status, value, reason = "unwritten", None, error_reason(exc)
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
