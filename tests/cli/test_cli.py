"""The command line, in process (Typer's CliRunner) and once through the installed script."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import DATA
from typer.testing import CliRunner

from motiontool.cli.app import app

runner = CliRunner()

GOOD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,Pose1,0,0\n00:00:500,Pose2,0.5,-0.2\n"
BAD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,Pose1,0,0\n00:00:040,Pose2,-1.5,abc\n"
WARN = b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:01:000,Pose1,0.5\n"


@pytest.fixture
def files(tmp_path: Path) -> Path:
    (tmp_path / "good.motion").write_bytes(GOOD)
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "bad.motion").write_bytes(BAD)
    (tmp_path / "warn.motion").write_bytes(WARN)
    (tmp_path / "notes.txt").write_text("not a motion")
    return tmp_path


def invoke(*args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, list(args))
    return result.exit_code, result.stdout, result.stderr


@pytest.mark.needs("kinematics")
def test_validate_clean_file_exits_0(files: Path) -> None:
    code, out, _ = invoke("validate", str(files / "good.motion"))
    assert code == 0
    assert out.splitlines()[0].startswith("robot: nao (20 ms controller step, model sha256 ")
    assert out.splitlines()[1:] == ["checked 1 file: 0 errors, 0 warnings, 0 notes"]
    code, out, _ = invoke("validate", "--robot", "none", str(files / "good.motion"))
    assert (code, out) == (
        0,
        "robot: none (--robot none): Webots syntax checks only\n"
        "checked 1 file: 0 errors, 0 warnings, 0 notes\n",
    )


def test_validate_text_reads_like_a_compiler(files: Path) -> None:
    code, out, _ = invoke("validate", str(files / "sub" / "bad.motion"))
    assert code == 1
    path = files / "sub" / "bad.motion"
    assert out.splitlines() == [
        "robot: not checked against a robot: 1 file Webots rejects",
        f"{path}:3:22: error MT108: expected a number or '*' for HeadPitch, found 'abc'",
        " 3 | 00:00:040,Pose2,-1.5,abc",
        "   |                      ^~~",
        "checked 1 file: 1 error, 0 warnings, 0 notes",
    ]


@pytest.mark.needs("kinematics")
def test_validate_directory_recursively(files: Path) -> None:
    code, out, _ = invoke("validate", str(files))
    assert code == 1
    assert out.endswith("checked 3 files: 1 error, 1 warning, 0 notes\n")


def test_warnings_pass_unless_strict(files: Path) -> None:
    assert invoke("validate", str(files / "warn.motion"))[0] == 0
    assert invoke("validate", "--strict", str(files / "warn.motion"))[0] == 1
    assert invoke("validate", "--strict", "--ignore", "MT206", str(files / "warn.motion"))[0] == 0


@pytest.mark.needs("kinematics")
def test_json_report(files: Path) -> None:
    code, out, _ = invoke("validate", "--format", "json", str(files))
    assert code == 1
    doc = json.loads(out)
    assert doc["schema"] == "motiontool.validate" and doc["schema_version"] == 1
    assert doc["stamps"]["motiontool"] and "mujoco" in doc["stamps"]
    assert doc["summary"] == {"files": 3, "errors": 1, "warnings": 1, "notes": 0}
    bad = next(f for f in doc["files"] if f["path"].endswith("bad.motion"))
    assert bad["accepted_by_webots"] is False
    assert bad["diagnostics"] == [
        {
            "code": "MT108",
            "severity": "error",
            "line": 3,
            "column": 22,
            "end_column": 25,
            "message": "expected a number or '*' for HeadPitch, found 'abc'",
            "hint": None,
            "joint": "HeadPitch",
            "time_ms": 40,
            "fix": None,
        }
    ]


def test_sarif_report(files: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(files)
    out_file = files / "report.sarif"
    code, out, _ = invoke("validate", "--format", "sarif", "-o", str(out_file), ".")
    assert code == 1 and out == ""
    doc = json.loads(out_file.read_text())
    assert doc["version"] == "2.1.0"
    run = doc["runs"][0]
    assert run["tool"]["driver"]["name"] == "motiontool"
    rules = [r["id"] for r in run["tool"]["driver"]["rules"]]
    results = run["results"]
    assert {r["ruleId"] for r in results} == {"MT108", "MT206"}
    bad = next(r for r in results if r["ruleId"] == "MT108")
    assert rules[bad["ruleIndex"]] == "MT108"
    assert bad["level"] == "error"
    loc = bad["locations"][0]["physicalLocation"]
    assert loc["artifactLocation"]["uri"] == "sub/bad.motion"
    assert loc["region"] == {"startLine": 3, "startColumn": 22, "endColumn": 25}


def test_github_annotations(files: Path) -> None:
    code, out, _ = invoke("validate", "--format", "github", str(files / "sub" / "bad.motion"))
    assert code == 1
    line = out.splitlines()[0]
    assert line.startswith(
        f"::error file={files / 'sub' / 'bad.motion'},line=3,col=22,endColumn=25,"
    )
    assert "title=MT108 invalid value%3A expected a number or '*'::" in line
    assert line.endswith("::expected a number or '*' for HeadPitch, found 'abc'")


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            ["validate", "missing.motion"],
            "motiontool: error: cannot read 'missing.motion': No such file or directory\n",
        ),
        (["validate", "emptydir"], "motiontool: error: no .motion file under 'emptydir'\n"),
        (
            ["validate", "--ignore", "MT999", "x"],
            "motiontool: error: --ignore: unknown code 'MT999'; did you mean 'MT902'?\n",
        ),
        (
            ["info", "missing.motion"],
            "motiontool: error: cannot read 'missing.motion': No such file or directory\n",
        ),
    ],
)
def test_usage_and_io_errors_exit_2_with_one_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, args: list[str], message: str
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "emptydir").mkdir()
    (tmp_path / "x").write_bytes(GOOD)
    code, out, err = invoke(*args)
    assert (code, out, err) == (2, "", message)


def test_bad_option_value_is_a_usage_error(files: Path) -> None:
    code, _, err = invoke("validate", "--format", "xml", str(files))
    assert code == 2 and "xml" in err


def test_info_text_and_json(files: Path) -> None:
    code, out, _ = invoke("info", str(files / "good.motion"))
    assert code == 0
    rows = dict(re.split(r"\s{2,}", line, maxsplit=1) for line in out.splitlines())
    assert rows["poses"] == "2" and rows["duration"] == "500 ms (0.500 s)"
    assert rows["spacing"] == "500 ms (uniform)" and rows["undefined"] == "0 cells ('*')"
    code, out, _ = invoke("info", "--format", "json", str(files / "good.motion"))
    doc = json.loads(out)
    assert (
        doc["poses"] == 2
        and doc["duration_ms"] == 500
        and doc["joints"] == ["HeadYaw", "HeadPitch"]
    )


def test_info_counts_star_and_marker_as_no_command_but_not_nan(tmp_path: Path) -> None:
    path = tmp_path / "odd.motion"
    path.write_bytes(b"#WEBOTS_MOTION,V1.0,A,B\n0,P,nan,*\n100,Q,1,-9999999.9\n")
    code, out, _ = invoke("info", "--format", "json", str(path))
    assert code == 0, out
    assert json.loads(out)["undefined"] == {"A": 0, "B": 2}  # Webots sends 'nan' to A


def test_info_on_a_rejected_file_names_the_error(files: Path) -> None:
    code, out, err = invoke("info", str(files / "sub" / "bad.motion"))
    assert code == 2 and out == ""
    assert (
        err
        == f"motiontool: error: {files / 'sub' / 'bad.motion'}:3:22: expected a number or '*' for HeadPitch, found 'abc' [MT108]\n"
    )


def test_sample_csv(tmp_path: Path) -> None:
    path = tmp_path / "ex.motion"
    path.write_bytes(
        b"#WEBOTS_MOTION,V1.0,A,B\n00:00:000,P1,0,*\n00:00:100,P2,1,2\n00:00:150,P3,0.5,1\n"
    )
    code, out, _ = invoke("sample", str(path), "--timestep", "32")
    assert code == 0
    assert out == "time_ms,A,B\n0,0.0,\n32,0.32,\n64,0.64,\n96,0.96,\n128,0.72,1.44\n160,0.5,1.0\n"


def test_sample_json_and_output_file(tmp_path: Path) -> None:
    path = tmp_path / "ex.motion"
    path.write_bytes(GOOD)
    out_file = tmp_path / "s.json"
    code, out, _ = invoke("sample", str(path), "-t", "250", "-f", "json", "-o", str(out_file))
    assert code == 0 and out == ""
    doc = json.loads(out_file.read_text())
    assert doc["elapsed_ms"] == [0, 250, 500]
    assert doc["targets"] == [[0.0, 0.0], [0.25, -0.1], [0.5, -0.2]]


def test_codes_lists_every_code() -> None:
    from motiontool.motionfmt.diagnostics import CODES

    code, out, _ = invoke("codes")
    assert code == 0 and len(out.splitlines()) == len(CODES)


def test_validate_the_webots_corpus_has_no_syntax_error(corpus: Path) -> None:
    # Robot checks find real problems in some Webots files (tests/kinematics/test_checks.py).
    code, out, _ = invoke("validate", "--robot", "none", str(corpus))
    assert code == 0, out


def test_installed_script(tmp_path: Path) -> None:
    script = shutil.which("motiontool", path=str(Path(sys.executable).parent))
    assert script, "the console script 'motiontool' is not installed next to this Python"
    bad = DATA / "invalid" / "decimal_comma.motion"
    proc = subprocess.run(
        [script, "validate", str(bad)], capture_output=True, text=True, check=False
    )
    assert proc.returncode == 1
    assert "error MT110" in proc.stdout and "decimal comma?" in proc.stdout
    proc = subprocess.run(
        [script, "validate", str(tmp_path / "nope.motion")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert (proc.returncode, proc.stderr) == (
        2,
        f"motiontool: error: cannot read '{tmp_path / 'nope.motion'}': No such file or directory\n",
    )
    assert "Traceback" not in proc.stderr


@pytest.mark.needs("plot")
@pytest.mark.parametrize(
    "rows",
    [
        b"8,P,1e308,1.7976931348623157e308\n",  # one pose: a flat panel at the double's end
        b"20,P,1e308,-1e308\n1000,Q,-1e200,1e308\n2147483647,R,-1e200,0\n",  # span overflows
    ],
)
def test_plot_draws_values_near_the_double_s_end(tmp_path: Path, rows: bytes) -> None:
    """A range of -1e308 to 1e308 overflowed matplotlib's ticks (a ValueError traceback) and
    printed numpy's overflow warnings (pytest makes them errors here)."""
    path = tmp_path / "w.motion"
    path.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw,RShoulderPitch\n" + rows)
    result = runner.invoke(app, ["plot", str(path), "-o", str(tmp_path / "w.png")])
    assert result.exit_code == 0, result.output
    assert (tmp_path / "w.png").read_bytes().startswith(b"\x89PNG\r\n\x1a\n")


@pytest.mark.needs("plot")
def test_plot_to_stdout_and_diff_plot_refuses_stdout(tmp_path: Path) -> None:
    path = tmp_path / "w.motion"
    path.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,P,0\n400,Q,1\n")
    result = runner.invoke(app, ["plot", str(path), "-o", "-"])
    assert result.exit_code == 0, result.output
    assert result.stdout_bytes.startswith(b"\x89PNG\r\n\x1a\n")
    assert result.stderr.startswith("PNG on stdout: 1 joint in 1 group; robot nao (model ")
    assert "wrote" not in result.stderr  # stdout is not a file written
    assert not (tmp_path / "-").exists() and not Path("-").exists()
    code, out, err = invoke("diff", str(path), str(path), "--plot", "-")
    assert (code, out) == (2, "")
    assert (
        err == "motiontool: error: --plot -: the report goes to stdout; name a PNG file to write\n"
    )
