"""The executor registry (issue #16 item 4): every row of ``REGISTRY`` is offered by ``batch
--executor``, described in its help, names an extra that exists, and runs tasks to the same
outcomes as the local pool (executors whose library is missing: skipped here; Ray runs a real
cluster in tests/batch/test_ray.py)."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.extras import EXTRAS
from motiontool.sim.executor import EXECUTORS, REGISTRY, ExecutorInfo, executor_info
from motiontool.sim.pool import run_pool

runner = CliRunner()


def square(x: int) -> int:
    return x * x


@pytest.mark.parametrize("info", REGISTRY, ids=lambda i: i.name)
def test_every_executor_is_offered_and_described(info: ExecutorInfo) -> None:
    assert info.extra is None or info.extra in EXTRAS
    help_text = " ".join(runner.invoke(app, ["batch", "--help"]).stdout.split())
    assert info.name in help_text and info.summary in help_text
    assert executor_info(info.name) is info and info.name in EXECUTORS


@pytest.mark.parametrize(
    "info",
    [
        pytest.param(i, id=i.name, marks=pytest.mark.needs(*[i.extra] if i.extra else []))
        for i in REGISTRY
        if not i.takes_address
    ],
)
def test_executors_without_a_cluster_give_the_pool_s_outcomes(info: ExecutorInfo) -> None:
    tasks = list(range(7))
    run = info.factory(None)
    got = sorted((o.index, o.status, o.value) for o in run(square, tasks, jobs=2, timeout_s=None))
    want = sorted(
        (o.index, o.status, o.value) for o in run_pool(square, tasks, jobs=1, timeout_s=None)
    )
    assert got == want == [(i, "done", i * i) for i in tasks]


def test_an_unknown_executor_lists_the_registry() -> None:
    result = runner.invoke(app, ["batch", "motions", "--executor", "dask"])
    assert result.exit_code == 2
    assert " or ".join(EXECUTORS) in result.stderr


def test_an_address_only_goes_with_an_executor_that_takes_one() -> None:
    local = next(i for i in REGISTRY if not i.takes_address)
    result = runner.invoke(
        app, ["batch", "motions", "--executor", local.name, "--ray-address", "auto"]
    )
    assert result.exit_code == 2 and "--ray-address" in result.stderr
