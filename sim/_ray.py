"""The Ray executor (the only module importing ray): the same runs, on a Ray cluster.

Ray is an optional extra (``pip install 'motiontool[ray]'``). Each run is one Ray task; at most
``jobs`` are in flight; a task that exceeds the timeout is cancelled (its worker is killed) and
reported as ``timeout``; a task whose worker dies is reported as ``crashed``. A batch run travels
as bytes (:mod:`motiontool.sim.shipped`): packed when it is sent, so the driver holds only the
runs in flight; its recordings come back through Ray's object store, fetched and written one at
a time. The runs in flight are the cluster's CPUs, at most ``jobs`` (:func:`ray_session`). A
worker that cannot import motiontool stops the batch with one line (:func:`_setup_error`). Ray
ships its own types (``py.typed``): the module is imported directly (lazily), so mypy checks
every call.
"""

from __future__ import annotations

import re
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from functools import partial
from typing import TYPE_CHECKING, Never, TypeVar

from motiontool.errors import MotionToolError, OutputError
from motiontool.extras import require
from motiontool.sim.executor import (
    ClusterSetupError,
    Outcome,
    Parallelism,
    Status,
    call_runner,
    error_reason,
)
from motiontool.sim.shipped import Parcel, land, open_parcel, pack

if TYPE_CHECKING:
    from ray import ObjectRef

    #: A task in flight: what :func:`~motiontool.sim.executor.call_runner` returns, once ready.
    _Ref = ObjectRef[tuple[Status, object, str]]

__all__ = ["SIM_MODULES", "ray_session", "run_ray"]

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

    Uses the Ray this process is connected to (:func:`ray_session`), else connects to
    ``address`` (``auto`` finds a running cluster) or, when None, starts a local Ray instance
    for the duration of the call. ``jobs``: at most this many runs in flight (None: the
    cluster's CPUs).

    Raises:
        MotionToolError: the cluster cannot be reached (within :data:`CONNECT_TIMEOUT_S`); a
            run that cannot be packed (its file cannot be read).
        ClusterSetupError: the workers cannot import motiontool or its simulation libraries,
            or Ray cannot set up their runtime environment: the batch stops.
    """
    import ray

    with ray_session(address, jobs) as parallel:
        remote = ray.remote(max_retries=0)(_call_on_worker)
        pending = list(range(len(tasks)))
        in_flight: dict[_Ref, tuple[int, float]] = {}
        while pending or in_flight:
            while pending and len(in_flight) < parallel.in_flight:
                i = pending.pop(0)
                in_flight[remote.remote(runner, pack(tasks[i]))] = (i, time.monotonic())
            yield from _collect(in_flight, timeout_s)


@contextmanager
def ray_session(
    address: str | None, jobs: int | None, runtime_env: dict[str, object] | None = None
) -> Iterator[Parallelism]:
    """Connected to Ray for the ``with`` block (already connected: as it is), and how many
    runs go in flight: the cluster's CPUs, at most ``jobs``.

    ``address``: the cluster (None: a local Ray started with ``jobs`` CPUs, or this machine's);
    ``runtime_env``: Ray's runtime environment of the batch's tasks
    (``ray.init(runtime_env=...)``: ``py_modules``, ``pip``, ``env_vars``...).

    Raises:
        MotionToolError: the cluster cannot be reached, or refuses ``runtime_env``.
    """
    require("ray", "ray", "the Ray executor")
    import ray

    started_here = not ray.is_initialized()
    if started_here:
        _connect(address, jobs, runtime_env)
    try:
        cpus = int(ray.cluster_resources().get("CPU", 0))  # type: ignore[no-untyped-call]
        in_flight = max(1, min(cpus, jobs) if jobs is not None else cpus)
        yield Parallelism(in_flight, cpus, jobs)
    finally:
        if started_here:
            ray.shutdown()


CONNECT_TIMEOUT_S = 10.0
"""How long the driver waits for a cluster's head to answer on its port before it gives up, s
(Ray itself retries an unreachable head for minutes)."""


def _connect(address: str | None, jobs: int | None, runtime_env: dict[str, object] | None) -> None:
    """Connect to the cluster at ``address`` (None: start a local one with ``jobs`` CPUs)."""
    import logging
    import os

    import ray

    where = "Ray" if address is None else f"the Ray cluster at {address!r}"
    if address is not None:
        _probe(address)
    cpus = jobs if jobs is not None else os.cpu_count() or 1
    try:
        ray.init(
            address=address,
            num_cpus=max(cpus, 1) if address is None else None,
            runtime_env=runtime_env,
            include_dashboard=False,
            log_to_driver=False,
            logging_level=logging.WARNING,  # not Ray's "Connecting to..." on stderr
        )
    except (ValueError, TypeError) as exc:
        if runtime_env is None:
            raise MotionToolError(f"cannot reach {where}: {error_reason(exc)}") from None
        raise MotionToolError(
            f"{where} refuses the runtime environment: {error_reason(exc)}"
        ) from None
    except (ConnectionError, RuntimeError, TimeoutError) as exc:
        raise MotionToolError(f"cannot reach {where}: {error_reason(exc)}") from None


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
    worker: its recordings kept in the object store. A batch run on a worker without the
    simulation's libraries raises their :class:`ImportError` (the driver stops the batch)."""
    import importlib

    import ray

    if isinstance(task, Parcel):
        for module in SIM_MODULES:
            importlib.import_module(module)
    return call_runner(partial(open_parcel, runner, store=ray.put), task)


SIM_MODULES = ("mujoco",)
"""What a worker imports before it plays a batch run: a worker without them cannot play one."""


def _setup_error(exc: Exception) -> ClusterSetupError | None:
    """The :class:`ClusterSetupError` that a task's failure ``exc`` shows, or None: a worker
    could not import motiontool (Ray could not unpickle the task) or a simulation library, or
    Ray could not set up its runtime environment."""
    import ray

    text = str(exc)
    ip = re.search(r"\bip=([^\s,)]+)|\[Node ([^\]\s]+)\]", text)
    host = next((g for g in ip.groups() if g), "a worker") if ip else "a worker"
    if isinstance(exc, ray.exceptions.RuntimeEnvSetupError):
        last = [line.strip() for line in text.splitlines() if line.strip()][-1]
        return ClusterSetupError(
            f"Ray could not set up the runtime environment on {host}: {last}", remedy=False
        )
    found = re.findall(r"(?:ModuleNotFoundError|ImportError): (.+)", text)
    if not isinstance(exc, ray.exceptions.RayTaskError) or not found:
        return None
    return ClusterSetupError(
        f"the Ray workers cannot import motiontool or its simulation libraries"
        f" ({found[-1].strip()}, on {host})"
    )


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
        except ray.exceptions.RayError as exc:
            setup = _setup_error(exc)
            if setup is not None:
                raise setup from None
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
