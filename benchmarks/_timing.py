"""Timing helpers shared by the benchmarks (run as scripts: ``python benchmarks/bench_*.py``)."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

__all__ = ["best_of"]


def best_of(n: int, fn: Callable[[], Any]) -> float:
    """The shortest of ``n`` wall-clock timings of ``fn()``, in seconds."""
    times = []
    for _ in range(n):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)
