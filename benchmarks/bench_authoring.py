"""Benchmark: ``mirror``, ``concat``, ``trim``, ``scale``, ``retime``, ``resample`` and ``diff`` on the
100 000-pose, 26-joint file of ``bench_validate.py`` (about 26 MB).

Run: ``python benchmarks/bench_authoring.py``. Each time covers reading the file into a lossless
document, the operation, and the result read back as a document (as Webots reads it); it is
printed with its ratio to a baseline measured in the same run: the plain read (``loads`` of the
file). Target: < 2 s each. concat joins the file and a 2-pose motion (26 MB out);
the file joined with itself (52 MB out, two reads of twice the data) is printed too. scale
(x0.5: every cell re-spelt), retime (--speed 0.7: every time re-spelt, the new times in
integers), resample (a 30 ms grid, its deviation compared at every ms) and diff
(the file against its scaled copy at every ms: 4 million steps) are printed for information.

Then the peak memory of each command as a whole process (``motiontool mirror big.motion -o
out.motion``, ...; GNU time), against ``motiontool info big.motion`` (which reads the file) in
the same run, and per MB of file. No target: ``trim`` and ``retime --speed`` hold the input
and write their result a block of lines at a time (``motionfmt/retime.py``, ``retimed_blocks``); ``mirror``,
``concat`` and ``scale`` hold the input and the result's bytes, read back for their checks
(for the record; ``validate``, ``sample``, ``diff`` and ``plot`` are measured flat by
``bench_findings.py`` and ``bench_duration.py``).
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
from pathlib import Path

from _timing import best_child, best_of  # benchmarks/_timing.py (run as a script)
from bench_validate import JOINTS, make_file


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--poses", type=int, default=100_000)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()

    from motiontool.kinematics.mirror import mirror_map
    from motiontool.kinematics.robots import load_robot
    from motiontool.motionfmt import loads, read_file
    from motiontool.motionfmt.compare import compare_motions
    from motiontool.motionfmt.ops.concat import concat
    from motiontool.motionfmt.ops.mirror import mirror
    from motiontool.motionfmt.ops.scale import scale
    from motiontool.motionfmt.ops.trim import trim
    from motiontool.motionfmt.resample import resample
    from motiontool.motionfmt.retime import scale_times

    nao = load_robot("nao")
    mapping = mirror_map(nao).as_dict()
    vmax = {j.name: j.max_velocity for j in nao.joints}
    with tempfile.TemporaryDirectory() as tmp:
        big = Path(tmp) / "big.motion"
        make_file(big, args.poses)
        size_mb = big.stat().st_size / 1e6
        end = 40 * (args.poses - 1)

        def read() -> None:
            assert loads(read_file(big), "big.motion").n_poses == args.poses

        def do_mirror() -> None:
            doc = loads(read_file(big), "big.motion")
            assert len(mirror(doc, mapping).document.to_bytes()) > 0

        # A short motion of the same joints, in another column order, to join after the file.
        tail = "#WEBOTS_MOTION,V1.0," + ",".join(JOINTS[::-1]) + "\n"
        tail += "".join(f"{t},T{t},{','.join(['0.1'] * len(JOINTS))}\n" for t in (0, 500))
        small = loads(tail.encode(), "tail.motion")

        def do_concat() -> None:
            doc = loads(read_file(big), "big.motion")
            out = concat([doc, small], max_velocity=vmax).document
            assert out.n_poses == args.poses + 2

        def do_concat_twice() -> None:
            doc = loads(read_file(big), "big.motion")
            out = concat([doc, doc], max_velocity=vmax).document
            assert out.n_poses == 2 * args.poses

        def do_trim() -> None:
            doc = loads(read_file(big), "big.motion")
            out = trim(doc, end // 10 + 7, end - end // 10 + 13).document  # off the pose times
            assert out.n_poses > args.poses // 2

        def do_scale() -> None:
            doc = loads(read_file(big), "big.motion")
            assert scale(doc, 0.5).changed > 0

        def do_retime() -> None:
            doc = loads(read_file(big), "big.motion")
            doc.set_times(list(scale_times(doc.result.times_ms, 0.7).times_ms))
            assert doc.motion.duration_ms == round(end / 0.7)

        def do_resample() -> None:
            doc = loads(read_file(big), "big.motion")
            assert resample(doc, step_ms=30).document.n_poses > args.poses

        scaled = scale(loads(read_file(big), "big.motion"), 0.5).document.motion

        def do_diff() -> None:
            doc = loads(read_file(big), "big.motion")
            assert not compare_motions(doc.motion, scaled).same

        t_base = best_of(args.repeat, read)
        print(f"file: {args.poses} poses x {len(JOINTS)} joints, {size_mb:.1f} MB")
        print(f"baseline (read into a lossless document): {t_base:.3f} s")
        for label, fn in (
            ("mirror (read, mirror, bytes)", do_mirror),
            ("concat (read, file + a 2-pose motion)", do_concat),
            ("trim (read, keep 80 %, 2 new poses)", do_trim),
        ):
            t = best_of(args.repeat, fn)
            print(f"{label:<41} {t:.3f} s  ratio {t / t_base:.2f}x baseline  (target < 2 s)")
        for label, fn in (
            ("concat (read, file + itself: 52 MB out)", do_concat_twice),
            ("scale (read, x0.5: every cell re-spelt)", do_scale),
            ("retime (read, x0.7: every time re-spelt)", do_retime),
            ("resample (read, 30 ms grid, every ms)", do_resample),
            ("diff (read, against scaled, every ms)", do_diff),
        ):
            t = best_of(args.repeat, fn)
            print(f"{label:<41} {t:.3f} s  ratio {t / t_base:.2f}x baseline  (for information)")
        peaks(big, Path(tmp))


def peaks(big: Path, tmp: Path) -> None:
    """Peak resident memory of each command on ``big``, whole process, against ``info``."""
    script = shutil.which("motiontool", path=os.path.dirname(sys.executable)) or "motiontool"
    out = str(tmp / "out.motion")
    size_mb = big.stat().st_size / 2**20
    base = best_child(1, [script, "info", str(big)])
    print(f"peak memory, whole process ({size_mb:.0f} MiB file):")
    print(
        f"  {'info (reads the file)':<36} {base.peak_mib:6.0f} MiB  {base.peak_mib / size_mb:4.1f}x the file"
    )
    for label, args in (
        ("mirror", ["mirror", str(big), "-o", out]),
        ("trim (80 %)", ["trim", str(big), "-o", out, "--from", "1000", "--to", "3200000"]),
        ("retime --speed 0.5", ["retime", str(big), "-o", out, "--speed", "0.5"]),
        ("scale --amplitude 0.5", ["scale", str(big), "-o", out, "--amplitude", "0.5"]),
        ("concat (the file and itself)", ["concat", str(big), str(big), "-o", out]),
        ("resample --step 20", ["resample", str(big), "-o", out, "--step", "20"]),
    ):
        child = best_child(1, [script, *args])
        if child.returncode not in (0, 1):
            raise SystemExit(f"{label}: exit status {child.returncode}")
        print(
            f"  {label:<36} {child.peak_mib:6.0f} MiB  {child.peak_mib / size_mb:4.1f}x the file,"
            f" {child.peak_mib / base.peak_mib:.2f}x info's"
        )


if __name__ == "__main__":
    main()
