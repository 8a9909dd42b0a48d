"""Every report format of the registry (``motiontool.cli.reports.REPORTS``) is offered by
``validate --format`` and renders a real report; GitLab Code Quality in detail."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import jsonschema
import numpy as np
import pytest
import xmlschema
from conftest import DATA
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.cli.reports import REPORTS

runner = CliRunner()
JUNIT_SCHEMA = xmlschema.XMLSchema(str(DATA / "junit" / "junit-10.xsd"))
"""Jenkins xunit's JUnit schema, the strictest reader of JUnit XML (tests/data/junit)."""

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


def sarif(args: list[str]) -> dict[str, object]:
    result = runner.invoke(app, ["validate", "--robot", "none", "-f", "sarif", *args])
    assert result.exit_code == 1, result.output
    doc: dict[str, object] = json.loads(result.stdout)
    return doc


def test_sarif_uris_are_relative_to_the_repository_root(
    here: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (here / ".git").mkdir()
    monkeypatch.chdir(here / "sub")
    run = sarif(["bad.motion"])["runs"][0]  # type: ignore[index]
    location = run["results"][0]["locations"][0]["physicalLocation"]["artifactLocation"]
    assert location == {"uri": "sub/bad.motion", "uriBaseId": "%SRCROOT%"}
    assert run["originalUriBaseIds"]["%SRCROOT%"]["uri"] == here.as_uri() + "/"
    assert gitlab(["bad.motion"])[0]["location"]["path"] == "sub/bad.motion"  # type: ignore[index]


def test_sarif_results_have_fingerprints_that_survive_a_line_added_above(here: Path) -> None:
    def prints() -> list[str]:
        run = sarif(["sub/bad.motion"])["runs"][0]  # type: ignore[index]
        return [r["partialFingerprints"]["motiontoolFinding/v1"] for r in run["results"]]

    before = prints()
    lines = BAD.split(b"\n")
    shifted = b"\n".join([lines[0], b"00:00:000,P0,0,0", *lines[1:]])
    (here / "sub" / "bad.motion").write_bytes(shifted.replace(b"00:00:000,P1", b"00:00:040,P1"))
    assert len(set(before)) == len(before) and set(before) <= set(prints())


def test_identical_findings_get_the_same_fingerprints_in_either_order(here: Path) -> None:
    """Identical findings (one message in one file) are told apart by their rank in their
    file; the ranks are counted a file at a time, and --sort severity gives the same ones."""
    twice = b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,P1,2rad\n00:00:040,P2,nan\n00:00:080,P3,2rad\n"
    (here / "sub" / "twice.motion").write_bytes(twice)
    files = ["sub/bad.motion", "sub/twice.motion"]

    def prints(*extra: str) -> dict[tuple[str, int], str]:
        run = sarif([*files, *extra])["runs"][0]  # type: ignore[index]
        return {
            (r["ruleId"], r["locations"][0]["physicalLocation"]["region"]["startLine"]): r[
                "partialFingerprints"
            ]["motiontoolFinding/v1"]
            for r in run["results"]
        }

    by_file, by_severity = prints(), prints("--sort", "severity")
    assert by_file == by_severity
    assert by_file[("MT203", 2)] != by_file[("MT203", 4)]  # one message, told apart by rank
    assert len(set(by_file.values())) == len(by_file)
    issues = gitlab([*files, "--sort", "severity"])
    assert {i["fingerprint"] for i in issues} == {i["fingerprint"] for i in gitlab(files)}


def test_every_sarif_rule_has_markdown_help(here: Path) -> None:
    run = sarif(["sub/bad.motion"])["runs"][0]  # type: ignore[index]
    driver = run["tool"]["driver"]
    for rule in driver["rules"]:
        assert rule["help"]["markdown"].startswith(f"**{rule['id']}**: ")


@pytest.mark.parametrize("strict", [False, True])
def test_junit_has_a_case_per_file_with_the_reason_in_the_failure_body(
    here: Path, strict: bool
) -> None:
    import xml.etree.ElementTree as ET

    (here / "ok.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,P,0\n")
    (here / "warn.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,P,1rad\n")
    args = ["validate", "--robot", "none", "-f", "junit", "sub/bad.motion", "ok.motion"]
    result = runner.invoke(app, [*args, "warn.motion", *(["--strict"] if strict else [])])
    assert result.exit_code == 1, result.output
    suite = ET.fromstring(result.stdout).find("testsuite")
    assert suite is not None and suite.get("tests") == "3"
    cases = {c.get("name"): c for c in suite.iter("testcase")}
    assert set(cases) == {"sub/bad.motion", "ok.motion", "warn.motion"}
    JUNIT_SCHEMA.validate(result.stdout)  # Jenkins xunit's junit-10.xsd: no testcase@file
    bad = cases["sub/bad.motion"].find("failure")
    assert bad is not None and bad.get("message") == ("1 error, 1 warning" if strict else "1 error")
    assert "sub/bad.motion:3:14: error MT113: HeadYaw = 'nan'" in (bad.text or "")
    assert cases["ok.motion"].find("failure") is None
    assert (cases["warn.motion"].find("failure") is not None) is strict
    assert suite.get("failures") == ("2" if strict else "1")


def test_statistics_count_each_code_most_frequent_first(here: Path) -> None:
    (here / "more.motion").write_bytes(
        b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,P,1rad\n00:00:040,Q,2rad\n00:00:080,R,nan\n"
    )
    result = runner.invoke(
        app, ["validate", "--robot", "none", "--statistics", "sub/bad.motion", "more.motion"]
    )
    assert result.exit_code == 1, result.output
    lines = result.stdout.splitlines()
    assert lines[1:] == [  # no grouped finding here: the two counts agree
        "findings  per pose  code   severity  title",
        "       3         3  MT203  warning   trailing characters after a number are ignored",
        "       2         2  MT113  error     value is nan or infinite",
        "checked 2 files: 2 errors, 3 warnings, 0 notes",
    ]
    refused = runner.invoke(app, ["validate", "--statistics", "-f", "sarif", "more.motion"])
    assert refused.exit_code == 2 and "--statistics: --format text or json" in refused.stderr


def test_ranks_counted_on_disk_past_a_files_held_keys_give_the_same_fingerprints(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A file with more distinct findings than are counted in memory goes on counting them in
    a temporary SQLite table: the same ranks, so the same fingerprints, in either order."""
    from motiontool.cli.reports.common import Fingerprints, Order
    from motiontool.motionfmt.diagnostics import Diagnostic, Severity

    rng = np.random.default_rng(5)
    found = [
        Diagnostic(
            f"MT{code}",
            Severity.WARNING if code == 203 else Severity.ERROR,
            path,
            line,
            1,
            f"message {rng.integers(0, 6)}",
        )
        for path in ("a.motion", "b.motion")
        for line in range(1, 60)
        for code in (203, 301)
    ]

    def prints(held: int, order: Order) -> list[str]:
        with monkeypatch.context() as m:
            m.setattr(Fingerprints, "HELD_KEYS", held)
            fingerprint = Fingerprints()
            if order is Order.severity:  # as a report by severity reads them
                return [
                    fingerprint(d, order) for d in sorted(found, key=lambda d: (d.path, d.severity))
                ]
            return [fingerprint(d, order) for d in found]

    for order in (Order.file, Order.severity):
        in_memory = prints(1 << 30, order)
        assert len(set(in_memory)) == len(found)  # ranks tell identical findings apart
        assert prints(2, order) == in_memory


def test_a_sarif_fix_of_more_edits_than_it_carries_is_counted_not_written(
    here: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A grouped limit finding over many poses has a fix of one clamp per pose: past
    MAX_FIX_EDITS the result carries no ``fixes`` but their number (``fixEdits``)."""
    from motiontool.cli.reports import sarif as sarif_report

    rows = "".join(f"00:00:{40 * k:03d},P{k},3\n" for k in range(20))
    (here / "sub" / "over.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n" + rows.encode())

    def result(most: int) -> dict[str, Any]:
        with monkeypatch.context() as m:
            m.setattr(sarif_report, "MAX_FIX_EDITS", most)
            args = [
                "validate",
                "sub/over.motion",
                "--robot",
                "nao",
                "--unsafe-fixes",
                "-f",
                "sarif",
            ]
            out = runner.invoke(app, args)
        assert out.exit_code == 1, out.output
        results = json.loads(out.stdout)["runs"][0]["results"]
        found: dict[str, Any] = next(r for r in results if r["ruleId"] == "MT302")
        return found

    carried = result(1000)
    assert len(carried["fixes"][0]["artifactChanges"][0]["replacements"]) == 20
    assert "fixEdits" not in carried["properties"]
    counted = result(19)
    assert "fixes" not in counted and counted["properties"]["fixEdits"] == 20
    assert counted["properties"]["count"] == 20


LINED = {  # findings whose message names another line
    "MT106": b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:100,P1,0\n00:00:040,P2,0\n",
    "MT201": b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,P1,0\n\n00:00:040,P2,0\n",
}


@pytest.mark.parametrize("code", sorted(LINED))
def test_a_finding_that_names_another_line_keeps_its_fingerprints_when_lines_come_above(
    here: Path, code: str
) -> None:
    """Its message names a line ("(line 3)"), which moves with the lines added above: the
    fingerprints hash the finding without it, and SARIF gives that line as a related
    location; the text report still names it."""
    path = here / "sub" / "lined.motion"

    def prints() -> tuple[str, str, dict[str, Any]]:
        args = ["--strict", str(path.relative_to(here))]  # MT201 is a warning: exit 1 too
        run = sarif(args)["runs"][0]  # type: ignore[index]
        (result,) = [r for r in run["results"] if r["ruleId"] == code]
        (issue,) = [i for i in gitlab(args) if i["check_name"] == code]
        return (
            result["partialFingerprints"]["motiontoolFinding/v1"],
            str(issue["fingerprint"]),
            result,
        )

    path.write_bytes(LINED[code])
    sarif_before, gitlab_before, result = prints()
    lines = LINED[code].split(b"\n")
    path.write_bytes(
        b"\n".join([lines[0], b"00:00:000,P0,0", *lines[1:]]).replace(
            b"00:00:000,P1", b"00:00:020,P1"
        )
    )
    sarif_after, gitlab_after, moved = prints()
    assert (sarif_after, gitlab_after) == (sarif_before, gitlab_before)
    # The other line is a related location of the result, where it is now.
    (related,) = result["relatedLocations"]
    (related_moved,) = moved["relatedLocations"]
    other = 2 if code == "MT106" else 4
    assert related["physicalLocation"]["region"]["startLine"] == other
    assert related_moved["physicalLocation"]["region"]["startLine"] == other + 1
    assert related["message"]["text"]
    text = runner.invoke(app, ["validate", "--robot", "none", str(path.relative_to(here))])
    assert f"(line {other + 1})" in text.stdout


def test_no_golden_finding_is_identified_by_a_line_number() -> None:
    """What fingerprints hash (:attr:`Diagnostic.identity`) names no line, in every golden
    invalid file: a line added above any of them leaves them the same findings."""
    import re

    from conftest import golden

    from motiontool.motionfmt import read_bytes

    names_a_line = re.compile(r"\blines? \d")
    found = [
        f"{path.name}: {d.code} {d.identity}"
        for path in golden("invalid")
        for d in read_bytes(path.read_bytes(), path.name).diagnostics
        if names_a_line.search(d.identity)
    ]
    assert not found, "\n".join(found)


@pytest.mark.parametrize(
    "urls",
    [
        [],
        ["Homepage, https://example.org/motiontool", "Rules, https://example.org/m/rules.md"],
    ],
)
def test_sarif_links_the_project_urls_of_the_installed_package(
    here: Path, monkeypatch: pytest.MonkeyPatch, urls: list[str]
) -> None:
    """The driver's ``informationUri`` is the package's ``Homepage`` project URL and each
    rule's ``helpUri`` its section of the ``Rules`` one (docs/rules.md): the one home of the
    addresses is pyproject.toml's ``[project.urls]``; without them, no link that goes nowhere."""
    from motiontool.cli.reports import sarif as sarif_module

    monkeypatch.setattr(sarif_module, "project_urls", lambda: dict(u.split(", ") for u in urls))
    doc = sarif(["sub/bad.motion"])
    jsonschema.validate(doc, json.loads((DATA / "sarif" / "sarif-schema-2.1.0.json").read_text()))
    run = doc["runs"][0]  # type: ignore[index]
    driver = run["tool"]["driver"]
    if not urls:
        assert "informationUri" not in driver and "helpUri" not in json.dumps(run)
        return
    assert driver["informationUri"] == "https://example.org/motiontool"
    for rule in driver["rules"]:
        assert rule["helpUri"] == f"https://example.org/m/rules.md#{rule['id'].lower()}"


def test_the_installed_project_urls_are_pyprojects() -> None:
    """What SARIF links (:func:`~motiontool.cli.reports.sarif.project_urls`, read from the
    installed package) is what pyproject.toml says: reinstall (pip install -e .) after
    changing ``[project.urls]``."""
    import tomllib

    from conftest import ROOT

    from motiontool.cli.reports.sarif import project_urls

    declared = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"].get("urls", {})
    assert project_urls() == declared, "reinstall the package: pip install -e ."
