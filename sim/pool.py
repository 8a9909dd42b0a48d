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
import signal
import sys
import time
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait
from typing import Any

from motiontool import exit_codes
from motiontool.sim.executor import Outcome, call_runner

__all__ = ["run_pool"]


_ENDINGS = (signal.SIGTERM, signal.SIGHUP)
"""The signals that end a worker (the parent's, or ``timeout``'s to the whole group)."""

_GRACE_S = 2.0
"""How long a worker sent SIGTERM has to unwind (its temporary files removed) before it is
killed, seconds."""


def _stop_worker(signum: int, frame: object) -> None:
    raise SystemExit(exit_codes.BY_SIGNAL[signum])


def _worker(runner: Callable[[Any], Any], conn: Connection) -> None:
    # Ctrl-C reaches the whole process group: the parent stops the pool (and kills its
    # workers); a worker that took it too would print a KeyboardInterrupt traceback.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    # SIGTERM or SIGHUP (from the parent stopping the pool, or to the whole group): the run
    # unwinds through its ``with`` and ``finally`` (no temporary file left) and the worker
    # exits quietly, whatever handler it inherited from the parent.
    for ending in _ENDINGS:
        if signal.getsignal(ending) is not signal.SIG_IGN:
            signal.signal(ending, _stop_worker)
    while True:
        try:
            message = conn.recv()
        except EOFError:
            return
        if message is None:
            return
        index, task = message
        conn.send((index, *call_runner(runner, task)))


@dataclass
class _Slot:
    process: mp.process.BaseProcess
    conn: Connection
    task: int | None = None
    started: float = 0.0


def _context() -> Any:
    return mp.get_context("fork" if sys.platform.startswith("linux") else "spawn")


def run_pool(
    runner: Callable[[Any], Any],
    tasks: Sequence[Any],
    *,
    jobs: int = 2,
    timeout_s: float | None = None,
) -> Iterator[Outcome]:
    """Run ``runner(task)`` for every task on ``jobs`` worker processes; yield outcomes as they end
    (an :class:`~motiontool.sim.executor.Executor`).

    Args:
        runner: a picklable module-level function.
        tasks: its arguments, one task each.
        jobs: number of worker processes (>= 1).
        timeout_s: wall-clock limit of one task in seconds; None for no limit.
    """
    if jobs < 1:
        raise ValueError(f"jobs must be >= 1, got {jobs}")
    pool = _Pool(runner, tasks, timeout_s)
    try:
        pool.start(min(jobs, len(tasks)))
        while pool.busy():
            yield from pool.collect()
    finally:
        pool.close()


class _Pool:
    """Worker processes, each holding at most one task (its index in ``tasks``)."""

    def __init__(
        self, runner: Callable[[Any], Any], tasks: Sequence[Any], timeout_s: float | None
    ) -> None:
        self.runner = runner
        self.tasks = tasks
        self.timeout_s = timeout_s
        self.ctx = _context()
        self.pending = deque(range(len(tasks)))
        self.slots: list[_Slot] = []

    def start(self, workers: int) -> None:
        for _ in range(workers):
            slot = self._spawn()
            self.slots.append(slot)
            self._feed(slot)

    def busy(self) -> list[_Slot]:
        return [s for s in self.slots if s.task is not None]

    def collect(self) -> Iterator[Outcome]:
        """Wait for the first task to end (or to time out); yield every task that has ended,
        giving its worker the next task (a dead or killed worker is replaced first)."""
        ready = self._wait(self.busy())
        now = time.monotonic()
        for i, slot in enumerate(self.slots):
            ended = None if slot.task is None else self._ended(slot, ready, now)
            if ended is None:
                continue
            outcome, lost_worker = ended
            if lost_worker:
                _retire(slot)
                slot = self.slots[i] = self._spawn()
            self._feed(slot)
            yield outcome

    def close(self) -> None:
        """Stop every worker: an idle one ends when told, one still running a task (the batch
        was stopped) is terminated and unwinds (:func:`_retire`)."""
        for slot in self.slots:
            if slot.process.is_alive() and slot.task is None:
                with contextlib.suppress(OSError):
                    slot.conn.send(None)
        for slot in self.slots:
            if slot.task is None:
                slot.process.join(timeout=1.0)
            _retire(slot)

    def _spawn(self) -> _Slot:
        parent, child = self.ctx.Pipe()
        process = self.ctx.Process(target=_worker, args=(self.runner, child), daemon=True)
        process.start()
        child.close()
        return _Slot(process, parent)

    def _feed(self, slot: _Slot) -> None:
        if self.pending:
            slot.task = self.pending.popleft()
            slot.started = time.monotonic()
            slot.conn.send((slot.task, self.tasks[slot.task]))
        else:
            slot.task = None

    def _wait(self, busy: list[_Slot]) -> list[Any]:
        """The connections and process sentinels of ``busy`` that are ready, waiting at most
        until the first task's timeout."""
        wait_s = None
        if self.timeout_s is not None:
            now = time.monotonic()
            wait_s = max(0.0, min(s.started + self.timeout_s - now for s in busy))
        return wait([s.conn for s in busy] + [s.process.sentinel for s in busy], wait_s)

    def _ended(self, slot: _Slot, ready: list[Any], now: float) -> tuple[Outcome, bool] | None:
        """(how the slot's task ended, whether its worker is lost), or None if it runs on."""
        index = slot.task
        assert index is not None
        wall_s = now - slot.started
        if slot.conn in ready:
            try:
                got_index, status, value, reason = slot.conn.recv()
            except (EOFError, OSError):
                pass  # the worker died while sending: handled as a crash below
            else:
                return Outcome(got_index, status, value, reason, wall_s), False
        if slot.process.sentinel in ready or not slot.process.is_alive():
            slot.process.join(timeout=5.0)  # reap it, so that its exit code is known
            reason = f"worker died (exit code {slot.process.exitcode})"
            return Outcome(index, "crashed", reason=reason, wall_s=wall_s), True
        if self.timeout_s is not None and wall_s >= self.timeout_s:
            reason = f"exceeded the {self.timeout_s:g} s timeout"
            return Outcome(index, "timeout", reason=reason, wall_s=wall_s), True
        return None


def _retire(slot: _Slot) -> None:
    """End the slot's worker: SIGTERM, so that it removes its temporary files, then SIGKILL
    if it has not ended after :data:`_GRACE_S` (a worker stuck in native code)."""
    slot.conn.close()
    if slot.process.is_alive():
        slot.process.terminate()
        slot.process.join(timeout=_GRACE_S)
    if slot.process.is_alive():
        slot.process.kill()
    slot.process.join()
