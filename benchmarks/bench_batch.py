"""Benchmark: batch throughput, ``--jobs 1`` vs ``--jobs 2`` on the local pool, and Ray vs local;
and the memory of ``motiontool batch`` against its number of runs.

Run: ``python benchmarks/bench_batch.py`` (``--memory-only`` for the last part). Plays the same
batch (a Nao motion x perturbation samples, no cache) with each executor and prints runs per
second and the ratios measured in the same run. Targets: jobs 2 >= 1.7x jobs 1; Ray
>= 0.8x the local pool at 2 jobs. Then the whole ``batch`` command with 20 and 80 samples of a
short motion and a JSON report: the peak of the larger against the smaller (target: flat, at
most 1.1x: the runs' reports are stored on disk as they end, not held). ``--shipping``: what a
Ray task costs to ship as bytes (:mod:`motiontool.sim.shipped`): packing on the
driver, the parcel's pickled size, and a run opened from its parcel (files written to a
temporary folder, report mapped back, recording read back) against the same run played in place.
``--cluster``: a two-node cluster started with ``ray start`` (a head and a worker, one CPU
each, on this machine) against the local pool at 2 jobs (target: 0.95x or better); the per-task
cost of shipping (as ``--shipping``); the driver's peak memory over 20 and 200 runs with
recordings on that cluster (target: flat, at most 1.1x).
"""

from __future__ import annotations

import argparse
import logging
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

from _timing import best_child  # benchmarks/_timing.py (run as a script)

from motiontool.kinematics.robots import load_robot
from motiontool.sim.batch import RunSpec, parse_perturbation, plan, run_batch
from motiontool.sim.runs import run_spec

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--motion", default=str(ROOT / "motions" / "nao" / "wave_right.motion"))
    parser.add_argument("--samples", type=int, default=8)
    parser.add_argument("--no-ray", action="store_true")
    parser.add_argument("--memory-only", action="store_true")
    parser.add_argument("--shipping", action="store_true")
    parser.add_argument("--cluster", action="store_true")
    args = parser.parse_args()
    if args.cluster:
        cluster(Path(args.motion), args.samples)
        shipping(Path(args.motion))
        return
    if args.memory_only:
        memory()
        return
    if args.shipping:
        shipping(Path(args.motion))
        return
    specs = plan([args.motion], ["nao"], perturbations=[parse_perturbation("friction=0.8:1.2")],
                 samples=args.samples, seed=1)  # fmt: skip

    def rate(executor: str, jobs: int) -> float:
        return _rate(specs, executor, jobs)

    run_spec(specs[0])  # warm the page cache and this process's imports (workers fork from it)
    r1 = rate("local", 1)
    r2 = rate("local", 2)
    print(f"batch: {len(specs)} runs of {Path(args.motion).name} on the Nao")
    print(f"local pool, --jobs 1: {r1:.2f} runs/s")
    print(f"local pool, --jobs 2: {r2:.2f} runs/s  ratio {r2 / r1:.2f}x jobs 1  (target >= 1.7)")
    if not args.no_ray:
        import ray

        ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
        try:
            rate("ray", 2)  # starts Ray's workers and their imports; measure the second batch
            rr = rate("ray", 2)
        finally:
            ray.shutdown()
        print(
            f"ray (local cluster), 2 in flight: {rr:.2f} runs/s  ratio {rr / r2:.2f}x local pool  (target >= 0.8)"
        )
    memory()


def _model_hash(robot: str) -> str:
    return load_robot(robot).model_hash


def _rate(specs: list[RunSpec], executor: str, jobs: int, address: str | None = None) -> float:
    """Runs per second of the batch ``specs``, no cache; every run clean."""
    t0 = time.perf_counter()
    batch = run_batch(specs, run_spec, model_hash=_model_hash, executor=executor, jobs=jobs,
                      cache_dir=None, ray_address=address)  # fmt: skip
    wall = time.perf_counter() - t0
    assert [r.status for r in batch.runs] == ["clean"] * len(specs), batch.runs[0].reason
    return len(specs) / wall


