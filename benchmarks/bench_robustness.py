"""Benchmark: what ``--robustness N`` costs over one play (about N / cores plays).

Run: ``python benchmarks/bench_robustness.py [--members 8] [--jobs CORES] [--repeat 2]
[MOTION]``. Plays MOTION (default: Webots' Forwards50, tests/data/corpus) on the Nao once, in
this process, as ``play`` does (the baseline); then its N members as ``play --robustness N``
runs them (:func:`motiontool.sim.robustness.member_specs` on the batch's local pool,
:func:`motiontool.sim.batch.run_batch`, no cache), pool start included. Best of ``--repeat``
each, interleaved. Prints both wall times, the members' cost in plays and N / jobs (the target:
the members cost about N / jobs plays; a member at 1 ms costs twice one at 2 ms, one at 4 ms
half). On a machine whose cores other work shares, the wall time of the pool measures the load
as much as the runs: read the ratio with ``--jobs`` at most the cores that are free.
"""

from __future__ import annotations

import argparse
import hashlib
import math
import os
import resource
import sys
import time
from pathlib import Path

from _timing import best_of  # benchmarks/_timing.py (run as a script)

ROOT = Path(__file__).resolve().parent.parent
DANCE = ROOT / "tests/data/corpus/webots/projects/robots/softbank/dancing_nao/motions"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("motion", nargs="?", type=Path, default=DANCE / "Forwards50.motion")
    parser.add_argument("--members", type=int, default=8)
    parser.add_argument("--loops", type=int, default=4)
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args()
    if not args.motion.is_file():
        print(f"{args.motion} not found", file=sys.stderr)
        return 2

    from motiontool.kinematics.robots import load_robot
    from motiontool.sim import PlayOptions, play
    from motiontool.sim.batch import RunSpec, run_batch
    from motiontool.sim.robustness import member_specs
    from motiontool.sim.runs import run_spec

    robot = load_robot("nao")
    nominal = RunSpec(
        str(args.motion),
        hashlib.sha256(args.motion.read_bytes()).hexdigest(),
        "nao",
        options=(("loops", args.loops), ("timestep_ms", robot.default_timestep_ms)),
    )
    specs = member_specs(nominal, args.members, seed=0, control_step_ms=robot.default_timestep_ms)

    def one_play() -> None:
        play([args.motion], robot="nao", options=PlayOptions(loops=args.loops))

    def members() -> None:
        batch = run_batch(specs, run_spec, model_hash=lambda _r: robot.model_hash, jobs=args.jobs)
        assert all(r.report is not None for r in batch.runs), [r.reason for r in batch.runs]

    plain = ensemble = plain_cpu = ensemble_cpu = math.inf
    for _ in range(args.repeat):  # interleaved: a load that comes and goes hits both
        start = time.process_time()
        plain = min(plain, best_of(1, one_play))
        plain_cpu = min(plain_cpu, time.process_time() - start)
        start = _cpu()
        ensemble = min(ensemble, best_of(1, members))
        ensemble_cpu = min(ensemble_cpu, _cpu() - start)
    # A member at 1 ms steps twice as often as the play's 2 ms, one at 4 ms half as often.
    steps = [dict(s.options)["physics_step_ms"] for s in specs]
    weighted = sum(2.0 / step for step in steps) / args.jobs
    cost = ensemble / plain
    print(
        f"{args.motion.name} x{args.loops} on nao, {args.members} members on {args.jobs} jobs"
        f" (local pool), physics steps {sorted(steps)} ms"
    )
    print(f"  one play:          {plain:6.2f} s wall, {plain_cpu:6.2f} s CPU")
    print(f"  the members:       {ensemble:6.2f} s wall, {ensemble_cpu:6.2f} s CPU (workers too)")
    print(
        f"  the members cost {cost:.2f} plays; N / jobs = {args.members / args.jobs:.2f}"
        f" (ratio {cost / (args.members / args.jobs):.2f}, target about 1); weighted by their"
        f" physics steps {weighted:.2f} plays (ratio {cost / weighted:.2f})"
    )
    cpu_cost = ensemble_cpu / plain_cpu / args.jobs
    print(
        f"  by CPU time, on {args.jobs} free cores: the members cost {cpu_cost:.2f} plays"
        f" (ratio {cpu_cost / (args.members / args.jobs):.2f} to N / jobs,"
        f" {cpu_cost / weighted:.2f} to the weighted)"
    )
    return 0


def _cpu() -> float:
    """CPU time (user + system, s) of this process and of its children waited for."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


if __name__ == "__main__":
    raise SystemExit(main())
