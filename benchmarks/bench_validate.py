"""Benchmark: syntax-level ``validate`` on a 100 000-pose, 26-joint Nao-style file (about 26 MB),
and the start-up time of ``motiontool validate small.motion``.

Run: ``python benchmarks/bench_validate.py``. Every time is printed with its ratio to a baseline
measured in the same run: reading the file and splitting it into tokens in plain Python, and
starting a bare ``python -c pass``. Targets (issue 2): validate <= 1.0 s (Webots' C reader takes
about 0.6 s), start-up < 0.3 s.

The C baseline (issue 17 item 4): a small C program compiled here with ``cc -O2`` that reads the
file as Webots' ``wbu_motion_new`` does (``fgets`` of 4096-byte pieces, ``strtok`` on ``",\n\r"``,
``sscanf``/``strtod`` per value, times and values in growing arrays), run as a child process like
``motiontool validate --robot none``; both are timed (wall) and their peak resident memory
measured (GNU time). Targets: syntax-level validate at most 0.6x the C loader's wall time, and a
peak under 3x the file's size. Without ``cc`` the C baseline is skipped (the script says so).
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
from _timing import Child, best_child, best_of  # benchmarks/_timing.py (run as a script)

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


C_LOADER = r"""
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Reads a .motion file as Webots' wbu_motion_new does: fgets of 4096-byte pieces, strtok on
   ",\n\r", the time with sscanf, each value with strtod ('*' is no value), times and values
   kept in arrays that grow. Prints the pose count so that nothing is optimised away. */
int main(int argc, char **argv) {
  FILE *f = fopen(argv[1], "r");
  if (!f) return 2;
  char line[4096];
  int n_joints = 0, n_poses = 0, cap = 16;
  int *times = malloc(cap * sizeof(int));
  double *values = NULL;
  char **names = NULL;
  if (!fgets(line, sizeof(line), f)) return 3;
  for (char *tok = strtok(line, ",\n\r"); tok; tok = strtok(NULL, ",\n\r")) {
    names = realloc(names, (n_joints + 1) * sizeof(char *));
    names[n_joints++] = strdup(tok);
  }
  n_joints -= 2; /* #WEBOTS_MOTION, V1.0 */
  values = malloc((size_t)cap * n_joints * sizeof(double));
  while (fgets(line, sizeof(line), f)) {
    char *tok = strtok(line, ",\n\r");
    if (!tok) break;
    int m, s, ms;
    if (sscanf(tok, "%d:%d:%d", &m, &s, &ms) != 3) return 4;
    if (n_poses == cap) {
      cap *= 2;
      times = realloc(times, cap * sizeof(int));
      values = realloc(values, (size_t)cap * n_joints * sizeof(double));
    }
    times[n_poses] = 60000 * m + 1000 * s + ms;
    if (!strtok(NULL, ",\n\r")) return 5; /* the pose name */
    for (int j = 0; j < n_joints; j++) {
      tok = strtok(NULL, ",\n\r");
      if (!tok) return 6;
      values[(size_t)n_poses * n_joints + j] = tok[0] == '*' ? -9999999.9 : strtod(tok, NULL);
    }
    n_poses++;
  }
  fclose(f);
  printf("%d\n", n_poses);
  return n_poses > 0 ? 0 : 7;
}
"""


def c_loader(tmp: Path) -> Path | None:
    """The C baseline compiled with ``cc -O2`` into ``tmp``, or None without a C compiler."""
    cc = shutil.which("cc")
    if cc is None:
        return None
    source = tmp / "load_motion.c"
    source.write_text(C_LOADER)
    exe = tmp / "load_motion"
    subprocess.run([cc, "-O2", "-o", str(exe), str(source)], check=True)
    return exe


def report_c_baseline(tmp: Path, big: Path, validate_cmd: list[str], repeat: int) -> None:
    """Syntax-level ``validate`` (whole process) against the C loader, measured in this run."""
    exe = c_loader(tmp)
    if exe is None:
        print("C baseline skipped: no C compiler (cc) on this machine")
        return
    size = big.stat().st_size
    c: Child = best_child(repeat, [str(exe), str(big)])
    v: Child = best_child(repeat, validate_cmd)
    if c.returncode != 0 or v.returncode != 0:
        raise SystemExit(f"exit status: C loader {c.returncode}, validate {v.returncode}")
    time_ratio, peak_ratio = v.wall_s / c.wall_s, v.peak_bytes / size
    print(
        f"C loader (Webots' reading, cc -O2):                {c.wall_s:.3f} s, {c.peak_mib:.0f} MiB peak"
    )
    print(
        f"validate --robot none, whole process:              {v.wall_s:.3f} s, {v.peak_mib:.0f} MiB peak"
    )
    print(
        f"  wall time {time_ratio:.2f}x the C loader (target <= 0.6x: "
        f"{'met' if time_ratio <= 0.6 else 'not met'})"
    )
    print(
        f"  peak {peak_ratio:.2f}x the file's size {size / 2**20:.0f} MiB (target < 3x: "
        f"{'met' if peak_ratio < 3 else 'not met'}); {v.peak_bytes / c.peak_bytes:.1f}x the C loader's peak"
    )


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

        report_c_baseline(Path(tmp), big, [script, "validate", "--robot", "none", str(big)], 5)

        t_py = run([sys.executable, "-c", "pass"])
        t_cli = run([script, "validate", "--robot", "none", str(small)])
        print(f"start-up, bare python -c pass:                     {t_py:.3f} s")
        print(
            f"start-up, motiontool validate small.motion:        {t_cli:.3f} s  ratio {t_cli / t_py:.2f}x bare python  (target < 0.3 s)"
        )


if __name__ == "__main__":
    main()
