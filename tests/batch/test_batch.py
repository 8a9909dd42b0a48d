"""Planning, perturbation draws, caching and reports of a batch (the simulator itself is tested
in tests/sim; here a small deterministic runner stands in for it)."""

from __future__ import annotations

import contextlib
import json
import subprocess
import xml.etree.ElementTree as ET
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import xmlschema
from conftest import DATA
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.cli.batch_reports import render_json, render_markdown, render_summary, write_junit
from motiontool.errors import OutputError
from motiontool.kinematics.robots import UnknownRobotError
from motiontool.motionfmt import MotionToolError, read_motion
from motiontool.sim import batch as batch_module
from motiontool.sim.batch import (
    RunSpec,
    check_robots,
    parse_perturbation,
    plan,
    recording_stems,
    run_batch,
)

JUNIT_SCHEMA = xmlschema.XMLSchema(str(DATA / "junit" / "junit-10.xsd"))
CALLS: list[str] = []


def runner(spec: RunSpec) -> dict[str, Any]:
    """Deterministic stand-in: 'falls' when the motion is longer than 1 s or friction < 0.8."""
    motion = read_motion(spec.path)
    params = dict(spec.params)
    fell = motion.duration_ms > 1000 or params.get("friction", 1.0) < 0.8
    return {
        "clean": not fell,
        "reason": "fell at 0.5 s" if fell else "",
        "base": {"max_tilt_deg": 60.0 if fell else 2.0},
    }


@pytest.fixture
def motions(tmp_path: Path) -> list[Path]:
    short = tmp_path / "short.motion"
    short.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n500,B,0.5\n")
    long = tmp_path / "long.motion"
    long.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n2000,B,0.5\n")
    return [short, long]


def test_parse_perturbation() -> None:
    p = parse_perturbation("friction=0.7:1.3")
    assert (p.name, p.low, p.high) == ("friction", 0.7, 1.3)
    with pytest.raises(MotionToolError, match="NAME one of friction, mass, motor-strength"):
        parse_perturbation("gravity=1:2")
    with pytest.raises(MotionToolError, match="need finite LOW <= HIGH"):
        parse_perturbation("mass=1.1:0.9")


@pytest.mark.needs("sim")
@pytest.mark.parametrize(
    ("given", "message"),
    [
        ("mass=-1:0", "mass takes values > 0 (a factor on every body mass), got LOW -1"),
        ("speed=0:0", "speed takes values > 0 (a factor on the playback speed), got LOW 0"),
        ("friction=0:1", "friction takes values > 0 (a factor on the floor friction), got LOW 0"),
        ("motor-strength=-0.5", "motor-strength takes values > 0 (a factor on every motor's"),
        ("start-noise=-0.1:0.1", "start-noise takes values >= 0 (the standard deviation of"),
    ],
)
def test_a_perturbation_out_of_its_range_is_a_usage_error_before_any_run(
    tmp_path: Path, given: str, message: str
) -> None:
    """Every run errored (mass 0 has no inertia, speed 0 no duration) and the batch exited 1;
    start-noise below 0 was played as no noise. Refused where parsed, the range in the line."""
    (tmp_path / "nod.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n200,B,0.2\n")
    result = CliRunner().invoke(
        app, ["batch", str(tmp_path / "nod.motion"), "--no-cache", "--perturb", given]
    )
    assert (result.exit_code, result.stdout) == (2, ""), result.output
    assert result.stderr.startswith(f"motiontool: error: perturbation {given!r}: {message}")
    assert result.stderr.count("\n") == 1
    for edge in ("start-yaw=-180:180", "start-noise=0:0.01", "mass=0.9:1.1", "speed=0.5:2"):
        parse_perturbation(edge)  # in range: drawn as given


