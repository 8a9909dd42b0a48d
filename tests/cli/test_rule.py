"""``motiontool rule``: every code explained (cli/rules.py), and every explanation's
example checked by ``validate`` itself, so that the docs cannot lie."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import jsonschema
import pytest
from typer.testing import CliRunner

from motiontool.cli import schemas
from motiontool.cli.app import app
from motiontool.cli.rules import RULES, Example
from motiontool.kinematics.checks.registry import check_of_code
from motiontool.motionfmt.diagnostics import CODES
from motiontool.motionfmt.fixes import ROBOT_CODES, SAFE_CODES, UNSAFE_CODES

runner = CliRunner()


def reported(example: Example, data: bytes, folder: Path, monkeypatch: pytest.MonkeyPatch):
    """The codes ``validate`` reports on ``data`` written as ``example``'s file (its siblings
    beside it, its missing modules hidden), findings and the run's notes alike."""
    monkeypatch.chdir(folder)
    for name, sibling in example.siblings:
        (folder / name).write_bytes(sibling)
    (folder / example.name).write_bytes(data)
    for module in example.missing:
        monkeypatch.setitem(sys.modules, module, None)  # 'import pinocchio' fails
    result = runner.invoke(
        app, ["validate", "--isolated", "-f", "json", *example.args, example.name]
    )
    assert result.exit_code in (0, 1), result.output
    doc = json.loads(result.stdout)
    found = {d["code"] for f in doc["files"] for d in f["diagnostics"]}
    return found | {d["code"] for d in doc["notes"]}


def test_every_code_has_an_explanation_and_nothing_else_does() -> None:
    assert list(RULES) == list(CODES)
    for code, entry in RULES.items():
        assert entry.code == code and entry.webots and entry.fix


def _needs_its_check_extra(code: str) -> object:
    """``code``, marked ``needs`` the extra of the check that reports it (if any)."""
    check = check_of_code(code)
    extras = [check.extra] if check is not None and check.extra is not None else []
    return pytest.param(code, marks=pytest.mark.needs(*extras))


@pytest.mark.parametrize("code", [_needs_its_check_extra(code) for code in CODES])
def test_the_example_produces_its_code_and_the_fixed_example_does_not(
    code: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    entry = RULES[code]
    (tmp_path / "example").mkdir()
    assert code in reported(entry.example, entry.example.data, tmp_path / "example", monkeypatch)
    if entry.fixed is not None:
        (tmp_path / "fixed").mkdir()
        assert code not in reported(entry.example, entry.fixed, tmp_path / "fixed", monkeypatch)


def test_rule_explains_a_code_its_example_its_fix_and_whether_fix_fixes_it() -> None:
    result = runner.invoke(app, ["rule", "mt303"])
    assert result.exit_code == 0, result.output
    out = result.stdout
    assert out.startswith(
        "MT303  warning  segment faster than the joint's maxVelocity: the motor falls behind\n"
    )
    assert "Webots: The motor's speed is capped at maxVelocity" in out
    assert (
        "Example (motiontool validate --robot nao --checks limits,velocity example.motion):\n"
        "  #WEBOTS_MOTION,V1.0,RShoulderRoll\n  00:00:000,P1,0\n  00:00:100,P2,-1.2\n"
    ) in out
    assert (
        "Fixed:\n  #WEBOTS_MOTION,V1.0,RShoulderRoll\n  00:00:000,P1,0\n  00:00:200,P2,-1.2\n"
        in out
    )
    assert "validate --fix: only with --unsafe-fixes" in out


@pytest.mark.parametrize(
    ("code", "says"),
    [
        ("MT203", "validate --fix: yes, a safe fix (Webots then sends exactly the same commands)"),
        ("MT201", "validate --fix: only with --unsafe-fixes (it changes what the robot does)"),
    ],
)
def test_rule_says_which_fix_validate_applies(code: str, says: str) -> None:
    assert says in runner.invoke(app, ["rule", code]).stdout


def test_examples_with_bytes_that_do_not_print_are_escaped_and_long_lines_cut() -> None:
    nul = runner.invoke(app, ["rule", "MT114"]).stdout
    assert "  00:00:500,P2,0.5\\x00 head up\n" in nul
    long = runner.invoke(app, ["rule", "MT111"]).stdout
    assert "... (4,113 bytes)" in long and max(len(line) for line in long.splitlines()) < 120


def test_rule_alone_lists_every_code_as_codes_does() -> None:
    listed = runner.invoke(app, ["rule"])
    assert listed.exit_code == 0
    assert listed.stdout == runner.invoke(app, ["codes"]).stdout
    assert len(listed.stdout.splitlines()) == len(CODES)


def test_an_unknown_code_is_one_error_line_with_a_did_you_mean() -> None:
    result = runner.invoke(app, ["rule", "MT3033"])
    assert result.exit_code == 2
    assert result.stderr == "motiontool: error: unknown code 'MT3033'; did you mean 'MT303'?\n"


def test_json_is_the_same_explanation_and_follows_its_schema() -> None:
    one = json.loads(runner.invoke(app, ["rule", "MT205", "--format", "json"]).stdout)
    jsonschema.validate(one, schemas.load("rule"))
    assert one["rules"][0]["code"] == "MT205" and one["rules"][0]["autofix"] == "safe"
    assert one["rules"][0]["example"]["file"].startswith("#WEBOTS_MOTION,V1.0,HeadYaw,HeadYaw")
    every = json.loads(runner.invoke(app, ["rule", "--format", "json"]).stdout)
    jsonschema.validate(every, schemas.load("rule"))
    assert [r["code"] for r in every["rules"]] == list(CODES)
    autofix = {r["code"]: r["autofix"] for r in every["rules"]}
    assert {c for c, a in autofix.items() if a == "safe"} == SAFE_CODES
    assert {c for c, a in autofix.items() if a == "unsafe"} == UNSAFE_CODES | ROBOT_CODES
    latin1 = json.loads(runner.invoke(app, ["rule", "MT208", "-f", "json"]).stdout)
    assert latin1["rules"][0]["example"]["file"].endswith("00:00:000,Pos\\xe9,0\n")
    assert latin1["escaped_bytes"] == 1  # as every JSON report writes bytes that are not UTF-8


def test_sarif_rules_carry_the_same_explanations(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,P1,2rad\n")
    result = runner.invoke(app, ["validate", "--robot", "none", "-f", "sarif", "a.motion"])
    rules = json.loads(result.stdout)["runs"][0]["tool"]["driver"]["rules"]
    assert {r["id"] for r in rules} == set(CODES)
    for r in rules:
        explained = RULES[r["id"]]
        assert explained.webots in r["help"]["text"] and explained.fix in r["help"]["markdown"]
        assert f"motiontool rule {r['id']}" in r["help"]["text"]


def test_docs_rules_md_is_what_the_records_say() -> None:
    """docs/rules.md, where SARIF's ``helpUri`` points (a section a code: ``#mt106``), is made
    from the same records as ``motiontool rule CODE``."""
    from conftest import ROOT

    from motiontool.cli.rule import rules_markdown

    doc = (ROOT / "docs" / "rules.md").read_text(encoding="utf-8")
    assert doc == rules_markdown(), "docs/rules.md is stale: run python dev/rules_doc.py"
    for code in CODES:
        assert f"\n## {code}\n" in doc  # GitHub's anchor of that heading: #mt106
        assert runner.invoke(app, ["rule", code]).stdout in doc
