"""Every report format of the registry (``motiontool.cli.reports.REPORTS``) is offered by
``validate --format`` and renders a real report; GitLab Code Quality in detail."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.cli.reports import REPORTS

runner = CliRunner()

# Webots accepts it; 'nan' is an error (MT1xx), '2rad' a warning.
BAD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,P1,0,2rad\n00:00:080,P2,nan,0\n"
MACHINE = {"json", "sarif", "gitlab"}  # formats that are one JSON document


@pytest.fixture
def here(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "bad.motion").write_bytes(BAD)
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.mark.parametrize("fmt", list(REPORTS))
def test_every_registered_format_renders_the_findings(here: Path, fmt: str) -> None:
    result = runner.invoke(app, ["validate", "--robot", "none", "-f", fmt, "sub/bad.motion"])
    assert result.exit_code == 1, result.output
    out = result.stdout
    if fmt in MACHINE:
        json.loads(out)
    assert "MT" in out and ("bad.motion" in out or "bad.motion" in json.dumps(json.loads(out)))


def test_help_offers_every_registered_format() -> None:
    help_text = runner.invoke(app, ["validate", "--help"]).stdout
    assert f"<{'|'.join(REPORTS)}>" in help_text


def gitlab(args: list[str]) -> list[dict[str, object]]:
    result = runner.invoke(app, ["validate", "--robot", "none", "-f", "gitlab", *args])
    assert result.exit_code == 1, result.output
    issues = json.loads(result.stdout)
    assert isinstance(issues, list)
    return issues


def test_gitlab_code_quality_issues(here: Path) -> None:
    issues = gitlab(["sub/bad.motion"])
    assert [(i["check_name"], i["severity"]) for i in issues] == [
        ("MT203", "minor"),
        ("MT113", "major"),
    ]
    for issue in issues:
        assert set(issue) >= {"description", "check_name", "fingerprint", "severity", "location"}
        assert issue["severity"] in {"info", "minor", "major", "critical", "blocker"}
        location = issue["location"]
        assert isinstance(location, dict) and location["path"] == "sub/bad.motion"
        assert location["lines"]["begin"] >= 1
        assert str(issue["description"]).startswith(str(issue["check_name"]))
    assert len({i["fingerprint"] for i in issues}) == len(issues)


def test_gitlab_fingerprints_survive_a_line_added_above(here: Path) -> None:
    before = {i["fingerprint"] for i in gitlab(["sub/bad.motion"])}
    lines = BAD.split(b"\n")
    shifted = b"\n".join([lines[0], b"00:00:000,P0,0,0", *lines[1:]])
    shifted = shifted.replace(b"00:00:000,P1", b"00:00:040,P1")
    (here / "sub" / "bad.motion").write_bytes(shifted)
    after = {i["fingerprint"] for i in gitlab(["sub/bad.motion"])}
    assert before <= after


def test_gitlab_paths_are_relative_to_the_working_directory(
    here: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(here / "sub")
    (issue, *_) = gitlab([str(here / "sub" / "bad.motion")])
    assert issue["location"]["path"] == "bad.motion"  # type: ignore[index]
