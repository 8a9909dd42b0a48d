"""Timing helpers shared by the benchmarks (run as scripts: ``python benchmarks/bench_*.py``)."""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

__all__ = ["Child", "best_child", "best_of", "run_child"]


def best_of(n: int, fn: Callable[[], Any]) -> float:
    """The shortest of ``n`` wall-clock timings of ``fn()``, in seconds."""
    times = []
    for _ in range(n):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


@dataclass(frozen=True)
class Child:
    """One run of a command in a child process: wall time (s), CPU time (user + system, s),
    peak resident memory (bytes, the kernel's ``ru_maxrss`` of that child alone) and exit
    status."""

    wall_s: float
    cpu_s: float
    peak_bytes: int
    returncode: int

    @property
    def peak_mib(self) -> float:
        return self.peak_bytes / 2**20


_TIME = shutil.which("time", path="/usr/bin:/bin")
"""GNU time: it forks the command from its own small process, so the peak it reports is the
command's alone (a child forked from this Python process starts with this process's pages)."""


def run_child(
    cmd: Sequence[str],
    env: dict[str, str] | None = None,
    *,
    peak: bool = True,
    cwd: str | os.PathLike[str] | None = None,
) -> Child:
    """Run ``cmd`` (in folder ``cwd``) with its output thrown away, and measure it: through
    GNU time where it is installed, else ``os.wait4``, whose peak includes what the child
    inherited from here. ``peak=False``: by ``os.wait4`` alone, for a wall time that is the
    command's own (GNU time's fork and exec add 3-4 ms to a run); its peak is then not the
    command's alone."""
    with tempfile.NamedTemporaryFile("r", suffix=".time") as out:
        timed = _TIME if peak else None
        wrapped = [timed, "-q", "-f", "%U %S %M", "-o", out.name, *cmd] if timed else list(cmd)
        t0 = time.perf_counter()
        proc = subprocess.Popen(
            wrapped, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env, cwd=cwd
        )
        _pid, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - t0
        code = os.waitstatus_to_exitcode(status)
        if timed:
            user, system, kib = out.read().split()[-3:]
            return Child(wall, float(user) + float(system), int(kib) * 1024, code)
    return Child(wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss * 1024, code)


def best_child(n: int, cmd: Sequence[str], env: dict[str, str] | None = None) -> Child:
    """The fastest (by wall time) of ``n`` runs of ``cmd``, with the largest peak memory
    of them all (the machine's load changes time, not memory)."""
    runs = [run_child(cmd, env) for _ in range(n)]
    best = min(runs, key=lambda c: c.wall_s)
    peak = max(c.peak_bytes for c in runs)
    return Child(best.wall_s, min(c.cpu_s for c in runs), peak, best.returncode)
