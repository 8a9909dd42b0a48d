"""A local process pool for simulation runs, where one run can crash or hang without harm.

``concurrent.futures`` loses every pending task when one worker dies, and cannot stop one task
that runs too long. This pool gives each worker one task at a time over a pipe, so the parent
always knows which task a worker holds: a worker that dies fails only its own task (``crashed``),
and a task that outlives its timeout has its worker killed and replaced (``timeout``). Everything
else comes back as the runner returned it, or as the exception it raised (``error``).
"""

from __future__ import annotations

import contextlib
import multiprocessing as mp
import sys
import time
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait
from typing import Any, Generic, TypeVar

__all__ = ["Outcome", "error_reason", "run_pool"]

T = TypeVar("T")
R = TypeVar("R")


@dataclass(frozen=True)
class Outcome(Generic[T]):
    """How one task ended.

    Attributes:
        index: the task's position in the input.
        status: ``done``, ``error`` (the runner raised), ``crashed`` (the worker died) or
            ``timeout``.
        value: the runner's return value when ``done``.
        reason: a one-line explanation otherwise.
        wall_s: wall-clock seconds the task took.
    """

    index: int
    status: str
    value: Any = None
    reason: str = ""
    wall_s: float = 0.0


def _worker(runner: Callable[[Any], Any], conn: Connection) -> None:
    while True:
        try:
            message = conn.recv()
        except EOFError:
            return
        if message is None:
            return
        index, task = message
        try:
            conn.send((index, "done", runner(task), ""))
        except Exception as exc:  # reported to the parent, never lost
            conn.send((index, "error", None, error_reason(exc)))


def error_reason(exc: BaseException) -> str:
    """One line for a report: the message the runner raised (a diagnostic such as
    ``wave.motion:3:14: expected ...``), never the exception class or a source location."""
    lines = str(exc).strip().splitlines()
    return lines[0] if lines else "the run stopped on an unexpected error (no message)"


@dataclass
class _Slot:
    process: mp.process.BaseProcess
    conn: Connection
    task: int | None = None
    started: float = 0.0


def _context() -> Any:
    return mp.get_context("fork" if sys.platform.startswith("linux") else "spawn")


def run_pool(
    runner: Callable[[T], R],
    tasks: Sequence[T],
    *,
    jobs: int = 2,
    timeout_s: float | None = None,
) -> Iterator[Outcome[T]]:
    """Run ``runner(task)`` for every task on ``jobs`` worker processes; yield outcomes as they end.

    Args:
        runner: a picklable module-level function.
        tasks: its arguments, one task each.
        jobs: number of worker processes (>= 1).
        timeout_s: wall-clock limit of one task in seconds; None for no limit.
    """
    if jobs < 1:
        raise ValueError(f"jobs must be >= 1, got {jobs}")
    ctx = _context()
    pending = deque(range(len(tasks)))
    slots: list[_Slot] = []

    def spawn() -> _Slot:
        parent, child = ctx.Pipe()
        process = ctx.Process(target=_worker, args=(runner, child), daemon=True)
        process.start()
        child.close()
        return _Slot(process, parent)

    def feed(slot: _Slot) -> None:
        if pending:
            slot.task = pending.popleft()
            slot.started = time.monotonic()
            slot.conn.send((slot.task, tasks[slot.task]))
        else:
            slot.task = None

    def retire(slot: _Slot) -> None:
        slot.conn.close()
        if slot.process.is_alive():
            slot.process.kill()
        slot.process.join()

    try:
        for _ in range(min(jobs, len(tasks))):
            slot = spawn()
            slots.append(slot)
            feed(slot)
        while any(s.task is not None for s in slots):
            busy = [s for s in slots if s.task is not None]
            wait_s = None
            if timeout_s is not None:
                now = time.monotonic()
                wait_s = max(0.0, min(s.started + timeout_s - now for s in busy))
            ready = wait([s.conn for s in busy] + [s.process.sentinel for s in busy], wait_s)
            now = time.monotonic()
            for i, slot in enumerate(slots):
                if slot.task is None:
                    continue
                index = slot.task
                if slot.conn in ready:
                    try:
                        got_index, status, value, reason = slot.conn.recv()
                    except (EOFError, OSError):
                        pass  # the worker died while sending: handled as a crash below
                    else:
                        yield Outcome(got_index, status, value, reason, now - slot.started)
                        feed(slot)
                        continue
                if slot.process.sentinel in ready or not slot.process.is_alive():
                    slot.process.join(timeout=5.0)  # reap it, so that its exit code is known
                    code = slot.process.exitcode
                    retire(slot)
                    yield Outcome(index, "crashed", reason=f"worker died (exit code {code})",
                                  wall_s=now - slot.started)  # fmt: skip
                elif timeout_s is not None and now - slot.started >= timeout_s:
                    retire(slot)
                    yield Outcome(index, "timeout", reason=f"exceeded the {timeout_s:g} s timeout",
                                  wall_s=now - slot.started)  # fmt: skip
                else:
                    continue
                slots[i] = spawn()
                feed(slots[i])
    finally:
        for slot in slots:
            if slot.process.is_alive():
                with contextlib.suppress(OSError):
                    slot.conn.send(None)
            slot.process.join(timeout=1.0)
            retire(slot)