def test_plan_is_seeded_and_independent_of_order(motions: list[Path]) -> None:
    perturb = [parse_perturbation("friction=0.7:1.3"), parse_perturbation("mass=0.9:1.1")]
    a = plan(motions, ["nao"], perturbations=perturb, samples=4, seed=1)
    b = plan(motions, ["nao"], perturbations=perturb[::-1], samples=4, seed=1)
    c = plan(motions, ["nao"], perturbations=perturb, samples=4, seed=2)
    assert a == b and a != c and len(a) == 8
    for spec in a:
        params = dict(spec.params)
        assert 0.7 <= params["friction"] <= 1.3 and 0.9 <= params["mass"] <= 1.1
    assert plan(motions, ["nao", "nao-v5"], samples=5)[0].params == ()  # no perturbation: 1 sample
    assert len(plan(motions, ["nao", "nao-v5"], samples=5)) == 4


def test_plan_resolves_auto_per_file(tmp_path: Path) -> None:
    nao = tmp_path / "nao.motion"
    nao.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadYw\n0,A,0,0\n")  # a typo: still the Nao
    arm = tmp_path / "arm.motion"
    arm.write_bytes(b"#WEBOTS_MOTION,V1.0,elbow_joint\n0,A,0\n")
    stray = tmp_path / "stray.motion"
    stray.write_bytes(b"#WEBOTS_MOTION,V1.0,leg0\n0,A,0\n")
    specs = plan([nao, arm, stray], ["auto", "nao-v5"])
    assert [(Path(s.path).name, s.robot) for s in specs] == [
        ("nao.motion", "nao"),
        ("nao.motion", "nao-v5"),
        ("arm.motion", "ur5e"),
        ("arm.motion", "nao-v5"),
        ("stray.motion", "auto"),  # no robot fits: kept, and that run fails alone
        ("stray.motion", "nao-v5"),
    ]
    check_robots(["auto", "nao"])
    with pytest.raises(UnknownRobotError, match="did you mean 'nao'"):
        check_robots(["auto", "nao7"])


