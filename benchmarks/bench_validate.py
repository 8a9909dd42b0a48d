"""Benchmark: syntax-level ``validate`` on a 100 000-pose, 26-joint Nao-style file (about 26 MB),
and the start-up time of ``motiontool validate small.motion``.

Run: ``python benchmarks/bench_validate.py``. Every time is printed with its ratio to a baseline
measured in the same run: reading the file and splitting it into tokens in plain Python, and
starting a bare ``python -c pass``. Targets (issue 2): validate <= 1.0 s (Webots' C reader takes
about 0.6 s), start-up < 0.3 s.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _timing import best_of  # benchmarks/_timing.py (run as a script)

JOINTS = [
    "HeadYaw", "HeadPitch", "LShoulderPitch", "LShoulderRoll", "LElbowYaw", "LElbowRoll",
    "LWristYaw", "LHipYawPitch", "LHipRoll", "LHipPitch", "LKneePitch", "LAnklePitch",
    "LAnkleRoll", "RHipYawPitch", "RHipRoll", "RHipPitch", "RKneePitch", "RAnklePitch",
    "RAnkleRoll", "RShoulderPitch", "RShoulderRoll", "RElbowYaw", "RElbowRoll", "RWristYaw",
    "LPhalanx1", "RPhalanx1",
]  # fmt: skip


def make_file(path: Path, poses: int, seed: int = 0) -> None:
    rng = np.random.default_rng(seed)
    values = rng.uniform(-2.0, 2.0, size=(poses, len(JOINTS)))
    with path.open("w", newline="\n") as f:
        f.write("#WEBOTS_MOTION,V1.0," + ",".join(JOINTS) + "\n")
        for p in range(poses):
            t = 40 * p
            cells = ",".join(repr(round(float(v), 6)) for v in values[p])
            f.write(f"{t // 60000:02d}:{t // 1000 % 60:02d}:{t % 1000:03d},Pose{p + 1},{cells}\n")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--poses", type=int, default=100_000)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()

    from motiontool.motionfmt import read_file, validate_bytes

    with tempfile.TemporaryDirectory() as tmp:
        big = Path(tmp) / "big.motion"
        make_file(big, args.poses)
        size_mb = big.stat().st_size / 1e6

        def baseline() -> None:
            data = big.read_bytes()
            [line.split(b",") for line in data.split(b"\n")]

        def validate() -> None:
            report = validate_bytes(read_file(big), str(big))
            assert report.read.accepted and len(report.read.times_ms) == args.poses

        t_base = best_of(args.repeat, baseline)
        t_val = best_of(args.repeat, validate)
        print(f"file: {args.poses} poses x {len(JOINTS)} joints, {size_mb:.1f} MB")
        print(f"baseline (read + split into tokens, plain Python): {t_base:.3f} s")
        print(
            f"validate (syntax level, in process):               {t_val:.3f} s  ratio {t_val / t_base:.2f}x baseline  (target <= 1.0 s)"
        )

        small = Path(tmp) / "small.motion"
        small.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,Pose1,0\n00:00:500,Pose2,0.5\n")
        script = shutil.which("motiontool", path=os.path.dirname(sys.executable)) or "motiontool"

        def run(cmd: list[str]) -> float:
            samples = []
            for _ in range(5):
                t0 = time.perf_counter()
                subprocess.run(cmd, check=False, capture_output=True)
                samples.append(time.perf_counter() - t0)
            return statistics.median(samples)

        t_cold = run([script, "validate", "--robot", "none", str(big)])
        print(
            f"motiontool validate big.motion, whole process:     {t_cold:.3f} s  ratio {t_cold / t_base:.2f}x baseline  (start-up and imports included)"
        )

        t_py = run([sys.executable, "-c", "pass"])
        t_cli = run([script, "validate", "--robot", "none", str(small)])
        print(f"start-up, bare python -c pass:                     {t_py:.3f} s")
        print(
            f"start-up, motiontool validate small.motion:        {t_cli:.3f} s  ratio {t_cli / t_py:.2f}x bare python  (target < 0.3 s)"
        )


if __name__ == "__main__":
    main()
