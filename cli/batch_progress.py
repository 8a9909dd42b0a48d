"""``motiontool batch``'s runs (:func:`motiontool.sim.batch.run_batch`, cached) under a progress
bar on stderr: runs done, runs per second, runs not clean, time left (a terminal only)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from motiontool.cli.color import rich_no_color
from motiontool.cli.output import emit_stderr
from motiontool.cli.text import plural
from motiontool.errors import MotionToolError

if TYPE_CHECKING:
    from pathlib import Path

    from rich.progress import Progress

    from motiontool.sim.batch import BatchResult, RunResult, RunSpec
    from motiontool.sim.executor import Parallelism

__all__ = ["in_flight", "run_with_progress"]


def _model_hash(name: str) -> str:
    from motiontool.kinematics.robots import AUTO, load_robot

    return "" if name == AUTO else load_robot(name).model_hash


def run_with_progress(
    specs: list[RunSpec],
    *,
    executor: str,
    jobs: int | None,
    timeout: float | None,
    cache: tuple[Path | None, bool, float],
    ray: tuple[str | None, dict[str, object] | None],
    spool_dir: Path,
) -> BatchResult:
    """Run the batch (:func:`motiontool.sim.batch.run_batch`) under a progress bar on stderr
    (a terminal only), cached (``cache``: the folder, default the user's; no cache; its size
    limit in MB), each run's report stored in ``spool_dir`` as it ends; ``ray``: the cluster's
    address and runtime environment. On a cluster, the runs in flight (its CPUs, at most
    ``jobs``) are said in one line on stderr; a cluster that cannot play the batch at all (its
    workers cannot import motiontool) stops it with one line, exit 2."""
    from motiontool.sim.executor import ClusterSetupError, session

    try:
        with session(executor, jobs, address=ray[0], runtime_env=ray[1]) as parallel:
            if parallel.cpus is not None:
                emit_stderr(f"motiontool: {executor}: {in_flight(parallel)}\n")
            return _run(specs, executor, parallel.in_flight, timeout, cache, ray[0], spool_dir)
    except ClusterSetupError as exc:
        if not exc.remedy:
            raise
        raise MotionToolError(
            f"{exc.problem}: install motiontool[sim] in the cluster's image or pass"
            " --ray-runtime-env (docs/ray.md)"
        ) from None


def in_flight(parallel: Parallelism) -> str:
    """``4 runs in flight (the cluster's 4 CPUs)``: how many runs a cluster plays at once, and
    why."""
    runs = plural(parallel.in_flight, "run")
    cpus = plural(parallel.cpus or 0, "CPU")
    if parallel.asked is None:
        return f"{runs} in flight (the cluster's {cpus})"
    if parallel.asked <= parallel.in_flight:
        return f"{runs} in flight (--jobs {parallel.asked}; the cluster has {cpus})"
    return f"{runs} in flight (the cluster's {cpus}; --jobs {parallel.asked} is more)"


def _run(
    specs: list[RunSpec],
    executor: str,
    jobs: int,
    timeout: float | None,
    cache: tuple[Path | None, bool, float],
    ray_address: str | None,
    spool_dir: Path,
) -> BatchResult:
    """The batch run under the progress bar."""
    cache_dir, no_cache, cache_max_mb = cache
    from motiontool.disk_cache import BYTES_PER_MB
    from motiontool.sim.batch import default_cache_dir, run_batch
    from motiontool.sim.runs import run_outputs, run_spec

    failures = 0
    with _progress_bar() as bar:
        task = bar.add_task("batch", total=len(specs), rate=0.0, failures=0)

        def progress(result: RunResult, done: int, total: int) -> None:
            nonlocal failures
            failures += not result.ok
            elapsed = bar.tasks[0].elapsed or 1e-9
            bar.update(task, completed=done, rate=done / elapsed, failures=failures)

        return run_batch(
            specs,
            run_spec,
            model_hash=_model_hash,
            executor=executor,
            jobs=jobs,
            timeout_s=timeout,
            cache_dir=None if no_cache else (cache_dir or default_cache_dir()),
            cache_max_bytes=round(cache_max_mb * BYTES_PER_MB),
            ray_address=ray_address,
            outputs=run_outputs,
            progress=progress,
            spool_dir=spool_dir,
        )


def _progress_bar() -> Progress:
    """The batch's progress bar on stderr: runs done, runs per second, runs not clean, time
    left; shown on a terminal only, gone when the batch is over."""
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeRemainingColumn,
    )

    # Colour: rich follows NO_COLOR / FORCE_COLOR itself; --no-color is the root option.
    console = Console(stderr=True, no_color=rich_no_color())
    return Progress(
        TextColumn("[progress.description]{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("{task.fields[rate]:.2f} runs/s, {task.fields[failures]} not clean"),
        TimeRemainingColumn(),
        console=console,
        transient=True,
        disable=not console.is_terminal,
    )
