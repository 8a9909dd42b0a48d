"""``validate`` reads top-down: the command checks each file and hands it to the report's
writer (``cli/validate_report.py:report_pieces``); a writer (``cli/reports/``) never reads or
checks a file, and an error in a check comes from the check, not from the report."""

from __future__ import annotations

import re
import sys
import traceback
from collections import Counter
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from types import FrameType
from typing import Any

import pytest
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.cli.reports import REPORTS
from motiontool.errors import MotionToolError
from motiontool.kinematics.checks import RobotChecks
from motiontool.motionfmt import validate as validate_module
from motiontool.motionfmt.findings import Findings
from motiontool.motionfmt.reader import ReadResult

runner = CliRunner()

# Webots accepts both; HeadPitch 2 rad is past the Nao's limit (MT302)
ONE = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,P1,0,2\n00:00:100,P2,0.1,0\n"
TWO = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,P1,0,0\n00:00:100,P2,0.2,2\n"
_FRAME = re.compile(r'^  File "(?P<file>[^"]+)", line \d+, in (?P<name>\S+)$', re.MULTILINE)


@pytest.fixture
def two_files(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> list[str]:
    (tmp_path / "a.motion").write_bytes(ONE)
    (tmp_path / "b.motion").write_bytes(TWO)
    monkeypatch.chdir(tmp_path)
    return ["a.motion", "b.motion"]


def _in_a_writer() -> bool:
    """Whether a report writer (a module of ``cli/reports``) is on the stack."""
    return any("/cli/reports/" in frame.filename for frame in traceback.extract_stack())


def _exploding_check(self: RobotChecks, result: ReadResult, *, group: bool) -> Findings:
    raise MotionToolError(f"the check broke on {result.path}")


@pytest.mark.parametrize("fmt", ["json", "sarif", "junit", "text"])
def test_an_error_in_a_check_comes_from_the_check(
    two_files: list[str], monkeypatch: pytest.MonkeyPatch, fmt: str
) -> None:
    monkeypatch.setattr(RobotChecks, "_check", _exploding_check)
    result = runner.invoke(
        app, ["--debug", "validate", *two_files, "--robot", "nao", "--no-cache", "-f", fmt]
    )
    assert result.exit_code == 2, result.output
    assert "the check broke on a.motion" in result.stderr
    frames = [(m["file"], m["name"]) for m in _FRAME.finditer(result.stderr)]
    names = [name for _file, name in frames]
    assert "validate_command" in names and names[-1] == "_exploding_check", result.stderr
    between = frames[names.index("validate_command") : -1]
    assert [f for f, _name in between if "/cli/reports/" in f] == [], result.stderr
    assert "report_pieces" in names or "surveyed" in names  # the command's loop checks it
    assert not any("emit_pieces" in n or "in_blocks" in n for n in names)  # nor the output


@pytest.mark.parametrize("fmt", list(REPORTS))
def test_the_command_reads_and_checks_each_file_then_hands_it_to_the_writer(
    two_files: list[str], monkeypatch: pytest.MonkeyPatch, fmt: str
) -> None:
    calls: list[tuple[str, str]] = []
    read_bytes, check = validate_module.read_bytes, RobotChecks._check

    def reading(data: bytes, path: str, **kwargs: object) -> ReadResult:
        assert not _in_a_writer(), "a report writer read a file"
        calls.append(("read", path))
        return read_bytes(data, path, **kwargs)  # type: ignore[arg-type]

    def checking(self: RobotChecks, result: ReadResult, *, group: bool) -> Findings:
        assert not _in_a_writer(), "a report writer checked a file"
        calls.append(("check", result.path))
        return check(self, result, group=group)

    writer = REPORTS[fmt].writer
    handed = writer.file  # type: ignore[attr-defined]

    def rendering(self: object, f: validate_module.FileReport, shown: object) -> object:
        calls.append(("render", f.path))
        return handed(self, f, shown)

    monkeypatch.setattr(validate_module, "read_bytes", reading)
    monkeypatch.setattr(RobotChecks, "_check", checking)
    monkeypatch.setattr(writer, "file", rendering)
    result = runner.invoke(app, ["validate", *two_files, "--robot", "nao", "--no-cache", "-f", fmt])
    assert result.exit_code == 1, result.output
    each = [("read", "a.motion"), ("check", "a.motion"), ("read", "b.motion")]
    each += [("check", "b.motion")]
    renders = [("render", "a.motion"), ("render", "b.motion")]
    if fmt == "sarif" or fmt == "github" or fmt == "gitlab":  # no head that names the robots
        assert calls == [*each[:2], renders[0], *each[2:], renders[1]]
    else:  # the robots of every file first (text, json), or how many fail (junit)
        assert calls == [*each, *renders]


def test_a_file_past_the_held_bytes_is_read_again_by_the_command(
    two_files: list[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """``--sort severity`` passes over the files once per severity; with no report held, the
    command checks a file again for each pass, and the writer is handed each one."""
    monkeypatch.setattr(validate_module, "HELD_INPUT_BYTES", 0)
    calls: list[str] = []
    read_bytes = validate_module.read_bytes

    def reading(data: bytes, path: str, **kwargs: object) -> ReadResult:
        assert not _in_a_writer(), "a report writer read a file"
        calls.append(path)
        return read_bytes(data, path, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(validate_module, "read_bytes", reading)
    args = ["validate", *two_files, "--robot", "nao", "--no-cache", "-f", "github"]
    result = runner.invoke(app, [*args, "--sort", "severity"])
    assert result.exit_code == 1, result.output
    assert calls[:2] == ["a.motion", "b.motion"] and len(calls) > 2
    lines = [x for x in result.stdout.splitlines() if x.startswith("::error")]
    assert len(lines) == 2 and "a.motion" in lines[0] and "b.motion" in lines[1]


def _layer(frame: FrameType) -> str | None:
    name = str(frame.f_globals.get("__name__", ""))
    if not name.startswith("motiontool."):
        return None
    return "cli" if name.startswith("motiontool.cli.") else "library"


@contextmanager
def _calls_back() -> Iterator[Counter[str]]:
    """Every call from the library (motionfmt, kinematics, sim) into ``motiontool.cli`` while
    the block runs, counted by the cli function called."""
    back: Counter[str] = Counter()

    def profile(frame: FrameType, event: str, arg: Any) -> None:
        if event != "call" or _layer(frame) != "cli":
            return
        caller = frame.f_back
        while caller is not None and _layer(caller) is None:
            caller = caller.f_back
        if caller is not None and _layer(caller) == "library":
            back[f"{frame.f_globals['__name__']}.{frame.f_code.co_qualname}"] += 1

    sys.setprofile(profile)
    try:
        yield back
    finally:
        sys.setprofile(None)


@pytest.mark.needs("kinematics")
def test_validate_goes_to_the_library_and_back_once_per_file(two_files: list[str]) -> None:
    """The library calls the command back only to say how far it is (the progress display):
    never to read, check or settle a file."""
    with _calls_back() as back:
        result = runner.invoke(
            app, ["validate", *two_files, "--robot", "nao", "--no-cache", "-f", "json"]
        )
    assert result.exit_code == 1, result.output
    assert set(back) == {"motiontool.cli.progress.Step.__call__"}, back
    # each file: 'read', 'checks', then one line per robot check (limits, velocity, ...)
    assert back["motiontool.cli.progress.Step.__call__"] % len(two_files) == 0


@pytest.mark.needs("sim", "rerun")
def test_play_rrd_goes_to_the_library_and_back_once_per_chunk(tmp_path: Path) -> None:
    """``play --rrd`` (plan, run, report): the run calls the command back once a chunk, to
    say how far it is; the recording takes each chunk in the library."""
    from motiontool.sim import commands
    from motiontool.sim.recording import RunRecorder

    motion = tmp_path / "wave.motion"
    lines = [f"00:{k // 10:02d}:{k % 10 * 100:03d},P{k},{0.1 * (k % 3)},0" for k in range(80)]
    motion.write_text("#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n" + "\n".join(lines) + "\n")
    chunks = []
    add = RunRecorder.add

    def recorded(self: RunRecorder, chunk: Any) -> None:
        chunks.append(chunk)
        add(self, chunk)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(RunRecorder, "add", recorded)
        mp.setattr(commands, "CHUNK_STEPS", 256)  # a few chunks of a short run
        with _calls_back() as back:
            args = ["play", str(motion), "--headless", "--robot", "nao", "--loop", "3"]
            result = runner.invoke(app, [*args, "--rrd", str(tmp_path / "run.rrd")])
    assert result.exit_code == 0, result.output
    assert len(chunks) >= 3 and (tmp_path / "run.rrd").stat().st_size > 0
    # the progress display, told once a chunk how far the run is; nothing else
    assert back == Counter({"motiontool.cli.play._run.<locals>.simulated": len(chunks)}), back
