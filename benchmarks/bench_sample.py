"""Benchmark: ``motiontool sample`` streams (issue #15 item 6). Memory stays flat whatever the
duration, and the first row is out at once however long the motion plays.

Run: ``python benchmarks/bench_sample.py``. For 3-pose, 26-joint motions playing 1 min, 10 min
and 100 min at 1 ms it prints the peak memory (RSS) of the whole run, CSV and JSON, with its ratio
to the 1-minute run measured in the same run; and the time to the first row of a motion playing
24 days, with its ratio to the time the 1-minute motion takes to its first row. Targets: peak
RSS ratio <= 1.1 from 1 to 100 minutes (flat); first-row ratio <= 1.5 (at once).
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

JOINTS = 26
MINUTE_MS = 60_000


def motiontool() -> str:
    found = shutil.which("motiontool", path=str(Path(sys.executable).parent))
    if found is None:
        sys.exit("motiontool is not installed next to this Python (pip install -e .)")
    return found


def make_file(path: Path, duration_ms: int) -> None:
    names = ",".join(f"J{j}" for j in range(JOINTS))
    zeros = ",".join("0" for _ in range(JOINTS))
    ones = ",".join("1" for _ in range(JOINTS))
    path.write_text(
        f"#WEBOTS_MOTION,V1.0,{names}\n0,P,{zeros}\n{duration_ms // 2},Q,{ones}\n"
        f"{duration_ms},R,{zeros}\n"
    )


def peak_rss_mib(args: list[str]) -> float:
    """The peak resident memory of ``args`` run to the end (its output thrown away), MiB."""
    probe = (
        "import resource, subprocess, sys\n"
        "subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, check=True)\n"
        "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)\n"
    )
    out = subprocess.run([sys.executable, "-c", probe, *args], capture_output=True, check=True)
    return int(out.stdout) / 1024  # ru_maxrss is in KiB on Linux


def first_row_s(args: list[str]) -> float:
    """Seconds until ``args`` has written its header and first row (then it is stopped)."""
    t0 = time.perf_counter()
    with subprocess.Popen(args, stdout=subprocess.PIPE) as proc:
        assert proc.stdout is not None
        proc.stdout.readline()
        proc.stdout.readline()
        elapsed = time.perf_counter() - t0
        proc.kill()
    return elapsed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=3, help="timings per case (best kept)")
    args = parser.parse_args()
    exe = motiontool()
    with tempfile.TemporaryDirectory() as tmp:
        files = {}
        for minutes in (1, 10, 100):
            files[minutes] = Path(tmp) / f"m{minutes}.motion"
            make_file(files[minutes], minutes * MINUTE_MS)
        days = Path(tmp) / "days.motion"
        make_file(days, 24 * 24 * 60 * MINUTE_MS)
        for fmt in ("csv", "json"):
            base = peak_rss_mib([exe, "sample", str(files[1]), "-t", "1", "-f", fmt])
            print(f"sample -f {fmt}, peak RSS: 1 min {base:.0f} MiB (baseline)")
            for minutes in (10, 100):
                rss = peak_rss_mib([exe, "sample", str(files[minutes]), "-t", "1", "-f", fmt])
                print(
                    f"  {minutes} min ({minutes * 60_000} rows): {rss:.0f} MiB, x{rss / base:.2f}"
                )
        short = min(
            first_row_s([exe, "sample", str(files[1]), "-t", "1"]) for _ in range(args.repeat)
        )
        long = min(first_row_s([exe, "sample", str(days), "-t", "1"]) for _ in range(args.repeat))
        print(
            f"first row: 1 min motion {short:.3f} s (baseline), 24 days {long:.3f} s, x{long / short:.2f}"
        )


if __name__ == "__main__":
    main()
