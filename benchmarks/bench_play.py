"""Benchmark: ``play`` of a long Nao walk (Webots' Forwards50 looped), against a bare MuJoCo loop.

Run: ``python benchmarks/bench_play.py [--loops 4] [--repeat 3]``. Prints simulated seconds per
wall-clock second for

- a bare loop: the same compiled scene (86 DoF, dense, same physics step) stepped with constant
  motor commands, ``mj_step(model, data, substeps)`` once per control step, nothing else;
- ``play`` without a recording (scene build, command stream, Webots motor law every control step,
  contact and self-collision bookkeeping, the report);
- ``play --rrd`` (the same plus the Rerun recording written to a temporary file);

and the ratios. Targets: play >= 0.8 x the bare loop; recording overhead < 25 %.
Best of ``--repeat`` runs each; the machine's other load shows in the spread.

``--memory-only``: the peak memory of the ``play`` command (a child process, GNU time) with a
recording, a bag and a JSON report, for the Nao's ``head_no.motion`` looped 40 and 160 times
(about 5 000 and 21 000 control steps) and the UR5e's ``jog.motion`` looped 20 and 80 times
(about 22 000 and 90 000 control steps: 180 and 717 s), and their ratios (target <= 1.1x: a
run is simulated and written a chunk at a time, and an arm's report folds a keyframe's visits
into one entry, so memory does not grow with the run's duration).
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
from pathlib import Path

from _timing import best_child, best_of  # benchmarks/_timing.py (run as a script)

ROOT = Path(__file__).resolve().parent.parent
CORPUS = ROOT / "tests" / "data" / "corpus" / "webots"  # vendored (see its NOTICE)
WALK = "projects/robots/softbank/dancing_nao/motions/Forwards50.motion"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--motion", type=Path, default=CORPUS / WALK)
    parser.add_argument("--loops", type=int, default=4)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--memory-only", action="store_true")
    args = parser.parse_args()
    if args.memory_only:
        memory()
        return 0
    if not args.motion.is_file():
        print(f"motion {args.motion} not found (the Webots corpus is needed)", file=sys.stderr)
        return 2

    import mujoco

    from motiontool.kinematics import load_robot
    from motiontool.motionfmt import read_motion
    from motiontool.sim import PlayOptions, command_matrix, command_stream, play
    from motiontool.sim._mujoco import build_scene

    robot = load_robot("nao")
    options = PlayOptions(loops=args.loops, hold_s=0.0)
    step_ms = robot.default_timestep_ms
    probe = build_scene(robot, step_ms)
    initial = probe.data.qpos[probe.qpos_adr].copy()
    targets, _commanded, _lengths, _ignored = command_matrix(
        command_stream(
            [read_motion(str(args.motion))], probe.joints, step_ms, initial, loops=args.loops
        )
    )
    steps = len(targets)
    simulated = steps * probe.control_step_s

    def bare() -> None:
        scene = build_scene(robot, step_ms)
        model, data = scene.model, scene.data
        data.qvel[scene.driver_dof] = 0.0
        for _ in range(steps):
            mujoco.mj_step(model, data, scene.control_substeps)

    def build_only() -> None:
        build_scene(robot, step_ms)

    report = play([args.motion], robot=robot, options=options)
    tmp = Path(tempfile.mkdtemp())

    def plain() -> None:
        play([args.motion], robot=robot, options=options)

    def recorded() -> None:
        play([args.motion], robot=robot, options=options, rrd=tmp / "run.rrd")

    t_build = best_of(args.repeat, build_only)
    t_bare = best_of(args.repeat, bare) - t_build
    t_plain = best_of(args.repeat, plain)
    t_rrd = best_of(args.repeat, recorded)
    size_mb = (tmp / "run.rrd").stat().st_size / 1e6

    print(
        f"motion: {args.motion.name} x{args.loops}: {simulated:.1f} s simulated, {steps} control "
        f"steps of {step_ms} ms, {probe.control_substeps} physics steps of "
        f"{probe.physics_step_s * 1000:g} ms each, nv {probe.model.nv}; "
        f"walked dx {report.base.dx_m if report.base else float('nan'):+.2f} m"
    )
    print(f"scene build: {t_build * 1000:.0f} ms (not in the bare loop's time)")
    print(f"bare mj_step loop : {simulated / t_bare:7.1f} sim s / wall s")
    print(
        f"play              : {simulated / t_plain:7.1f} sim s / wall s   "
        f"ratio to bare {t_bare / t_plain:.2f} (target >= 0.80)"
    )
    print(
        f"play --rrd        : {simulated / t_rrd:7.1f} sim s / wall s   "
        f"recording overhead {100 * (t_rrd / t_plain - 1):.0f} % (target < 25 %), "
        f".rrd {size_mb:.1f} MB"
    )
    return 0


def memory() -> None:
    """The play command's peak with a short and a four times longer run, and their ratio, for
    a humanoid and an arm."""
    memory_of(ROOT / "motions" / "nao" / "head_no.motion", (40, 160))
    memory_of(ROOT / "motions" / "ur5e" / "jog.motion", (20, 80))


def memory_of(motion: Path, loops: tuple[int, int]) -> None:
    """``play motion`` looped ``loops`` times: each peak, and their ratio."""
    script = shutil.which("motiontool", path=os.path.dirname(sys.executable)) or "motiontool"
    peaks = {}
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        for n in loops:
            cmd = [script, "play", str(motion), "--headless", "--loop", str(n), "--rrd",
                   str(out / "r.rrd"), "--bag", str(out / "r.mcap"), "--json", str(out / "r.json")]  # fmt: skip
            child = best_child(1, cmd)
            if child.returncode not in (0, 1):
                raise SystemExit(f"play --loop {n}: exit status {child.returncode}")
            peaks[n] = child.peak_bytes
            print(
                f"play {motion.name} --loop {n} --rrd --bag --json: {child.wall_s:.1f} s, "
                f"{child.peak_mib:.0f} MiB peak, .rrd {(out / 'r.rrd').stat().st_size / 1e6:.0f} MB"
            )
    short, long = loops
    ratio = peaks[long] / peaks[short]
    verdict = "met" if ratio <= 1.1 else "not met"
    print(f"{long // short}x the duration peaks at {ratio:.2f}x (target <= 1.1x, flat: {verdict})")


if __name__ == "__main__":
    sys.exit(main())
