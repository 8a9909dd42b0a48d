"""How the Webots walks move with the floor friction and the physics step (docs/play.md).

Plays motions of the Webots corpus (``tests/data/corpus/webots/``) on the Nao from the standing
zero pose, through the library (:func:`motiontool.sim.play`), at every floor friction x physics
step of the grid, in a process pool, and prints a Markdown table: motion, μ, step (ms), dx (m),
dy (m), yaw (°), max tilt (°), fell (at s). The control step is the Nao's 20 ms throughout, so
a physics step must divide 20 ms. Not a test (it takes minutes): run it by hand, e.g.

    .venv/bin/python dev/fidelity_sweep.py --jobs 2                  # 3 x 6 x 5 = 90 runs
    .venv/bin/python dev/fidelity_sweep.py --friction 0.5 1 2 3 --step 1 2 4 \\
        --point 7@2 --point 1@20 --point 7@20                         # the issue's grid + 3

Every run is deterministic: the same grid prints the same table.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CORPUS = ROOT / "tests" / "data" / "corpus" / "webots"

MOTIONS = ("Forwards50", "TurnLeft60", "TaiChi")
FRICTIONS = (0.5, 1.0, 2.0, 3.0, 5.0, 7.0)
STEPS_MS = (1.0, 2.0, 4.0, 10.0, 20.0)


@dataclass(frozen=True)
class Row:
    """One run's outcome (units in the names; ``fell_at_s`` None when it did not fall)."""

    motion: str
    friction: float
    step_ms: float
    dx_m: float
    dy_m: float
    yaw_deg: float | None
    max_tilt_deg: float
    fell_at_s: float | None
    warnings: str
    wall_s: float


def corpus_file(name: str) -> Path:
    found = sorted(CORPUS.rglob(f"{name}.motion"))
    if not found:
        raise SystemExit(f"fidelity_sweep: {name}.motion is not in the Webots corpus at {CORPUS}")
    return found[0]


def run_one(job: tuple[str, float, float]) -> Row:
    """Play ``job`` = (motion, friction, physics step in ms) and measure it."""
    from motiontool.sim import PlayOptions, play

    name, friction, step_ms = job
    t0 = time.monotonic()
    options = PlayOptions(floor_friction=friction, physics_step_ms=step_ms)
    report = play([corpus_file(name)], robot="nao", options=options)
    base = report.base
    assert base is not None, "the Nao has a free-flying base"
    raised = ", ".join(f"{k} x{v}" for k, v in sorted(report.warnings.items()) if v)
    return Row(
        name,
        friction,
        step_ms,
        base.dx_m,
        base.dy_m,
        base.yaw_change_deg,
        base.max_tilt_deg,
        base.fell_at_s,
        raised,
        time.monotonic() - t0,
    )


def parse_point(text: str) -> tuple[float, float]:
    """``7@20`` -> (friction 7, physics step 20 ms)."""
    friction, sep, step = text.partition("@")
    try:
        if not sep:
            raise ValueError
        return float(friction), float(step)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{text!r}: expected FRICTION@STEP_MS, e.g. 7@20"
        ) from None


def markdown(rows: list[Row]) -> str:
    lines = [
        "| motion | μ | step (ms) | dx (m) | dy (m) | yaw (°) | max tilt (°) | fell (at s) |",
        "|---|---:|---:|---:|---:|---:|---:|---|",
    ]
    for r in rows:
        yaw = "n/a" if r.yaw_deg is None else f"{r.yaw_deg:+.1f}"
        fell = "no" if r.fell_at_s is None else f"falls at {r.fell_at_s:.2f} s"
        if r.warnings:
            fell += f" (MuJoCo warnings: {r.warnings})"
        lines.append(
            f"| {r.motion} | {r.friction:g} | {r.step_ms:g} | {r.dx_m:+.3f} | {r.dy_m:+.3f} "
            f"| {yaw} | {r.max_tilt_deg:.1f} | {fell} |"
        )
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--jobs", "-j", type=int, default=2, help="parallel runs (default 2)")
    parser.add_argument("--motions", nargs="+", default=list(MOTIONS), help="corpus motions")
    parser.add_argument("--friction", nargs="+", type=float, default=list(FRICTIONS))
    parser.add_argument("--step", nargs="+", type=float, default=list(STEPS_MS), help="ms")
    parser.add_argument(
        "--point",
        action="append",
        type=parse_point,
        default=[],
        help="an extra FRICTION@STEP_MS run (repeatable), e.g. 7@20",
    )
    parser.add_argument("--json", type=Path, help="also write the rows as JSON here")
    args = parser.parse_args(argv)
    if args.jobs < 1:
        parser.error("--jobs must be >= 1")
    points = [(f, s) for f in args.friction for s in args.step]
    points += [p for p in args.point if p not in points]
    jobs = [(m, f, s) for m in args.motions for f, s in points]
    t0 = time.monotonic()
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        rows = list(pool.map(run_one, jobs))
    rows.sort(key=lambda r: (args.motions.index(r.motion), r.friction, r.step_ms))
    sys.stdout.write(markdown(rows))
    sys.stderr.write(f"{len(rows)} runs in {time.monotonic() - t0:.0f} s wall ({args.jobs} jobs)\n")
    if args.json is not None:
        args.json.write_text(json.dumps([r.__dict__ for r in rows], indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
