"""Benchmark: syntax-level ``validate`` on a 100 000-pose, 26-joint Nao-style file (about 26 MB),
and the start-up time of ``motiontool validate small.motion``.

Run: ``python benchmarks/bench_validate.py``. Every time is printed with its ratio to a baseline
measured in the same run: reading the file and splitting it into tokens in plain Python, and
starting a bare ``python -c pass``. Targets: validate <= 1.0 s (Webots' C reader takes
about 0.6 s), start-up < 0.3 s.

The C baseline: a small C program compiled here with ``cc -O2`` that reads the
file as Webots' ``wbu_motion_new`` (``src/controller/c/motion.c``) does: a first pass checks
every line (``fgets`` of 4096-byte pieces, ``strtok`` on ``",\n\r"``, the time with ``strspn``
and ``sscanf``, every value with ``sscanf("%lf")``) and counts the poses, a second pass reads
them again into one ``malloc`` per pose. It runs as a child process like ``motiontool validate
--robot none`` (bytecode cached, as installed); both are timed (wall) and their peak resident
memory measured (GNU time). Targets: syntax-level validate at most 0.6x the C loader's wall
time, and a peak under 3x the file's size. A lighter C reader (one pass, ``strtod``, growing
arrays: what this benchmark used as the baseline before, about 3x faster than Webots' own) is
printed for the record. Without ``cc`` the C baselines are skipped (the script says so).
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
    from motiontool.motionfmt.writer import format_time

    rng = np.random.default_rng(seed)
    values = rng.uniform(-2.0, 2.0, size=(poses, len(JOINTS)))
    with path.open("w", newline="\n") as f:
        f.write("#WEBOTS_MOTION,V1.0," + ",".join(JOINTS) + "\n")
        for p in range(poses):
            t = 40 * p
            cells = ",".join(repr(round(float(v), 6)) for v in values[p])
            f.write(f"{format_time(t)},Pose{p + 1},{cells}\n")


WEBOTS_LOADER = r"""
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Reads a .motion file as Webots' wbu_motion_new (src/controller/c/motion.c) does, in its two
   passes: a syntax check of every line (fgets of 4096-byte pieces, strtok on ",\n\r", the time
   checked with strspn and read with sscanf("%d:%d:%d"), each value read with sscanf("%lf"))
   that counts the poses; then rewind, one malloc per pose row, and the same lines read again
   into the arrays. Prints the pose count so that nothing is optimised away. */
#define SEP ",\n\r"

static int time_ms(const char *tok) {
  if (strspn(tok, "0123456789:") < strlen(tok)) return -1;
  int colons = 0;
  for (const char *c = tok; *c; c++) colons += *c == ':';
  int f[3] = {0, 0, 0}, got;
  switch (colons) {
    case 0: got = sscanf(tok, "%d", &f[2]); break;
    case 1: got = sscanf(tok, "%d:%d", &f[1], &f[2]); break;
    case 2: got = sscanf(tok, "%d:%d:%d", &f[0], &f[1], &f[2]); break;
    default: return -1;
  }
  return got == colons + 1 ? 60000 * f[0] + 1000 * f[1] + f[2] : -1;
}

int main(int argc, char **argv) {
  FILE *f = fopen(argv[1], "r");
  if (!f) return 2;
  char line[4096];
  int n_joints = 0, n_poses = 0, last = -1;
  if (!fgets(line, sizeof(line), f)) return 3;
  char *tok = strtok(line, SEP);
  if (!tok || strcmp(tok, "#WEBOTS_MOTION")) return 3;
  tok = strtok(NULL, SEP);
  if (!tok || strcmp(tok, "V1.0")) return 3;
  while (strtok(NULL, SEP)) n_joints++;
  while (fgets(line, sizeof(line), f)) { /* pass 1: the syntax */
    if (!(tok = strtok(line, SEP))) break;
    int t = time_ms(tok);
    if (t < 0 || t <= last) return 4;
    last = t;
    if (!strtok(NULL, SEP)) return 5; /* the pose name */
    for (int j = 0; j < n_joints; j++) {
      double v;
      if (!(tok = strtok(NULL, SEP))) return 6;
      if (strcmp(tok, "*") && sscanf(tok, "%lf", &v) != 1) return 6;
    }
    if (strtok(NULL, SEP)) return 7;
    n_poses++;
  }
  int *times = malloc(n_poses * sizeof(int));
  double **values = malloc(n_poses * sizeof(double *));
  for (int p = 0; p < n_poses; p++) values[p] = malloc(n_joints * sizeof(double));
  rewind(f); /* pass 2: the values */
  if (!fgets(line, sizeof(line), f)) return 3;
  for (int p = 0; p < n_poses; p++) {
    if (!fgets(line, sizeof(line), f)) return 8;
    times[p] = time_ms(strtok(line, SEP));
    strtok(NULL, SEP);
    for (int j = 0; j < n_joints; j++) {
      tok = strtok(NULL, SEP);
      if (strcmp(tok, "*") == 0) values[p][j] = -9999999.9;
      else sscanf(tok, "%lf", &values[p][j]);
    }
  }
  fclose(f);
  printf("%d\n", n_poses);
  return n_poses > 0 ? 0 : 7;
}
"""

ONE_PASS_LOADER = r"""
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A lighter reader than Webots' (a lower bound, printed for the record): one pass, fgets and
   strtok as Webots, but strtod per value and arrays that grow. */
