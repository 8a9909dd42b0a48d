"""Benchmark: what a motion's duration costs in memory where the output does not grow with it
(``plot``: one picture) and where it does (``convert`` to a robot format: a target, a message
or a servoj line per control step).

Run: ``python benchmarks/bench_duration.py``. 3-pose motions of the Nao's 40 joints (and the
UR5e's 6 for URScript) playing 6 minutes and 10 times as long; for each command the peak
memory (RSS) of the whole process at both durations and their ratio, measured in the same
run. Target: ``plot`` flat (ratio <= 1.3x for 10x the duration; 60 and 600 minutes as well),
and ``resample --step`` flat from 60 to 600 minutes: it writes its grid and compares it with
the original a block at a time (motionfmt/resample_grid.py), where it held both (3 GB for
11 h of 22 joints); 6 minutes (18,000 steps) fill less than its blocks, so its ratio to the
shortest run is printed too, without a target.
``convert --to naoqi`` and ``--to ros-trajectory`` flat as well (their output holds the
keys, not the steps): they make Webots' stream a chunk of steps at a time for their keys,
their deviation and their robot check (motionfmt/convert/held.py ``held_chunks``), where they
held it (NAOqi three times: 1.35 GB for 10 h of 40 joints). ``--to rosbag`` makes its
messages from the stream a chunk at a time too, and holds the bag it writes, as
``--to urscript`` holds the program it writes (a servoj line a step): no target, their files
grow with the duration.
"""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
from pathlib import Path
from typing import NamedTuple

from _timing import Child, run_child  # benchmarks/_timing.py (run as a script)

from motiontool.kinematics.robots import load_robot

MINUTE_MS = 60_000
FLAT = 1.3
STAR = ("Head", "Elbow", "Wrist")
"""Joints that get no command ('*') halfway: dotted held lines in the plot."""


def motiontool() -> str:
    found = shutil.which("motiontool", path=str(Path(sys.executable).parent))
    if found is None:
        sys.exit("motiontool is not installed next to this Python (pip install -e .)")
    return found


def make_file(path: Path, robot: str, duration_ms: int) -> None:
    """Three poses within the robot's limits, 40 % and 60 % of each joint's range; halfway
    the head, elbows and wrists get no command ('*')."""
    joints = load_robot(robot).joints

    def pose(share: float, star: bool = False) -> str:
        return ",".join(
            "*"
            if star and any(w in j.name for w in STAR)
            else repr(j.lower + share * (j.upper - j.lower))
            for j in joints
        )

    names = ",".join(j.name for j in joints)
    path.write_text(
        f"#WEBOTS_MOTION,V1.0,{names}\n0,P,{pose(0.4)}\n"
        f"{duration_ms // 2},Q,{pose(0.6, star=True)}\n{duration_ms},R,{pose(0.4)}\n"
    )


class Case(NamedTuple):
    """One command: its words, the motion it reads, its output's suffix, extra arguments, the
    control step (ms) and how many joints the stream it sends has (0: none, a picture or a
    motion file, by ``suffix``)."""

    label: str
    robot: str
    suffix: str
    extra: tuple[str, ...] = ()
    step_ms: int = 20
    joints: int = 0
    flat: bool = False
    flat_from: int = 0
    """The run (0: the shortest) from which memory must stay flat."""


CASES = (
    Case("plot", "nao", "png", flat=True),
    Case("convert --to rosbag", "nao", "mcap", ("--robot", "nao")),
    Case("convert --to naoqi", "nao", "json", ("--robot", "nao-v5"), joints=40, flat=True),
    Case("convert --to ros-trajectory", "nao", "yaml", ("--robot", "nao"), joints=40, flat=True),
    Case("convert --to urscript", "ur5e", "script", step_ms=8),
    Case("resample --step 20", "nao", "motion", flat=True, flat_from=1),
)


def measure(tool: str, tmp: Path, case: Case, minutes: int) -> Child:
    """``case`` on the motion of ``minutes``, in a child process."""
    words = case.label.split()
    src, out = tmp / f"{case.robot}{minutes}.motion", tmp / f"out.{case.suffix}"
    if words[0] in ("plot", "resample"):
        cmd = [words[0], str(src), "-o", str(out), *words[1:]]
    else:
        cmd = [*words[:1], str(src), str(out), *words[1:], *case.extra]
    child = run_child([tool, *cmd])
    if child.returncode != 0:
        sys.exit(f"{case.label}, {minutes} min: exit status {child.returncode}")
    return child


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=int, default=6, help="the shortest duration")
    short = parser.parse_args().minutes
    tool = motiontool()
    durations = (short, 10 * short, 100 * short)
    print(f"3-pose motions of {', '.join(map(str, durations))} min; peak RSS (whole process)")
    with tempfile.TemporaryDirectory(prefix="bench-duration-") as folder:
        tmp = Path(folder)
        for robot in ("nao", "ur5e"):
            for minutes in durations:
                make_file(tmp / f"{robot}{minutes}.motion", robot, minutes * MINUTE_MS)
        for case in CASES:
            print(_line(case, tool, tmp, durations), flush=True)


def _line(case: Case, tool: str, tmp: Path, durations: tuple[int, ...]) -> str:
    """``case`` at each duration (all three where memory should be flat), its peaks and their
    ratio."""
    runs = durations if case.flat else durations[:2]
    peaks = [measure(tool, tmp, case, minutes) for minutes in runs]
    shown = " -> ".join(f"{c.peak_mib:.0f}" for c in peaks)
    ratio = max(c.peak_bytes for c in peaks) / peaks[0].peak_bytes
    line = f"{case.label:<28} {shown} MiB, ratio {ratio:.2f}x"
    if case.flat:
        base = peaks[case.flat_from]
        grown = max(c.peak_bytes for c in peaks[case.flat_from :]) / base.peak_bytes
        which = "" if case.flat_from == 0 else f" from {runs[case.flat_from]} min: {grown:.2f}x"
        met = "met" if grown <= FLAT else "not met"
        return line + f" (target <= {FLAT}x{which}, flat: {met})"
    if case.joints:
        steps = runs[-1] * MINUTE_MS // case.step_ms + 1
        return line + (
            f" (the stream it sends at {runs[-1]} min: {steps * case.joints * 8 / 2**20:.0f} MiB)"
        )
    return line


if __name__ == "__main__":
    main()
