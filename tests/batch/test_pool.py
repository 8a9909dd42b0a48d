"""The local pool: one run crashing, raising or hanging never stops the others."""

from __future__ import annotations

import os
import time

import pytest

from motiontool.sim.pool import run_pool


def runner(task: tuple[str, int]) -> int:
    kind, n = task
    if kind == "crash":
        os._exit(3)
    if kind == "raise":
        raise ValueError(f"bad task {n}")
    if kind == "hang":
        time.sleep(60)
    return n * n


def test_results_come_back_whatever_the_order() -> None:
    tasks = [("ok", n) for n in range(7)]
    outcomes = sorted(run_pool(runner, tasks, jobs=2), key=lambda o: o.index)
    assert [o.status for o in outcomes] == ["done"] * 7
    assert [o.value for o in outcomes] == [n * n for n in range(7)]


def test_crash_error_and_timeout_are_isolated() -> None:
    tasks = [("ok", 1), ("crash", 2), ("ok", 3), ("raise", 4), ("hang", 5), ("ok", 6)]
    t0 = time.monotonic()
    outcomes = {o.index: o for o in run_pool(runner, tasks, jobs=2, timeout_s=1.5)}
    assert time.monotonic() - t0 < 20
    assert [outcomes[i].status for i in range(6)] == [
        "done",
        "crashed",
        "done",
        "error",
        "timeout",
        "done",
    ]
    assert outcomes[1].reason == "worker died (exit code 3)"
    assert outcomes[3].reason == "bad task 4"  # the message only: no class, no source path
    assert outcomes[4].reason == "exceeded the 1.5 s timeout"
    assert outcomes[5].value == 36


def test_jobs_must_be_positive() -> None:
    with pytest.raises(ValueError, match="jobs must be >= 1"):
        list(run_pool(runner, [("ok", 1)], jobs=0))
