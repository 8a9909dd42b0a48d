"""Benchmark: what ``play --world`` costs over a plain ``play`` (under 5 %).

Run: ``python benchmarks/bench_world.py [--loops 4] [--repeat 3]``. Plays the wrestling world's
HandWave (tests/data/worlds, looped) on the Nao at the world's 10 ms control step, best of
``--repeat`` each:

- ``play`` without a world (a floor plane, the 10 ms step given);
- ``play`` in the wrestling world, reading it included (the .wbt, its local PROTOs, the
  contact matching), as ``play --world`` does: the ring as a second support, the start
  position and the report's ``world`` object.

Prints both wall times and their ratio (target <= 1.05).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from _timing import best_of  # benchmarks/_timing.py (run as a script)

ROOT = Path(__file__).resolve().parent.parent
WORLDS = ROOT / "tests" / "data" / "worlds" / "wrestling"  # vendored (see its NOTICE)
WORLD = WORLDS / "worlds" / "wrestling.wbt"
MOTION = WORLDS / "controllers" / "motions" / "HandWave.motion"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--loops", type=int, default=4)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    if not (WORLD.is_file() and MOTION.is_file()):
        print(f"{WORLDS} not found (the vendored worlds are needed)", file=sys.stderr)
        return 2

    from motiontool.sim import PlayOptions, play
    from motiontool.sim.world import read_world
    from motiontool.sim.world_run import world_run

    options = PlayOptions(timestep_ms=10, loops=args.loops, hold_s=0.0)
    in_world = PlayOptions(loops=args.loops, hold_s=0.0)  # the step from the world

    def plain() -> None:
        play([MOTION], robot="nao", options=options)

    def world() -> None:
        play(
            [MOTION],
            robot="nao",
            options=in_world,
            world=world_run(read_world(WORLD, "participant", "nao")),
        )

    report = play(
        [MOTION],
        robot="nao",
        options=in_world,
        world=world_run(read_world(WORLD, "participant", "nao")),
    )
    plain_s = best_of(args.repeat, plain)
    world_s = best_of(args.repeat, world)
    print(f"HandWave x{args.loops}: {report.simulated_s:.1f} s simulated at 10 ms")
    print(f"play:          {plain_s:.3f} s")
    print(f"play --world:  {world_s:.3f} s")
    print(f"ratio:         {world_s / plain_s:.3f} (target <= 1.05)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
