"""The files of a run are validated as a report reads them, and only the first ones are held
(``motionfmt.validate.FileReports``): memory stays flat however many files a run has, and every
report is the same whatever the budget (a report past it is made again, never changed)."""

from __future__ import annotations

import gc
import io
import json
import tracemalloc
import weakref
from pathlib import Path

import pytest
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.cli.reports import REPORTS
from motiontool.cli.validate_report import render_pieces
from motiontool.motionfmt import validate as validate_module
from motiontool.motionfmt.diagnostics import Diagnostic, Severity
from motiontool.motionfmt.reader import ReadResult
from motiontool.motionfmt.validate import FileReports, validate_bytes, validate_paths

runner = CliRunner()

# Webots accepts it; '2rad' is a warning, each pose past the Nao's HeadPitch limit an error.
GOOD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,P1,0,2rad\n00:00:080,P2,0.5,0.9\n"


def _files(folder: Path, n: int, data: bytes = GOOD) -> list[Path]:
    folder.mkdir(exist_ok=True)
    paths = [folder / f"f{k:02}.motion" for k in range(n)]
    for p in paths:
        p.write_bytes(data)
    return paths


class _Made:
    """A check that records the files it was run on."""

    def __init__(self) -> None:
        self.paths: list[str] = []

    def __call__(self, result: ReadResult) -> list[Diagnostic]:
        self.paths.append(result.path)
        return [Diagnostic("MT203", Severity.WARNING, result.path, 2, 1, "checked")]


def test_a_file_is_validated_when_a_report_reads_it_not_before(tmp_path: Path) -> None:
    paths = _files(tmp_path / "m", 3)
    made = _Made()
    report = validate_paths([tmp_path / "m"], checks=[made])
    assert made.paths == [] and report.files.paths == [str(p) for p in paths]
    assert report.files[1].path == str(paths[1])
    assert made.paths == [str(paths[1])]


def test_within_the_budget_each_file_is_validated_once(tmp_path: Path) -> None:
    _files(tmp_path / "m", 4)
    made = _Made()
    report = validate_paths([tmp_path / "m"], checks=[made])
    for _ in range(3):
        assert [len(f.diagnostics) for f in report.files] == [2, 2, 2, 2]
    assert len(made.paths) == 4


