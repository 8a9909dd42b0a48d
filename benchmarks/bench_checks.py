"""Benchmark: ``validate`` with the Nao model (limits + velocity + collision) on the whole Webots
corpus (``tests/data/corpus/webots``, 27 files), in one process.

Run: ``python benchmarks/bench_checks.py``. Reported, each time with its ratio to the syntax-only
run (``--robot none``) measured in the same run:

* total: the installed ``motiontool validate --robot nao`` as a subprocess, start-up, imports
  (Pinocchio included) and the model build counted (best of ``--repeat`` runs, median too);
* per additional file: the corpus copied 4 times over (108 files) against once, whole process:
  (T(108) - T(27)) / 81;
* per file, in process with the model already built: the cost of the robot checks on each file
  (its validate time minus its syntax-only time), the largest ones listed;
* where a cold run's time goes: imports, model build, each check.

Targets: total < 2 s, < 20 ms per additional file.
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

from _timing import best_of  # benchmarks/_timing.py (run as a script)

ROOT = Path(__file__).resolve().parents[1]
CORPUS = ROOT / "tests" / "data" / "corpus" / "webots"  # vendored (see its NOTICE)
CHECKS = "limits,velocity,collision"


def _run(cmd: list[str], repeat: int) -> float:
    """Best of ``repeat`` wall-clock runs, s (the machine is shared: the minimum is the
    least disturbed run; the median is printed too by :func:`_report`)."""
    samples = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        subprocess.run(cmd, check=False, capture_output=True)
        samples.append(time.perf_counter() - t0)
    _MEDIANS[tuple(cmd)] = statistics.median(samples)
    return min(samples)


_MEDIANS: dict[tuple[str, ...], float] = {}


def _cold_breakdown() -> str:
    """Where one cold in-process run spends its time (a fresh interpreter)."""
    code = f"""
import time
t0 = time.perf_counter()
from motiontool.cli.app import app
t_cli = time.perf_counter()
import pinocchio
t_pin = time.perf_counter()
from motiontool.kinematics import load_robot, _pinocchio
spec = load_robot("nao")
_pinocchio.kinematic_tables(spec)
t_model = time.perf_counter()
from motiontool.kinematics.checks import robot_checks
from motiontool.motionfmt import collect_motion_files, read_file, validate_bytes
checks = robot_checks(spec, {CHECKS.split(",")!r})
files = [(str(p), read_file(p)) for p in collect_motion_files([{str(CORPUS)!r}])]
spent = [0.0] * len(checks)
t_read = 0.0
for path, data in files:
    t = time.perf_counter()
    report = validate_bytes(data, path)
    t_read += time.perf_counter() - t
    if report.read.accepted:
        for i, check in enumerate(checks):
            t = time.perf_counter()
            check(report.read)
            spent[i] += time.perf_counter() - t
names = [type(c).__name__ for c in checks]
print(f"imports (cli): {{t_cli - t0:.3f}} s; pinocchio import: {{t_pin - t_cli:.3f}} s; "
      f"Nao model build (Pinocchio + tables): {{t_model - t_pin:.3f}} s; "
      f"syntax (read + reader checks): {{t_read:.3f}} s; "
      + "; ".join(f"{{n}}: {{s:.3f}} s" for n, s in zip(names, spent)))
"""
    out = subprocess.run(
        [sys.executable, "-c", code], check=True, capture_output=True, text=True, cwd=ROOT
    )
    return out.stdout.strip()


def _per_file() -> list[tuple[float, float, str, int]]:
    """(check time s, syntax time s, file, poses) per file, in process, model already built."""
    from motiontool.kinematics.checks import RobotChecks
    from motiontool.motionfmt import collect_motion_files, read_file, validate_bytes

    checker = RobotChecks("nao", CHECKS.split(","))
    files = [(str(p), read_file(p)) for p in collect_motion_files([CORPUS])]
    for path, data in files:  # warm: model built, numpy paths compiled
        validate_bytes(data, path, checks=[checker])
    rows = []
    for path, data in files:
        syntax = best_of(5, lambda d=data, p=path: validate_bytes(d, p))
        full = best_of(5, lambda d=data, p=path: validate_bytes(d, p, checks=[checker]))
        poses = len(validate_bytes(data, path).read.times_ms)
        rows.append((full - syntax, syntax, path, poses))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    if not CORPUS.is_dir():
        sys.exit(f"Webots corpus not found at {CORPUS}")
    script = shutil.which("motiontool", path=os.path.dirname(sys.executable)) or "motiontool"
    n_files = len(list(CORPUS.rglob("*.motion")))

    syntax = _run([script, "validate", "--robot", "none", str(CORPUS)], args.repeat)
    full = _run(
        [script, "validate", "--robot", "nao", "--checks", CHECKS, str(CORPUS)], args.repeat
    )
    bare = _run([sys.executable, "-c", "pass"], args.repeat)
    print(f"corpus: {n_files} files under {CORPUS}")
    print(f"bare python -c pass:                          {bare:.3f} s")
    print(f"motiontool validate --robot none (syntax):    {syntax:.3f} s  (best of {args.repeat})")
    median = _MEDIANS[(script, "validate", "--robot", "nao", "--checks", CHECKS, str(CORPUS))]
    print(
        f"motiontool validate --robot nao ({CHECKS}): {full:.3f} s (median {median:.3f} s)  "
        f"ratio {full / syntax:.2f}x syntax-only  (target < 2 s, start-up included)"
    )

    with tempfile.TemporaryDirectory() as tmp:
        for k in range(4):
            shutil.copytree(CORPUS, Path(tmp) / f"copy{k}")
        syntax4 = _run([script, "validate", "--robot", "none", tmp], args.repeat)
        full4 = _run([script, "validate", "--robot", "nao", "--checks", CHECKS, tmp], args.repeat)
    extra = n_files * 3
    per_full = (full4 - full) / extra * 1000
    per_syntax = (syntax4 - syntax) / extra * 1000
    print(
        f"per additional file, whole process ({4 * n_files} vs {n_files} files): "
        f"{per_full:.1f} ms  ratio {per_full / per_syntax:.2f}x syntax-only "
        f"({per_syntax:.1f} ms)  (target < 20 ms)"
    )

    rows = sorted(_per_file(), reverse=True)
    checks_total = sum(r[0] for r in rows)
    syntax_total = sum(r[1] for r in rows)
    print(
        f"in process, model built: robot checks {checks_total * 1000:.0f} ms for {len(rows)} files"
        f" (mean {checks_total / len(rows) * 1000:.1f} ms/file, syntax {syntax_total * 1000:.0f}"
        f" ms, ratio {(checks_total + syntax_total) / syntax_total:.2f}x syntax-only); costliest:"
    )
    for cost, syn, path, poses in rows[:5]:
        print(
            f"  {cost * 1000:6.1f} ms checks + {syn * 1000:5.1f} ms syntax  {poses:4d} poses  "
            f"{Path(path).relative_to(CORPUS)}"
        )
    print("cold run breakdown: " + _cold_breakdown())


if __name__ == "__main__":
    main()