int main(int argc, char **argv) {
  FILE *f = fopen(argv[1], "r");
  if (!f) return 2;
  char line[4096];
  int n_joints = 0, n_poses = 0, cap = 16;
  int *times = malloc(cap * sizeof(int));
  double *values = NULL;
  if (!fgets(line, sizeof(line), f)) return 3;
  for (char *tok = strtok(line, ",\n\r"); tok; tok = strtok(NULL, ",\n\r")) n_joints++;
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


def c_loaders(tmp: Path) -> dict[str, Path] | None:
    """The C baselines compiled with ``cc -O2`` into ``tmp`` (Webots' reading, then the
    lighter one-pass reader), or None without a C compiler."""
    cc = shutil.which("cc")
    if cc is None:
        return None
    exes = {}
    for name, text in (("webots", WEBOTS_LOADER), ("one_pass", ONE_PASS_LOADER)):
        source = tmp / f"{name}.c"
        source.write_text(text)
        exes[name] = tmp / name
        subprocess.run([cc, "-O2", "-o", str(exes[name]), str(source)], check=True)
    return exes


def report_c_baseline(
    tmp: Path, big: Path, validate_cmd: list[str], repeat: int, env: dict[str, str]
) -> None:
    """Syntax-level ``validate`` (whole process) against Webots' C loader, measured in this
    run; the one-pass C reader is printed for the record."""
    exes = c_loaders(tmp)
    if exes is None:
        print("C baseline skipped: no C compiler (cc) on this machine")
        return
    size = big.stat().st_size
    c: Child = best_child(repeat, [str(exes["webots"]), str(big)])
    light: Child = best_child(repeat, [str(exes["one_pass"]), str(big)])
    v: Child = best_child(repeat, validate_cmd, env)
    if c.returncode != 0 or light.returncode != 0 or v.returncode != 0:
        raise SystemExit(
            f"exit status: C loader {c.returncode}, one-pass C {light.returncode},"
            f" validate {v.returncode}"
        )
    time_ratio, peak_ratio = v.wall_s / c.wall_s, v.peak_bytes / size
    print(
        f"C loader (Webots' wbu_motion_new, cc -O2):         {c.wall_s:.3f} s, {c.peak_mib:.0f} MiB peak"
    )
    print(
        f"C, one pass with strtod (lighter than Webots):     {light.wall_s:.3f} s, {light.peak_mib:.0f} MiB peak"
    )
    print(
        f"validate --robot none, whole process:              {v.wall_s:.3f} s, {v.peak_mib:.0f} MiB peak"
    )
    print(
        f"  wall time {time_ratio:.2f}x Webots' C loader (target <= 0.6x: "
        f"{'met' if time_ratio <= 0.6 else 'not met'}); {v.wall_s / light.wall_s:.2f}x the one-pass C"
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
        # Bytecode cached, as an installed package has it (written by the first run).
        env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
        env["PYTHONPYCACHEPREFIX"] = str(Path(tmp) / "pyc")
        subprocess.run(
            [script, "validate", "--robot", "none", str(small)], env=env, capture_output=True
        )

        def run(cmd: list[str]) -> float:
            samples = []
            for _ in range(5):
                t0 = time.perf_counter()
                subprocess.run(cmd, check=False, capture_output=True, env=env)
                samples.append(time.perf_counter() - t0)
            return statistics.median(samples)

        t_cold = run([script, "validate", "--robot", "none", str(big)])
        print(
            f"motiontool validate big.motion, whole process:     {t_cold:.3f} s  ratio {t_cold / t_base:.2f}x baseline  (start-up and imports included)"
        )

        report_c_baseline(Path(tmp), big, [script, "validate", "--robot", "none", str(big)], 5, env)

        t_py = run([sys.executable, "-c", "pass"])
        t_cli = run([script, "validate", "--robot", "none", str(small)])
        print(f"start-up, bare python -c pass:                     {t_py:.3f} s")
        print(
            f"start-up, motiontool validate small.motion:        {t_cli:.3f} s  ratio {t_cli / t_py:.2f}x bare python  (target < 0.3 s)"
        )


if __name__ == "__main__":
    main()
