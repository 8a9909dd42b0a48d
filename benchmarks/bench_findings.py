"""Benchmark: ``validate --robot nao`` on a file with random values, whole
process, against the syntax level on the same file measured in the same run.

Run: ``python benchmarks/bench_findings.py`` (``--poses 10000`` for a quick run). The file is
``bench_validate.py``'s: 26 joints, uniform(-2, 2) rad values, 100 000 poses (26 MB), so that
most cells are past a limit and most segments too fast (3.5 million findings one per pose).
Each command's report goes to a file (the bytes are written, then thrown away), and is timed
(wall) with its peak resident memory (GNU time). Printed:

- the syntax level, ``validate --robot none``: the baseline;
- ``validate --robot nao`` (grouped, the default checks) and its ratio to the baseline
  (target: at most 3x);
- ``validate --robot nao --no-group``: its peak (target: under 1 GB, the findings streamed to
  the output, never all held) and its ratio to the baseline;
- ``--format json`` and ``--format sarif`` (grouped, each finding with its fix): peak and time;
- how many findings and bytes each report has;
- memory across files: runs over 10 and 40 files of 10 000 random poses (2.6 MB each), the
  larger run's peak against the smaller's (flat: a run holds the reports of its first 32 MiB
  of input, the others are validated as the report reaches them).
- memory along a file (``--part long``): clean motions (every joint of the Nao on a slow sine
  within its limits, no finding) of 25 000 and 100 000 poses: the robot checks' peak above the
  syntax level's, per MB of file. No target: the checks keep a few bytes a cell (the held
  targets, the velocity check's moves), so what they add grows with the file; the blocks they
  work on do not (16 MiB per MB before they worked a block at a time, 3.8 now).
  Then a motion of the head alone, 400 000 poses: its time against the syntax level's (the
  collision check clears a pair of joints for a block of poses that cannot bring them near:
  ``kinematics/sweep_bound.py``).
- the reader's findings (``--part units``): files whose every value cell has a unit
  (``0.5rad``, a finding and a fix each) of 16,000 and 64,000 poses (416,000 and 1,664,000
  findings), ``validate --robot none`` to a report file, against the same files without the
  units: what the findings add to the peak, the larger file's against the smaller's (target:
  flat, at most 1.3x; the reader keeps the last 65,536 findings and writes older ones to a
  temporary file, ``motionfmt/finding_log.py``, where it held them all, half a kilobyte
  each).
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
from pathlib import Path

from _timing import Child, best_child  # benchmarks/_timing.py (run as a script)
from bench_validate import make_file

GIB = 2**30


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--poses", type=int, default=100_000)
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument(
        "--part",
        choices=("all", "big", "many", "long", "units"),
        default="all",
        help="the big file, many files, clean files of two lengths, a finding on every cell",
    )
    args = parser.parse_args()
    script = shutil.which("motiontool", path=os.path.dirname(sys.executable)) or "motiontool"
    with tempfile.TemporaryDirectory() as tmp:
        if args.part in ("all", "big"):
            big_file(script, Path(tmp), args.poses, args.repeat)
        if args.part in ("all", "many"):
            many_files(script, Path(tmp), args.repeat)
        if args.part in ("all", "long"):
            long_files(script, Path(tmp), args.repeat)
        if args.part in ("all", "units"):
            reader_findings(script, Path(tmp), args.repeat)


def big_file(script: str, tmp: Path, poses: int, repeat: int) -> None:
    """One file of ``poses`` random poses: the syntax level, then the robot checks."""
    big = tmp / "random.motion"
    make_file(big, poses)
    out = tmp / "report"
    size = big.stat().st_size
    print(f"file: {poses} poses x 26 joints, uniform(-2, 2) rad, {size / 1e6:.1f} MB")

    def measure(label: str, *extra: str) -> Child:
        cmd = [script, "validate", str(big), "-o", str(out), *extra]
        child = best_child(repeat, cmd)
        if child.returncode not in (0, 1):
            raise SystemExit(f"{label}: exit status {child.returncode}")
        text = out.read_bytes()
        lines = text.count(b"\n")
        print(
            f"{label:<40} {child.wall_s:7.2f} s  {child.peak_mib:7.0f} MiB peak  "
            f"report {len(text) / 1e6:8.1f} MB, {lines:,} lines"
        )
        return child

    base = measure("validate --robot none (syntax level)", "--robot", "none")
    grouped = measure("validate --robot nao", "--robot", "nao")
    flat = measure("validate --robot nao --no-group", "--robot", "nao", "--no-group")
    as_json = measure("validate --robot nao --format json", "--robot", "nao", "-f", "json")
    as_sarif = measure("validate --robot nao --format sarif", "--robot", "nao", "-f", "sarif")
    ratio = grouped.wall_s / base.wall_s
    print(
        f"grouped: {ratio:.1f}x the syntax level's wall time (target <= 3x: "
        f"{'met' if ratio <= 3 else 'not met'})"
    )
    print(
        f"--no-group: peak {flat.peak_bytes / GIB:.2f} GiB (target < 1 GiB: "
        f"{'met' if flat.peak_bytes < GIB else 'not met'}), "
        f"{flat.wall_s / base.wall_s:.1f}x the syntax level's wall time"
    )
    print(f"json: peak {as_json.peak_bytes / GIB:.2f} GiB, {as_json.wall_s:.1f} s")
    print(f"sarif: peak {as_sarif.peak_bytes / GIB:.2f} GiB, {as_sarif.wall_s:.1f} s")


def many_files(script: str, tmp: Path, repeat: int, counts: tuple[int, int] = (10, 40)) -> None:
    """Runs over few and many files of 10 000 random poses (2.6 MB each): the peak of the
    larger run against the smaller's (target: flat, at most 1.3x, whatever the number of
    files; a run holds the reports of its first 32 MiB of input only)."""
    peaks = {}
    for robot in ("none", "nao"):
        for files in counts:
            folder = tmp / f"many{files}"
            if not folder.exists():
                folder.mkdir()
                make_file(folder / "f0.motion", 10_000)
                for k in range(1, files):
                    (folder / f"f{k}.motion").write_bytes((folder / "f0.motion").read_bytes())
            total = sum(p.stat().st_size for p in folder.iterdir())
            child = best_child(repeat, [script, "validate", str(folder), "--robot", robot])
            peaks[robot, files] = child.peak_bytes
            print(
                f"{files} files, {total / 1e6:.0f} MB, --robot {robot}: {child.wall_s:.1f} s, "
                f"{child.peak_mib:.0f} MiB peak, {child.peak_bytes / total:.1f}x their size"
            )
        few, many = counts
        ratio = peaks[robot, many] / peaks[robot, few]
        print(
            f"--robot {robot}: {many} files peak at {ratio:.2f}x {few} files' (target <= 1.3x, "
            f"flat: {'met' if ratio <= 1.3 else 'not met'})"
        )


def clean_file(path: Path, poses: int, joints_named: tuple[str, ...] = ()) -> None:
    """Every Nao joint (or those ``joints_named``) on a 0.05 Hz sine about the middle of its
    range (a tenth of the range each side), a pose every 40 ms: within the limits and the
    velocities, no self-collision."""
    import numpy as np

    from motiontool.kinematics import load_robot
    from motiontool.motionfmt.writer import format_time

    joints = [j for j in load_robot("nao").joints if j.name in joints_named or not joints_named]
    lower, upper = np.array([j.lower for j in joints]), np.array([j.upper for j in joints])
    t_s = np.arange(poses) * 0.04
    phase = 2 * np.pi * 0.05 * t_s[:, None] + np.arange(len(joints))
    values = (lower + upper) / 2 + (upper - lower) * 0.1 * np.sin(phase)
    with path.open("w", newline="\n") as f:
        f.write("#WEBOTS_MOTION,V1.0," + ",".join(j.name for j in joints) + "\n")
        for p in range(poses):
            ms = 40 * p
            cells = ",".join(f"{v:.4f}" for v in values[p])
            f.write(f"{format_time(ms)},Pose{p + 1},{cells}\n")


def long_files(
    script: str, tmp: Path, repeat: int, lengths: tuple[int, int] = (25_000, 100_000)
) -> None:
    """What the default robot checks add to the syntax level's peak, per MB of a clean file,
    for a file and one four times as long."""
    added = {}
    for poses in lengths:
        path = tmp / f"clean{poses}.motion"
        clean_file(path, poses)
        size_mb = path.stat().st_size / 1e6
        syntax = best_child(repeat, [script, "validate", str(path), "--robot", "none"])
        checks = best_child(repeat, [script, "validate", str(path), "--robot", "nao"])
        if syntax.returncode != 0 or checks.returncode != 0:
            raise SystemExit(f"clean file: exit status {syntax.returncode}, {checks.returncode}")
        added[poses] = (checks.peak_bytes - syntax.peak_bytes) / 2**20 / size_mb
        print(
            f"clean file, {poses} poses ({size_mb:.0f} MB): syntax {syntax.wall_s:.2f} s, "
            f"{syntax.peak_mib:.0f} MiB; --robot nao {checks.wall_s:.2f} s, "
            f"{checks.peak_mib:.0f} MiB: the checks add {added[poses]:.1f} MiB per MB of file; "
            f"{checks.wall_s / syntax.wall_s:.1f}x the syntax level's time (the grouped target, "
            f"3x, on a motion a robot can play: {'met' if checks.wall_s <= 3 * syntax.wall_s else 'not met'})"
        )
    short, long = lengths
    print(
        f"{long // short}x the poses: the checks add {added[long] / added[short]:.2f}x as much per MB"
    )
    path = tmp / "nodding.motion"
    clean_file(path, 4 * long, ("HeadYaw", "HeadPitch"))
    syntax = best_child(repeat, [script, "validate", str(path), "--robot", "none"])
    checks = best_child(repeat, [script, "validate", str(path), "--robot", "nao"])
    if syntax.returncode != 0 or checks.returncode != 0:
        raise SystemExit(f"nodding file: exit status {syntax.returncode}, {checks.returncode}")
    print(
        f"the head alone, {4 * long} poses: syntax {syntax.wall_s:.2f} s; --robot nao "
        f"{checks.wall_s:.2f} s, ratio {checks.wall_s / syntax.wall_s:.1f}x"
    )


def reader_findings(
    script: str, tmp: Path, repeat: int, lengths: tuple[int, int] = (16_000, 64_000)
) -> None:
    """What the reader's findings add to the syntax level's peak: files with a unit on every
    value cell (26 findings a pose) against their twins without the units (no finding), a
    file and one four times as long (target: flat, at most 1.3x)."""
    from bench_validate import JOINTS

    added = {}
    for poses in lengths:
        peaks = {}
        for unit in ("", "rad"):
            path = tmp / f"units{poses}{unit}.motion"
            cells = ",".join(f"0.{j + 1}{unit}" for j in range(len(JOINTS)))
            with path.open("w", newline="\n") as f:
                f.write("#WEBOTS_MOTION,V1.0," + ",".join(JOINTS) + "\n")
                f.writelines(f"{40 * p},Pose{p + 1},{cells}\n" for p in range(poses))
            out = tmp / "report"
            cmd = [script, "validate", str(path), "--robot", "none", "-o", str(out)]
            child = best_child(repeat, cmd)
            if child.returncode != 0:  # warnings only
                raise SystemExit(f"units file: exit status {child.returncode}")
            peaks[unit] = child.peak_bytes
            print(
                f"{poses} poses, {'a unit on every cell' if unit else 'no finding':<20} "
                f"({path.stat().st_size / 1e6:4.1f} MB): {child.wall_s:5.1f} s, "
                f"{child.peak_mib:4.0f} MiB peak, report {out.stat().st_size / 1e6:4.0f} MB"
            )
        added[poses] = peaks["rad"] - peaks[""]
        print(
            f"  {poses * len(JOINTS):,} findings add {added[poses] / 2**20:.0f} MiB "
            f"({added[poses] / (poses * len(JOINTS)):.0f} bytes a finding)"
        )
    short, long = lengths
    ratio = added[long] / added[short]
    print(
        f"{long // short}x the findings: they add {ratio:.2f}x as much (target <= 1.3x, flat: "
        f"{'met' if ratio <= 1.3 else 'not met'})"
    )


if __name__ == "__main__":
    main()