def cluster(motion: Path, samples: int) -> None:
    """A two-node ``ray start`` cluster against the local pool, and the driver's peak memory
    on it over 20 and 200 runs with recordings."""
    import ray

    sys.path.insert(0, str(ROOT / "tests"))
    from raycluster import ray_cluster  # tests/raycluster.py: the tests' clusters

    specs = plan([motion], ["nao"], perturbations=[parse_perturbation("friction=0.8:1.2")],
                 samples=samples, seed=1)  # fmt: skip
    run_spec(specs[0])  # warm the page cache and this process's imports (workers fork from it)
    before = _rate(specs, "local", 2)
    with ray_cluster(nodes=2) as address:
        ray.init(address=address, log_to_driver=False, logging_level=logging.WARNING)
        try:
            cold = _rate(specs, "ray", 2)  # the job's workers start and import
            warm = _rate(specs, "ray", 2)
        finally:
            ray.shutdown()
        after = _rate(specs, "local", 2)
        local = max(before, after)  # the baseline: the local pool's better of two
        print(
            f"batch: {len(specs)} runs of {motion.name} on the Nao; load {os.getloadavg()[0]:.1f}"
        )
        print(f"local pool, --jobs 2: {before:.2f} runs/s before, {after:.2f} after the cluster's")
        print(f"two-node cluster (ray start, 2 x 1 CPU), first batch: {cold:.2f} runs/s"
              f"  ratio {cold / local:.2f}x local pool (its workers start)")  # fmt: skip
        print(f"two-node cluster, second batch: {warm:.2f} runs/s  ratio {warm / local:.2f}x"
              f" local pool  (target >= 0.95)")  # fmt: skip
        ray_args = ("--executor", "ray", "--ray-address", address)
        memory((20, 200), recordings=True, more=ray_args, what="two-node cluster, ")


def shipping(motion: Path, runs: int = 10) -> None:
    """The per-task cost of shipping a run as bytes, with a recording (best of ``runs``)."""
    import pickle

    from motiontool.sim.shipped import land, open_parcel, pack

    with tempfile.TemporaryDirectory() as tmp:
        options = {"rrd_dir": str(Path(tmp) / "rrd"), "rrd_name": motion.stem}
        Path(options["rrd_dir"]).mkdir()
        (spec,) = plan([motion], ["nao"], options=options)
        run_spec(spec)  # warm imports and the model
        t0 = time.perf_counter()
        for _ in range(1000):
            parcel = pack(spec)
        packing = (time.perf_counter() - t0) / 1000
        in_place, shipped = [], []
        for _ in range(runs):
            t0 = time.perf_counter()
            run_spec(spec)
            in_place.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            land(open_parcel(run_spec, parcel, store=bytes), fetch=bytes)
            shipped.append(time.perf_counter() - t0)
        size = len(pickle.dumps(parcel))
        rrd = sum(f.stat().st_size for f in Path(options["rrd_dir"]).iterdir())
    overhead = min(shipped) - min(in_place)
    print(f"shipping {motion.name}: pack {packing * 1e6:.0f} us, parcel {size} bytes pickled")
    print(
        f"run in place {min(in_place) * 1e3:.0f} ms, from its parcel {min(shipped) * 1e3:.0f} ms"
        f" (+{overhead * 1e3:.1f} ms a task, recording of {rrd / 1e6:.1f} MB included)"
    )


def memory(
    counts: tuple[int, int] = (20, 80),
    *,
    recordings: bool = False,
    more: tuple[str, ...] = (),
    what: str = "",
) -> None:
    """The batch command's peak with few and many runs (``recordings``: each with a Rerun
    recording; ``more``: more options, the executor's), and their ratio."""
    script = shutil.which("motiontool", path=os.path.dirname(sys.executable)) or "motiontool"
    motion = ROOT / "motions" / "nao" / "head_no.motion"
    peaks = {}
    with tempfile.TemporaryDirectory() as tmp:
        for n in counts:
            cmd = [script, "batch", str(motion), "--samples", str(n), "--perturb",
                   "start-yaw=0:10", "--no-cache", "--json", str(Path(tmp) / "r.json"),
                   *more]  # fmt: skip
            rrd = Path(tmp) / f"rrd{n}"
            child = best_child(1, [*cmd, "--rrd-dir", str(rrd)] if recordings else cmd)
            assert child.returncode in (0, 1), f"{' '.join(cmd)} exited {child.returncode}"
            peaks[n] = child.peak_bytes
            kept = (
                f" and {sum(f.stat().st_size for f in rrd.iterdir()) / 1e6:.0f} MB of recordings"
                if recordings
                else ""
            )
            print(
                f"{what}batch, {n} runs, a JSON report{kept}: {child.wall_s:.1f} s,"
                f" {child.peak_mib:.0f} MiB peak"
            )
    few, many = counts
    ratio = peaks[many] / peaks[few]
    verdict = "met" if ratio <= 1.1 else "not met"
    print(f"{what}{many} runs peak at {ratio:.2f}x {few} runs' (target <= 1.1x, flat: {verdict})")


if __name__ == "__main__":
    main()
