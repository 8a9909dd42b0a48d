"""A command that writes files says what it wrote, one line each on stderr:
``motiontool: wrote PATH (what it holds)``, through :func:`motiontool.cli.output.say_wrote`;
never for an output that is stdout (``-``)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.cli.output import say_wrote, written_motion

runner = CliRunner()

NOD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,A,0,0\n00:00:040,B,0.1,-0.1\n"
NOD2 = b"#WEBOTS_MOTION,V1.0,HeadPitch,HeadYaw\n0,A,0,0\n40,B,-0.1,*\n80,C,0,0.2\n"

WROTE = re.compile(r"motiontool: wrote (.+?) \((.+)\)")


@pytest.fixture
def here(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "nod.motion").write_bytes(NOD)
    (tmp_path / "nod2.motion").write_bytes(NOD2)
    return tmp_path


def wrote(args: list[str]) -> tuple[str, dict[str, str]]:
    """Run ``motiontool ARGS``; its stdout and what its stderr says it wrote (path: detail)."""
    result = runner.invoke(app, args)
    assert result.exit_code in (0, 1), result.output
    said = [WROTE.fullmatch(line) for line in result.stderr.splitlines()]
    return result.stdout, {m[1]: m[2] for m in said if m}


def test_say_wrote_is_one_line_on_stderr_and_nothing_for_stdout(
    capsys: pytest.CaptureFixture[str],
) -> None:
    say_wrote(Path("out/walk20.motion"), written_motion(52, 2080))
    say_wrote(None, "ignored")
    say_wrote(Path("-"), "ignored")
    assert capsys.readouterr() == ("", "motiontool: wrote out/walk20.motion (52 poses, 2.08 s)\n")
    assert written_motion(1, 0) == "1 pose, 0 s"


@pytest.mark.parametrize(
    ("args", "said"),
    [
        (["resample", "nod2.motion", "--step", "20"], "5 poses, 0.08 s"),
        (["retime", "nod.motion", "--speed", "0.5"], "2 poses, 0.08 s"),
        (["mirror", "nod2.motion"], "3 poses, 0.08 s"),
        (["concat", "nod.motion", "nod2.motion", "--transition", "40"], "5 poses, 0.16 s"),
        (["trim", "nod2.motion", "--from", "40"], "2 poses, 0.04 s"),
        (["scale", "nod.motion", "-k", "2"], "2 poses, 0.04 s"),
    ],
    ids=lambda v: v[0] if isinstance(v, list) else "",
)
def test_every_authoring_command_says_the_motion_it_wrote(
    here: Path, args: list[str], said: str
) -> None:
    _, lines = wrote([*args, "-o", "out/m.motion"])
    assert lines == {"out/m.motion": said}
    assert (here / "out/m.motion").is_file()
    out, lines = wrote([*args, "-o", "-"])  # the motion on stdout: nothing written
    assert out.startswith("#WEBOTS_MOTION") and lines == {}


@pytest.mark.needs("kinematics")
def test_generate_sample_expect_diff_plot_and_export_say_what_they_wrote(here: Path) -> None:
    assert wrote(["generate", "ur5e-jog", "-o", "jog.motion"])[1] == {
        "jog.motion": "122 poses, 8.952 s"
    }
    assert wrote(["sample", "nod2.motion", "-t", "20", "-o", "s.csv"])[1] == {
        "s.csv": "CSV, 5 rows every 20 ms"
    }
    assert wrote(["sample", "nod2.motion", "-f", "json", "-o", "-"])[1] == {}
    assert wrote(["expect", "--infer", "nod.motion", "nod2.motion", "-o", "e.toml"])[1] == {
        "e.toml": "TOML, expectations of 2 motions"
    }
    assert wrote(["expect", "--infer", "nod.motion"])[1] == {}  # stdout
    assert wrote(["diff", "nod.motion", "nod2.motion", "--plot", "d.png"])[1] == {
        "d.png": "PNG plot, 2 joints"
    }
    (detail,) = wrote(["plot", "nod.motion", "-o", "p.png"])[1].values()
    assert detail.startswith("PNG: 2 joints in 1 group; robot nao")
    lines = wrote(["robots", "export", "ur5e", "--mjcf", "u.xml"])[1]
    assert lines == {"u.xml": f"MJCF, {(here / 'u.xml').stat().st_size} bytes, robot ur5e"}
    assert wrote(["robots", "export", "ur5e", "--mjcf", "-"])[1] == {}
    for name in ("jog.motion", "s.csv", "e.toml", "d.png", "p.png"):
        assert (here / name).stat().st_size > 0


@pytest.mark.needs("sim")
def test_play_says_its_report_and_recording(here: Path) -> None:
    out, lines = wrote(
        ["play", "--headless", "--hold", "0", "nod.motion", "--json", "r.json", "--rrd", "r.rrd"]
    )
    assert lines == {
        "r.json": "play report, JSON, 0.06 s simulated",
        "r.rrd": "Rerun recording, 0.06 s simulated",
    }
    assert "wrote" not in out  # the text report on stdout says nothing of it
    _, lines = wrote(["play", "--headless", "--hold", "0", "nod.motion", "--json", "-"])
    assert lines == {}


@pytest.mark.needs("sim")
def test_play_that_cannot_start_says_its_report(here: Path) -> None:
    (here / "bad.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,abc\n")
    result = runner.invoke(app, ["play", "--headless", "bad.motion", "--json", "r.json"])
    assert result.exit_code == 2
    assert "motiontool: wrote r.json (play report, JSON: the run could not start)\n" in (
        result.stderr
    )


@pytest.mark.needs("sim")
def test_batch_says_each_report_and_its_recordings(here: Path) -> None:
    _, lines = wrote(
        [
            *("batch", "nod.motion", "nod2.motion", "--jobs", "1", "--no-cache"),
            *("--json", "b.json", "--markdown", "b.md", "--junit", "b.xml", "--rrd-dir", "rrd"),
        ]
    )
    assert lines == {
        "b.json": "batch report, JSON, 2 runs",
        "b.md": "Markdown summary, 2 runs",
        "b.xml": "JUnit XML, 2 runs",
        "rrd": "a folder of Rerun recordings, one per run: 2 runs",
    }
    assert len(list((here / "rrd").glob("*.rrd"))) == 2


@pytest.mark.needs("kinematics")
def test_validate_says_the_report_it_wrote(here: Path) -> None:
    """``validate -o FILE`` said nothing; now its line names the format and
    the counts, and ``--diff -o FILE`` the patch."""
    (here / "bad.motion").write_bytes(NOD + b"00:00:080,C,2rad,0\n")
    assert wrote(["validate", "nod.motion", "-o", "r.txt"])[1] == {
        "r.txt": "text report of 1 file: 0 errors, 0 warnings, 0 notes"
    }
    assert wrote(["validate", "nod.motion", "bad.motion", "-f", "sarif", "-o", "r.sarif"])[1] == {
        "r.sarif": "SARIF report of 2 files: 0 errors, 2 warnings, 0 notes"
    }
    assert wrote(["validate", "nod.motion", "--statistics", "-o", "s.txt"])[1] == {
        "s.txt": "statistics report of 1 file: 0 errors, 0 warnings, 0 notes"
    }
    assert wrote(["validate", "nod.motion", "-f", "json", "-o", "-"])[1] == {}
    assert wrote(["validate", "bad.motion", "--diff", "-o", "fix.patch"])[1] == {
        "fix.patch": "unified diff, the fixes of 1 file"
    }