def test_a_cached_report_of_other_code_is_not_served(
    motions: list[Path], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The cache's key has the simulation code's stamp: after an edit or an upgrade of the
    code that measures a run (the same version number), the run is played again."""
    specs = plan(motions[:1], ["nao"])
    cache = tmp_path / "cache"
    first = run_batch(specs, runner, model_hash=lambda r: "h", jobs=1, cache_dir=cache)
    again = run_batch(specs, runner, model_hash=lambda r: "h", jobs=1, cache_dir=cache)
    assert [r.cached for r in (*first.runs, *again.runs)] == [False, True]
    assert batch_module.code_stamp() == batch_module.code_stamp()  # one stamp a process
    monkeypatch.setattr(batch_module, "code_stamp", lambda: "edited")
    edited = run_batch(specs, runner, model_hash=lambda r: "h", jobs=1, cache_dir=cache)
    assert not edited.runs[0].cached
    assert specs[0].cache_key("h", "a") != specs[0].cache_key("h", "b")


def test_cache_replays_only_what_is_missing(motions: list[Path], tmp_path: Path) -> None:
    specs = plan(
        motions, ["nao"], perturbations=[parse_perturbation("friction=0.6:1.0")], samples=3, seed=3
    )
    cache = tmp_path / "cache"
    first = run_batch(specs, runner, model_hash=lambda r: "h", jobs=2, cache_dir=cache)
    assert [r.cached for r in first.runs] == [False] * 6
    second = run_batch(specs, runner, model_hash=lambda r: "h", jobs=2, cache_dir=cache)
    assert [r.cached for r in second.runs] == [True] * 6
    assert [(r.status, r.report) for r in second.runs] == [(r.status, r.report) for r in first.runs]
    other_model = run_batch(
        specs[:1], runner, model_hash=lambda r: "other", jobs=1, cache_dir=cache
    )
    assert not other_model.runs[0].cached
    expected = [
        "failed"
        if (s.path.endswith("long.motion") or dict(s.params)["friction"] < 0.8)
        else "clean"
        for s in specs
    ]
    assert [r.status for r in first.runs] == expected


def big_runner(spec: RunSpec) -> dict[str, Any]:
    """A report of about 100 kB (a long run's joint rows), with what JSON cannot spell plainly:
    NaN, and a name that is not UTF-8."""
    report = runner(spec)
    report["rows"] = [
        {"joint": f"J{k}", "rms": k / 7, "name": "Head\udcffYaw"} for k in range(2000)
    ]
    report["nan"] = float("nan")
    return report


def test_a_spooled_batch_holds_no_report_and_writes_the_same_json(
    motions: list[Path], tmp_path: Path
) -> None:
    specs = plan(
        motions, ["nao"], perturbations=[parse_perturbation("friction=0.7:1.3")], samples=3
    )
    held = run_batch(specs, big_runner, model_hash=lambda r: "h", jobs=2, cache_dir=None)
    spool = tmp_path / "spool"
    spool.mkdir()
    spooled = run_batch(
        specs, big_runner, model_hash=lambda r: "h", jobs=2, cache_dir=None, spool_dir=spool
    )
    assert all(r.report is None and r.stored is not None for r in spooled.runs)
    assert [r.tilt_deg for r in spooled.runs] == [r.tilt_deg for r in held.runs]
    spooled.wall_s = held.wall_s
    for a, b in zip(held.runs, spooled.runs, strict=True):
        b.wall_s = a.wall_s
    text = "".join(render_json(spooled))
    assert text == "".join(render_json(held))
    assert render_markdown(spooled) == render_markdown(held)
    doc = json.loads(text)
    assert doc["escaped_bytes"] == 6 * 2000 and len(doc["runs"]) == 6


def test_a_spooled_batch_holds_memory_flat_in_its_runs(motions: list[Path], tmp_path: Path) -> None:
    import tracemalloc

    specs = plan(
        motions, ["nao"], perturbations=[parse_perturbation("friction=0.7:1.3")], samples=4
    )

    def kept(spool: Path | None) -> int:
        tracemalloc.start()
        try:
            batch = run_batch(
                specs, big_runner, model_hash=lambda r: "h", jobs=2, cache_dir=None, spool_dir=spool
            )
            return tracemalloc.get_traced_memory()[0] if batch.runs else 0
        finally:
            tracemalloc.stop()

    spool = tmp_path / "spool"
    spool.mkdir()
    held, spooled = kept(None), kept(spool)
    assert held > 8 * 200_000  # 8 reports of about 300 kB held
    assert spooled < held / 5, (held, spooled)


@pytest.mark.needs("sim")
def test_reports(motions: list[Path], tmp_path: Path) -> None:
    specs = plan(motions, ["nao"])
    batch = run_batch(specs, runner, model_hash=lambda r: "h", jobs=2, cache_dir=None)
    summary = render_summary(batch)
    assert "long.motion" in summary and "failed: fell at 0.5 s" in summary
    assert summary.splitlines()[-1].startswith("2 runs: 1 clean, 1 not clean, 0 from cache;")
    doc = json.loads("".join(render_json(batch)))
    assert doc["summary"] == {"runs": 2, "clean": 1, "not_clean": 1, "cached": 0}
    assert doc["runs"][1]["report"]["base"]["max_tilt_deg"] == 60.0
    md = render_markdown(batch)
    assert "| motion | robot | runs | clean | worst case |" in md and "0 (0 %)" in md
    junit = tmp_path / "r.xml"
    write_junit(batch, junit)
    JUNIT_SCHEMA.validate(str(junit))  # Jenkins xunit's junit-10.xsd (tests/data/junit)
    suite = ET.parse(junit).getroot().find("testsuite")
    assert suite is not None and suite.get("tests") == "2" and suite.get("failures") == "1"
    failure = suite.find("testcase/failure")
    assert failure is not None and failure.get("message") == "fell at 0.5 s"


def test_markdown_cells_escape_pipes_and_line_breaks(tmp_path: Path) -> None:
    odd = tmp_path / "a|b.motion"
    odd.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n2000,B,0.5\n")
    batch = run_batch(plan([odd], ["nao"]), odd_runner, model_hash=lambda r: "h", jobs=1)
    row = render_markdown(batch).splitlines()[4]
    assert row.startswith("| `") and "a\\|b.motion" in row
    assert row.endswith("| failed: fell \\| badly then &lt;b>crashed&lt;/b> |")
    assert row.count("|") - row.count("\\|") == 6  # five cells, one row


def odd_runner(spec: RunSpec) -> dict[str, Any]:
    return {"clean": False, "reason": "fell | badly\nthen <b>crashed</b>"}


def test_recording_names_are_unique_and_keep_the_stem_when_they_can(tmp_path: Path) -> None:
    names = recording_stems(
        ["x/a/wave.motion", "x/b/wave.motion", "x/c/Wave.motion", "y/bow.motion"]
    )
    assert names == {
        "x/a/wave.motion": "a-wave",
        "x/b/wave.motion": "b-wave",
        "x/c/Wave.motion": "c-Wave",
        "y/bow.motion": "bow",
    }
    # A name that the folder-joined form still shares gets a hash of its path.
    clash = recording_stems(["x/a/wave.motion", "x/b/wave.motion", "x/a-wave.motion"])
    assert len(set(clash.values())) == 3 and clash["x/b/wave.motion"] == "b-wave"
    assert clash["x/a/wave.motion"].startswith("a-wave-")
    assert clash["x/a-wave.motion"].startswith("a-wave-")


@pytest.mark.needs("sim")
def test_batch_keeps_one_recording_per_motion_when_names_collide(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    for folder, value in (("a", b"0.2"), ("b", b"-0.2")):
        (tmp_path / folder).mkdir()
        (tmp_path / folder / "wave.motion").write_bytes(
            b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n200,B," + value + b"\n"
        )
    (tmp_path / "bow.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadPitch\n0,A,0\n200,B,0.2\n")
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(
        app, ["batch", ".", "--no-cache", "--jobs", "1", "--rrd-dir", "rrd"]
    )
    assert result.exit_code == 0, result.output
    # Before: both wave.motion runs wrote rrd/wave.nao.0.rrd, the second over the first.
    assert sorted(p.name for p in (tmp_path / "rrd").iterdir()) == [
        "a-wave.nao.0.rrd",
        "b-wave.nao.0.rrd",
        "bow.nao.0.rrd",
    ]


@pytest.mark.needs("sim")
@pytest.mark.parametrize("option", ["--json", "--markdown", "--junit"])
def test_a_report_where_a_recording_goes_is_refused_before_any_run(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, option: str
) -> None:
    """``batch in.motion --rrd-dir R --json R/in.nao.0.rrd`` replaced the run's recording with
    the report and said "wrote": refused (exit 2, one line) before anything runs, the
    recording as it was, whether it is named or reached through a symlink."""
    (tmp_path / "in.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n200,B,0.2\n")
    monkeypatch.chdir(tmp_path)
    base = ["batch", "in.motion", "--no-cache", "-j", "1", "--rrd-dir", "rrd"]
    fresh = CliRunner().invoke(app, [*base, option, "rrd/in.nao.0.rrd"])
    assert (fresh.exit_code, fresh.stdout) == (2, ""), fresh.output
    assert fresh.stderr == (
        f"motiontool: error: {option} and --rrd-dir both write 'rrd/in.nao.0.rrd' (the "
        "recording of in.motion on nao, sample 0); give each its own file\n"
    )
    assert not (tmp_path / "rrd").exists()  # nothing written, not even the folder
    first = CliRunner().invoke(app, base)
    assert first.exit_code == 0, first.output
    recording = tmp_path / "rrd" / "in.nao.0.rrd"
    before = recording.read_bytes()
    (tmp_path / "link").symlink_to(recording)
    for target in ("rrd/in.nao.0.rrd", "link", "./rrd/../rrd/in.nao.0.rrd"):
        again = CliRunner().invoke(app, [*base, option, target])
        assert again.exit_code == 2 and "--rrd-dir both write" in again.stderr, again.output
        assert "wrote" not in again.output
        assert recording.read_bytes() == before
    ok = CliRunner().invoke(app, [*base, option, "rrd/report"])  # beside the recordings: fine
    assert ok.exit_code == 0, ok.output


def unwritable(spec: RunSpec) -> dict[str, Any]:
    """Stand-in that cannot write its output for the short motion (a full disk)."""
    if "short" in spec.path:
        raise OutputError(f"cannot write '{spec.path}.rrd': No space left on device")
    return runner(spec)


def test_a_run_that_cannot_write_its_output_stops_the_batch(motions: list[Path]) -> None:
    """An OutputError is no failed run among others (the next ones would fail the same way):
    the batch stops with it, whatever the executor (one line, exit 2 in the CLI)."""
    specs = plan(motions, ["nao"])
    with pytest.raises(OutputError, match=r"No space left on device \(the batch stopped at run"):
        run_batch(specs, unwritable, model_hash=lambda _: "m", jobs=1)
    specs = plan(motions[1:], ["nao"])  # the other motion alone: a run that fails, no error
    assert run_batch(specs, unwritable, model_hash=lambda _: "m", jobs=1).runs[0].ok is False


@pytest.fixture
def full_folder(tmp_path: Path) -> Iterator[Path]:
    """A folder on a full disk: a tiny tmpfs, filled (mounting needs root, which CI has)."""
    folder = tmp_path / "full"
    folder.mkdir()
    done = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(folder)],
        capture_output=True,
        check=False,
    )
    if done.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs: {done.stderr.decode(errors='replace').strip()}")
    try:
        with contextlib.suppress(OSError), (folder / "filler").open("wb") as f:
            f.write(b"\0" * (1 << 20))  # ENOSPC once the 64 KiB are taken
        yield folder
    finally:
        subprocess.run(["umount", str(folder)], check=True)


@pytest.mark.needs("sim")
def test_recordings_on_a_full_disk_are_an_io_error_not_a_failed_run(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, full_folder: Path
) -> None:
    """``batch --rrd-dir`` on a full disk counted a failed run, exit 1, and said "wrote" about
    its reports and the folder: an I/O error stops the batch (exit 2, one line, nothing
    written, no temporary file left)."""
    for name in ("a", "b"):
        (tmp_path / f"{name}.motion").write_bytes(
            b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n200,B,0.2\n"
        )
    monkeypatch.chdir(tmp_path)
    args = ["batch", "a.motion", "b.motion", "--no-cache", "-j", "1", "--json", "r.json"]
    result = CliRunner().invoke(app, [*args, "--rrd-dir", "full/rrd"])
    assert (result.exit_code, result.stdout) == (2, ""), result.output
    assert result.stderr == (
        "motiontool: error: cannot write 'full/rrd/a.nao.0.rrd': No space left on device "
        "(the batch stopped at run 1 of 2)\n"
    )
    assert not (tmp_path / "r.json").exists()
    assert sorted(p.name for p in full_folder.rglob("*")) == ["filler", "rrd"]


@pytest.mark.needs("sim")
def test_a_file_without_a_robot_is_one_failed_run_and_the_others_are_reported(
    tmp_path: Path,
) -> None:
    (tmp_path / "good.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n200,B,0.2\n")
    (tmp_path / "typos.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYw,Foo,Bar\n0,A,0,0,0\n")
    (tmp_path / "syntax.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,abc\n")
    report = tmp_path / "report.json"
    junit = tmp_path / "report.xml"
    result = CliRunner().invoke(
        app,
        [
            "batch",
            str(tmp_path),
            "--no-cache",
            "-j",
            "1",
            "--json",
            str(report),
            "--junit",
            str(junit),
        ],
    )
    assert result.exit_code == 1, result.output  # was 2, before anything ran, and no report
    doc = json.loads(report.read_text())
    runs = {Path(r["spec"]["path"]).name: r for r in doc["runs"]}
    assert runs["good.motion"]["status"] == "clean"
    assert runs["typos.motion"]["status"] == "error"
    assert runs["typos.motion"]["reason"] == (
        "no robot fits the motion: no built-in robot (nao, nao-v5, ur5e) has any of its joints;"
        " name the robot explicitly (nao, nao-v5, ur5e, a .urdf/.xml path, or erd:<name>)"
    )
    assert runs["syntax.motion"]["status"] == "error"
    assert runs["syntax.motion"]["reason"] == (
        f"{tmp_path / 'syntax.motion'}:2:5: expected a number or '*' for HeadYaw, found 'abc'"
        " [MT108]"
    )
    for r in doc["runs"]:  # the diagnostic only: no exception class, no source path
        assert "Error:" not in r["reason"] and ".py" not in r["reason"]
    JUNIT_SCHEMA.validate(str(junit))
    suite = ET.parse(junit).getroot().find("testsuite")
    assert suite is not None and suite.get("tests") == "3" and suite.get("errors") == "2"


def test_speed_perturbation_retimes_as_retime_speed_does(tmp_path: Path) -> None:
    from motiontool.motionfmt.retime import scale_times
    from motiontool.sim.runs import retimed

    src = tmp_path / "m.motion"
    src.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n5,B,0.1\n16,C,0.2\n")
    motion = read_motion(str(src))
    batch = retimed(motion, 2.0)  # in memory: no temporary file
    result = CliRunner().invoke(
        app, ["retime", str(src), "--speed", "2", "-o", str(tmp_path / "r.motion")]
    )
    assert result.exit_code == 0, result.output
    written = read_motion(str(tmp_path / "r.motion"))
    # 5 / 2 = 2.5 ms: batch rounded it to even (2), retime half up (3).
    assert batch.times_ms.tolist() == written.times_ms.tolist() == [0, 3, 8]
    assert list(scale_times([0, 5, 16], 2.0).times_ms) == [0, 3, 8]
    assert batch.values.tobytes() == written.values.tobytes() == motion.values.tobytes()
    assert (batch.joints, batch.pose_names) == (motion.joints, motion.pose_names)


@pytest.mark.needs("sim")
def test_a_cached_run_whose_recording_is_missing_runs_again(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / "nod.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n200,B,0.2\n")
    monkeypatch.chdir(tmp_path)
    args = ["batch", "nod.motion", "-j", "1", "--cache-dir", "cache", "--rrd-dir", "rrd"]
    args += ["--json", "report.json"]
    first = CliRunner().invoke(app, args)
    assert first.exit_code == 0, first.output
    rrd = tmp_path / "rrd" / "nod.nao.0.rrd"
    assert rrd.is_file()
    rrd.unlink()
    again = CliRunner().invoke(app, args)
    assert again.exit_code == 0, again.output
    # Before: served from the cache, and no recording written.
    assert rrd.is_file()
    assert json.loads((tmp_path / "report.json").read_text())["summary"]["cached"] == 0
    third = CliRunner().invoke(app, args)  # the recording is there: the cache serves the run
    assert third.exit_code == 0, third.output
    assert json.loads((tmp_path / "report.json").read_text())["summary"]["cached"] == 1


def test_cached_results_are_used_only_while_the_runs_outputs_exist(
    motions: list[Path], tmp_path: Path
) -> None:
    specs = plan(motions[:1], ["nao"])
    marker = tmp_path / "made.txt"
    cache = tmp_path / "cache"

    def outputs(spec: RunSpec) -> list[Path]:
        return [marker]

    first = run_batch(specs, runner, model_hash=lambda r: "h", cache_dir=cache, outputs=outputs)
    assert not first.runs[0].cached  # nothing cached yet
    second = run_batch(specs, runner, model_hash=lambda r: "h", cache_dir=cache, outputs=outputs)
    assert not second.runs[0].cached  # cached, but its output is missing
    marker.write_text("")
    third = run_batch(specs, runner, model_hash=lambda r: "h", cache_dir=cache, outputs=outputs)
    assert third.runs[0].cached


def test_unknown_executor_names_the_choices(motions: list[Path]) -> None:
    with pytest.raises(MotionToolError, match="unknown executor 'dask'; choose local or ray"):
        run_batch(plan(motions, ["nao"]), runner, model_hash=lambda r: "h", executor="dask")
