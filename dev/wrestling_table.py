"""The targets in Webots' wrestling world, with the world's own settings, under
``--robustness`` (docs/simulation.md, *Playing in a Webots world*).

Plays the wrestling motions vendored in ``tests/data/worlds/wrestling/controllers/motions/``
through the CLI, as a user would: the get-ups and the turns in one ``motiontool batch
--robustness 8 --seed 0 --jobs 2`` (their ``motions.toml`` there names the world, the robot node
``participant``, the lying start or the Stand played before, and ``expect --infer``'s
expectations), the looped motions with ``motiontool play --loop NAME=N --chain --robustness 8``
(batch has no loops; a side-step loop plays after Stand, its sidecar's ``after``). Prints a
Markdown table: each target, what its run measured at the defaults and each verdict over the
members (holds, fragile k/n with the members that disagree, fails). Not a test
(about a minute on 2 cores): run it by hand,

    .venv/bin/python dev/wrestling_table.py              # --members 8 --seed 0 --jobs 2

Every run is deterministic: the same command prints the same table.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
WRESTLING = ROOT / "tests" / "data" / "worlds" / "wrestling"
MOTIONS = WRESTLING / "controllers" / "motions"
WORLD = WRESTLING / "worlds" / "wrestling.wbt"
CLI = [str(Path(sys.executable).parent / "motiontool")]

BATCHED = (
    "GetUpFront",
    "GetUpBack",
    "TurnLeft20",
    "TurnRight20",
    "TurnLeft40",
    "TurnRight40",
    "TurnLeft60",
    "TurnRight60",
)
"""Played once each by batch, with their sidecar (start, after = "Stand", expectations)."""

HAND_WAVE_WORLD = ("--world", str(WORLD), "--robot-node", "participant")

LOOPED = (
    ("SideStepLeftLoop", 4, ()),
    ("SideStepRightLoop", 4, ()),
    # No sidecar section (the world's tests play HandWave bare): the world and the
    # expectations that expect --infer proposes for it, on the command line.
    ("HandWave", 12, (*HAND_WAVE_WORLD, "--expect", "upright", "--expect", "feet-planted")),
)
"""(motion, loops, extra play arguments): looped as the controller loops a *Loop motion
(utils/motion_library.py: after Stand, its sidecar's ``after``; ``--loop NAME=N`` loops it
alone) and as the opponent loops HandWave, 4 and 12 times (61 s)."""


def _run(args: list[str]) -> None:
    done = subprocess.run([*CLI, *args], capture_output=True, text=True, check=False)
    if done.returncode not in (0, 1):
        raise SystemExit(f"wrestling_table: {' '.join(args)} exited {done.returncode}:\n"
                         f"{done.stdout}{done.stderr}")  # fmt: skip


def _measured(report: dict[str, Any]) -> str:
    """The run at the defaults: the base (dx, dy, yaw), the fall, a foot's largest move and
    the self-collisions (units in the text)."""
    base = report["base"]
    parts = [
        f"dx {base['dx_m']:+.3f} m, dy {base['dy_m']:+.3f} m, yaw {base['yaw_change_deg']:+.1f}°"
    ]
    if base.get("fell"):
        parts.append(f"fell at {base['fell_at_s']:.2f} s")
    parts.append(f"final tilt {base['final_tilt_deg']:.1f}°")
    feet = report.get("feet") or []
    if feet:
        parts.append(f"a foot moved {max(f['max_displacement_m'] for f in feet) * 1000:.1f} mm")
    pairs = sorted({f"{c['body_a']}/{c['body_b']}" for c in report.get("self_collisions") or []})
    if pairs:
        parts.append("self-collisions " + ", ".join(pairs))
    return "; ".join(parts)


def _verdicts(robustness: dict[str, Any]) -> str:
    out = []
    for v in robustness["verdicts"]:
        text = f"{v['name']} **{v['status']}**"
        if v["disagree"]:
            who = ", ".join(
                f"#{d['sample']} (μ ×{d['values'].get('friction', 1):.2f}, "
                f"{d['values'].get('physics-step', 0):g} ms)"
                for d in v["disagree"]
            )
            how = "pass" if v["status"] == "fails" else "disagree"
            text += f" ({len(v['disagree'])} of {v['members']} {how}: {who})"
        out.append(text)
    return "; ".join(out)


def _row(report: dict[str, Any], robustness: dict[str, Any]) -> str:
    names = [Path(f["path"]).stem + (f" ×{f['loops']}" if f["loops"] > 1 else "")
             for f in report["files"]]  # fmt: skip
    files = " + ".join(names)
    return f"| {files} | {_measured(report)} | {_verdicts(robustness)} |"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--members", type=int, default=8, help="--robustness N (default 8)")
    parser.add_argument("--seed", type=int, default=0, help="--seed (default 0)")
    parser.add_argument("--jobs", type=int, default=2, help="--jobs (default 2)")
    args = parser.parse_args()
    common = ["--robustness", str(args.members), "--seed", str(args.seed)]
    common += ["--jobs", str(args.jobs), "--no-cache"]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "batch.json"
        files = [str(MOTIONS / f"{m}.motion") for m in BATCHED]
        _run(["batch", *files, *common, "--json", str(out)])
        runs = {Path(r["spec"]["path"]).stem: r for r in json.loads(out.read_text())["runs"]}
        rows += [_row(runs[m]["report"], runs[m]["robustness"]) for m in BATCHED]
        for name, loops, extra in LOOPED:
            out = Path(tmp) / f"{name}.json"
            motion = str(MOTIONS / f"{name}.motion")
            _run(["play", "--headless", motion, "--loop", f"{name}={loops}", "--chain", *extra,
                  *common, "--json", str(out)])  # fmt: skip
            report = json.loads(out.read_text())
            rows.append(_row(report, report["robustness"]))
    print(f"| motion | run (world's settings) | verdicts over {args.members} members "
          f"(seed {args.seed}) |")  # fmt: skip
    print("|---|---|---|")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