def test_past_the_budget_reports_are_let_go_and_made_again_the_same(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(validate_module, "HELD_INPUT_BYTES", len(GOOD))  # the first file only
    paths = _files(tmp_path / "m", 4)
    made = _Made()
    report = validate_paths([tmp_path / "m"], checks=[made])
    first = [list(f.diagnostics) for f in report.files]
    second_report = weakref.ref(report.files[1])
    report.files[2]
    gc.collect()
    assert second_report() is None  # let go once the next file is read
    assert [list(f.diagnostics) for f in report.files] == first
    assert made.paths.count(str(paths[0])) == 1  # held
    assert made.paths.count(str(paths[3])) == 2  # made again
    made.paths.clear()
    assert report.count(Severity.WARNING) == 8 and made.paths == []  # the counts are kept
    assert report.hidden == 0 and made.paths == []


def test_counting_a_file_once_is_enough(tmp_path: Path) -> None:
    data = [GOOD] * 3
    made: list[int] = []

    def make(i: int) -> validate_module.FileReport:
        made.append(i)
        return validate_bytes(data[i], f"f{i}", checks=[_Made()])

    files = FileReports(["f0", "f1", "f2"], make, budget=0)
    assert [files.tally(i, Severity.WARNING) for i in range(3)] == [2, 2, 2]
    assert made == [0, 1, 2]
    assert files.tally(0, Severity.WARNING) == 2 and made == [0, 1, 2]
    assert files[0].count(Severity.WARNING) == 2 and made == [0, 1, 2, 0]
    assert files[0].diagnostics.counts is not None  # known without a pass


def test_the_survey_validates_what_fits_and_only_surveys_the_rest(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from motiontool.cli import lint_run
    from motiontool.cli.config import Resolver
    from motiontool.kinematics.checks import RobotChecks

    made: list[str] = []
    surveyed: list[str] = []
    validate, read = lint_run.validate_bytes, lint_run.read_bytes
    monkeypatch.setattr(
        lint_run,
        "validate_bytes",
        lambda data, name, **kw: made.append(name) or validate(data, name, **kw),
    )
    monkeypatch.setattr(
        lint_run,
        "read_bytes",
        lambda data, name, **kw: surveyed.append(name) or read(data, name, **kw),
    )
    paths = [tmp_path / f"f{i}.motion" for i in range(4)]
    for p in paths:
        p.write_bytes(GOOD)
    names = [str(p) for p in paths]

    def checker(robot: str, checks: object, timestep: int | None) -> RobotChecks:
        return RobotChecks(robot, ["limits"], timestep_ms=timestep)

    def run_with(budget: int) -> lint_run.LintRun:
        monkeypatch.setattr(validate_module, "HELD_INPUT_BYTES", budget)
        made.clear()
        surveyed.clear()
        return lint_run.lint(
            paths, Resolver(isolated=True), lint_run.Overrides(robot="nao"), checker
        )

    run = run_with(2 * len(GOOD))
    run.surveyed()
    run.surveyed()  # once a run
    # The two that fit, then the first past the budget (the report reads it next).
    assert made == names[:3] and surveyed == names[3:]
    assert [run.check(i).path for i in range(4)] == names and made == names  # none made twice
    run = run_with(0)
    run.surveyed()
    assert made == names[:1] and surveyed == names[1:]


@pytest.mark.parametrize(
    "args",
    [
        *(["-f", fmt] for fmt in REPORTS),
        ["--sort", "severity"],
        ["--statistics"],
        ["-f", "junit", "--strict"],
        ["--no-group", "-f", "json"],
    ],
    ids=lambda a: " ".join(a),
)
def test_every_report_is_the_same_whatever_the_budget(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, args: list[str]
) -> None:
    folder = tmp_path / "m"
    _files(folder, 3)
    (folder / "g-rejected.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,P1,x\n")
    (folder / "h-arm.motion").write_bytes(
        b"#WEBOTS_MOTION,V1.0,shoulder_pan_joint,elbow_joint\n00:00:000,P1,0,0\n00:00:040,P2,3,9\n"
    )
    (folder / "i-unknown.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,Foo,Bar\n0,P1,0,0\n")
    (tmp_path / "motiontool.toml").write_text("max-findings = 9\n")
    monkeypatch.chdir(tmp_path)
    whole = runner.invoke(app, ["validate", "m", *args])
    monkeypatch.setattr(validate_module, "HELD_INPUT_BYTES", 0)
    none_held = runner.invoke(app, ["validate", "m", *args])
    assert whole.exit_code == none_held.exit_code == 1, whole.output
    assert none_held.stdout == whole.stdout
    if args == ["-f", "json"]:
        robots = json.loads(whole.stdout)["robot"]["robots"]
        assert [r["name"] for r in robots] == ["nao", "ur5e"]


def _peak_bytes(folder: Path) -> int:
    report = validate_paths([folder])
    tracemalloc.start()
    try:
        for piece in render_pieces(report, "text"):
            io.StringIO().write(piece)
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_memory_is_flat_in_the_number_of_files(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    lines = b"".join(b"00:%02d:%03d,P,0.1,0.2\n" % divmod(k * 40, 1000) for k in range(1, 1400))
    data = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,P0,0,0\n" + lines
    _files(tmp_path / "two", 2, data)
    _files(tmp_path / "eight", 8, data)
    monkeypatch.setattr(validate_module, "HELD_INPUT_BYTES", 0)
    two, eight = _peak_bytes(tmp_path / "two"), _peak_bytes(tmp_path / "eight")
    assert eight < 1.3 * two, (two, eight)
    monkeypatch.setattr(validate_module, "HELD_INPUT_BYTES", 1 << 30)  # all held: it grows
    assert _peak_bytes(tmp_path / "eight") > 2 * two


def test_a_pipe_is_read_once_and_held_past_the_budget(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A pipe (``validate <(...)``) cannot be read again: it is read before the report and
    held, however small the budget; the text report reads it for its robot line, then
    validates it."""
    import os
    import threading

    (regular,) = _files(tmp_path / "m", 1)
    fifo = tmp_path / "pipe.motion"
    os.mkfifo(fifo)

    def feed() -> None:
        with open(fifo, "wb") as sink:
            sink.write(GOOD)

    writer = threading.Thread(target=feed)
    writer.start()
    monkeypatch.setattr(validate_module, "HELD_INPUT_BYTES", 0)
    result = runner.invoke(app, ["validate", str(fifo), str(regular)])
    writer.join()
    assert result.exit_code == 1, result.output
    assert result.stdout.startswith("robot: nao (20 ms controller step")
    assert f"{fifo}:2:16: error MT302" in result.stdout
    assert f"{regular}:2:16: error MT302" in result.stdout
