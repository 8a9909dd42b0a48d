"""Benchmark: start-up of the pre-commit case, ``motiontool validate small.motion`` (one small
file, the default checks, the whole process), and of ``motiontool --help``.

Run: ``python benchmarks/bench_startup.py [--before REV]``. Baselines measured in the same run:
a bare ``python -c pass``, and the same commands run from the code of git revision ``REV`` (by
default the last one before start-up work), extracted to a temporary folder.
Each time is the best of ``--repeat`` runs (wall clock, s), with CPU time (user + system, s)
and peak memory (MiB), bytecode cached as an installed package has it. Targets:
the pre-commit case in 0.2 s where it took 0.31 s, so at most 0.65x the ``REV`` time.

The collision check runs from the robot's tables stored on disk (``kinematics/tables_cache.py``);
the first run in a fresh cache folder builds them (it imports Pinocchio): printed as well. A file
checked before gets its robot findings from the findings cache
(``kinematics/checks/findings_cache.py``) without importing numpy: what a hook meets for the
files an editor or an earlier run has checked. ``--no-cache`` is the file met for the first time
(or edited): both are printed against the target.

Then the hook's three targets, each the median (and the best) of ``--repeat`` runs, wall
clock, with its CPU time, and as a ratio to a bare ``python -c pass`` of the same run:
the syntax level on a small file in 0.08 s, the default checks on a small file in 0.18 s
(a file met for the first time, ``--no-cache``; a file checked before printed too), twenty
small files in one call in 0.3 s. These are timed by ``os.wait4`` alone (GNU time's own fork and
exec would add 3-4 ms to each), in a folder without a configuration file; the syntax level is
also timed in a repository whose ``pyproject.toml`` configures motiontool.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from _timing import Child, best_child, run_child  # benchmarks/_timing.py (run as a script)

ROOT = Path(__file__).resolve().parent.parent
BEFORE = "6670fe6"
"""The last commit before the start-up work (commands imported when they run, the collision
check's tables on disk)."""
SMALL = b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,Pose1,0\n00:00:500,Pose2,0.5\n"
RUN = "import sys; from motiontool.cli.__main__ import main; sys.argv[0] = 'motiontool'; main()"
"""What the console script runs (``pyproject.toml``'s ``[project.scripts]``)."""
RUN_BEFORE = "import sys; from motiontool.cli.app import main; sys.argv[0] = 'motiontool'; main()"
"""The console script of :data:`BEFORE` (``--before`` must have it too)."""
TARGET_S = 0.2
BEFORE_S = 0.31
CONFIGURED = """[project]
name = "robot-motions"
version = "1.0.0"
requires-python = ">=3.10"
dependencies = []

[tool.motiontool]
robot = "nao"
extend-select = ["MT3"]
ignore = ["MT206"]
exclude = ["generated"]

[tool.motiontool.robots]
"arm/**" = "ur5e"

[tool.motiontool.per-file-ignores]
"legacy/*.motion" = ["MT203"]
"""
"""A repository's ``pyproject.toml`` that configures motiontool (the hook's case where a team
has configured it)."""
GOALS_S = {"syntax": 0.08, "default": 0.18, "twenty": 0.3}
"""The hook's targets (median wall clock, s): one small file at the syntax level, one with the
default checks, twenty small files in one call."""


def _line(label: str, c: Child, base: Child | None = None, note: str = "") -> None:
    if c.returncode or (base is not None and base.returncode):  # a failed start is no time
        raise SystemExit(
            f"{label}: exit status {c.returncode} (baseline {base and base.returncode})"
        )
    ratio = f"  ratio {c.wall_s / base.wall_s:.2f}x" if base is not None else ""
    print(
        f"{label:<44} {c.wall_s:.3f} s wall, {c.cpu_s:.3f} s CPU, {c.peak_mib:5.1f} MiB{ratio}{note}"
    )


def _checkout(rev: str, into: Path) -> Path:
    """The package at ``rev``, as ``into/motiontool`` (for ``PYTHONPATH``)."""
    package = into / "motiontool"
    package.mkdir(parents=True)
    archive = subprocess.run(
        ["git", "-C", str(ROOT), "archive", rev], check=True, capture_output=True
    ).stdout
    subprocess.run(["tar", "-x", "-C", str(package)], input=archive, check=True)
    return into


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", default=BEFORE, help="git revision of the baseline")
    parser.add_argument("--repeat", type=int, default=9)
    args = parser.parse_args()

    with tempfile.TemporaryDirectory() as tmp_name:
        tmp = Path(tmp_name)
        os.chdir(tmp)  # every run in the files' folder: the caller's may hold a configuration
        (tmp / "small.motion").write_bytes(SMALL)
        small = str(tmp / "small.motion")
        env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
        now = {**env, "PYTHONPYCACHEPREFIX": str(tmp / "pyc-now"), "XDG_CACHE_HOME": str(tmp / "c")}
        old = {
            **env,
            "PYTHONPATH": str(_checkout(args.before, tmp / "before")),
            "PYTHONPYCACHEPREFIX": str(tmp / "pyc-before"),
            "XDG_CACHE_HOME": str(tmp / "c-before"),
        }
        cli, cli_before = [sys.executable, "-c", RUN], [sys.executable, "-c", RUN_BEFORE]
        cold = run_child([*cli, "validate", small], now)  # builds the tables: Pinocchio
        run_child([*cli_before, "validate", small], old)  # bytecode of both, written once

        n = args.repeat
        bare = best_child(n, [sys.executable, "-c", "pass"], env)
        print(f"machine: {os.cpu_count()} cores, load {os.getloadavg()[0]:.2f} (1 min average)")
        _line("bare python -c pass", bare)
        for what in (["--help"], ["validate", "--robot", "none", small], ["validate", small]):
            label = "motiontool " + " ".join(what).replace(small, "small.motion")
            before = best_child(n, [*cli_before, *what], old)
            after = best_child(n, [*cli, *what], now)
            _line(f"{label} ({args.before})", before)
            if what != ["validate", small]:
                _line(f"{label} (now)", after, before)
                continue
            _line(f"{label} (now, its findings cached)", after, before, _target(after))
            # The same file checked again (edited, or never seen): the findings cache misses.
            checked = best_child(n, [*cli, "validate", "--no-cache", small], now)
            _line(f"{label} (now, --no-cache)", checked, before, _target(checked))
        _line(
            "motiontool validate small.motion, first run",
            cold,
            None,
            "  (stores the tables and the findings)",
        )
        _targets(max(n, 21), cli, now, tmp)


def _targets(n: int, cli: list[str], env: dict[str, str], tmp: Path) -> None:
    """The hook's three targets: median and best wall clock against each goal. Each run is
    timed by ``os.wait4`` alone (its own wall time: GNU time's fork and exec would add 3-4 ms),
    in the files' folder (no configuration file: the caller's folder may have one), and the
    cases take turns, a run of each in every round, so that a busy moment of the machine
    slows them all a little rather than one a lot. The syntax level is also timed in a
    repository whose ``pyproject.toml`` configures motiontool, for the record (the TOML
    parser's import and the parse)."""
    twenty = []
    for i in range(20):  # twenty different files: each its own findings
        (tmp / f"f{i:02}.motion").write_bytes(SMALL.replace(b",0.5", f",0.{i % 9 + 1}".encode()))
        twenty.append(str(tmp / f"f{i:02}.motion"))
    run_child([*cli, "validate", *twenty], env, cwd=tmp)  # their findings cached
    small = str(tmp / "small.motion")
    configured = tmp / "configured"
    configured.mkdir()
    (configured / "small.motion").write_bytes(SMALL)
    (configured / "pyproject.toml").write_text(CONFIGURED)
    syntax = ["validate", "--robot", "none"]
    cases = (
        ("bare", "python -c pass", [sys.executable, "-c", "pass"], tmp),
        ("syntax", "validate --robot none small.motion", [*cli, *syntax, small], tmp),
        (
            "default",
            "validate --no-cache small.motion (first seen)",
            [*cli, "validate", "--no-cache", small],
            tmp,
        ),
        ("default", "validate small.motion (findings cached)", [*cli, "validate", small], tmp),
        (
            "twenty",
            "validate --no-cache 20 small files",
            [*cli, "validate", "--no-cache", *twenty],
            tmp,
        ),
        ("twenty", "validate 20 small files (findings cached)", [*cli, "validate", *twenty], tmp),
        (
            "syntax",
            "the syntax level, configured in pyproject.toml",
            [*cli, *syntax, "small.motion"],
            configured,
        ),
    )
    runs: list[list[Child]] = [[] for _ in cases]
    for _ in range(n):
        for case, (_goal, _label, cmd, folder) in zip(runs, cases, strict=True):
            case.append(run_child(cmd, env, peak=False, cwd=folder))
    bare_s = statistics.median(c.wall_s for c in runs[0])
    print(f"targets (median of {n} runs each, taking turns; load {os.getloadavg()[0]:.2f})")
    for (goal, label, _cmd, _folder), case in zip(cases, runs, strict=True):
        if any(c.returncode for c in case):
            raise SystemExit(f"{label}: exit status {case[0].returncode}")
        median = statistics.median(c.wall_s for c in case)
        cpu = statistics.median(c.cpu_s for c in case)
        best = min(c.wall_s for c in case)
        times = f"{median:.3f} s median ({best:.3f} s best, {cpu:.3f} s CPU)"
        if goal == "bare":
            print(f"  {label:<46} {times}")
            continue
        goal_s = GOALS_S[goal]
        verdict = "met" if median <= goal_s else "not met"
        print(
            f"  {label:<46} {times}, {median / bare_s:.1f}x bare python; goal {goal_s} s: {verdict}"
        )


def _target(c: Child) -> str:
    """The pre-commit target's verdict on ``c``."""
    return (
        f"  (target <= {TARGET_S / BEFORE_S:.2f}x: {TARGET_S} s where it took {BEFORE_S} s; "
        f"{c.wall_s:.3f} s {'<=' if c.wall_s <= TARGET_S else '>'} {TARGET_S} s on this machine)"
    )


if __name__ == "__main__":
    main()
