"""Benchmark: what self-collision physics costs over a play without it (under 1.5x).

Run: ``python benchmarks/bench_self_collision.py [--loops 4] [--repeat 3]``. Plays on the Nao in
the wrestling world (tests/data/worlds; its Nao has ``selfCollision TRUE``), best of
``--repeat`` each (interleaved), with and without self-collision physics (``--no-self-collision``):

- the world's HandWave, looped: a gesture whose arms stay clear of the body (the cost of
  detecting the robot's pairs of bodies every physics step);
- a motion that drives the left arm into the torso and holds it there (``tests/sim/
  test_self_collision.py``'s HUG; the cost when the robot's parts keep touching: more contacts
  for the solver).

Prints the wall and CPU times and their ratios (target <= 1.5 for a play). On a machine whose
cores other work shares, read the CPU times: MuJoCo steps on one thread, and the wall time
then measures the load as much as the run.
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

from _timing import best_of  # benchmarks/_timing.py (run as a script)

ROOT = Path(__file__).resolve().parent.parent
WORLDS = ROOT / "tests" / "data" / "worlds" / "wrestling"  # vendored (see its NOTICE)
WORLD = WORLDS / "worlds" / "wrestling.wbt"
HAND_WAVE = WORLDS / "controllers" / "motions" / "HandWave.motion"
HUG = (
    "#WEBOTS_MOTION,V1.0,LShoulderPitch,LShoulderRoll,LElbowYaw,LElbowRoll\n"
    "00:00:000,Zero,0,0,0,0\n"
    "00:01:000,Out,1.5,0.5,0,-1.54\n"
    "00:02:000,In,1.5,-0.31,0,-1.54\n"
    "00:04:000,Held,1.5,-0.31,0,-1.54\n"
)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--loops", type=int, default=4)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    if not (WORLD.is_file() and HAND_WAVE.is_file()):
        print(f"{WORLDS} not found (the vendored worlds are needed)", file=sys.stderr)
        return 2

    from motiontool.sim import PlayOptions, play
    from motiontool.sim.world import read_world
    from motiontool.sim.world_run import world_run

    world = world_run(read_world(WORLD, "participant", "nao"))
    with tempfile.TemporaryDirectory() as folder:
        hug = Path(folder) / "hug.motion"
        hug.write_text(HUG, encoding="utf-8")
        for label, motion, loops in (
            (f"HandWave x{args.loops}", HAND_WAVE, args.loops),
            ("arm into the torso", hug, 1),
        ):
            times = {False: math.inf, True: math.inf}
            cpu = {False: math.inf, True: math.inf}
            for _ in range(args.repeat):  # interleaved: a load that comes and goes hits both
                for collide in (False, True):
                    options = PlayOptions(loops=loops, hold_s=0.0, self_collision=collide)

                    def run(options: PlayOptions = options, motion: Path = motion) -> None:
                        play([motion], robot="nao", options=options, world=world)

                    start = time.process_time()
                    times[collide] = min(times[collide], best_of(1, run))
                    cpu[collide] = min(cpu[collide], time.process_time() - start)
            report = play(
                [motion], robot="nao", options=PlayOptions(loops=loops, hold_s=0.0), world=world
            )
            touched = report.self_collision["touching_pairs"] if report.self_collision else 0
            print(f"{label}: {report.simulated_s:.1f} s simulated, {touched} pairs touched")
            print(
                f"  without self-collision physics: {times[False]:.3f} s ({cpu[False]:.3f} s CPU)"
            )
            print(f"  with:                           {times[True]:.3f} s ({cpu[True]:.3f} s CPU)")
            print(f"  ratio:                          {times[True] / times[False]:.3f}, CPU "
                  f"{cpu[True] / cpu[False]:.3f} (target <= 1.5)")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
