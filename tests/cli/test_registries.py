"""One home per code and per check: the code records (``CODES`` with their ``Rule``) and the
check registry (``CHECK_REGISTRY``), and everything read from them. Each test iterates a
registry, so that docs/architecture.md's "To add a code" and "To add a check" recipes are
complete: a record left out of a step fails here."""

from __future__ import annotations

import ast
import json
import re
from pathlib import Path
from typing import Any

import pytest
from conftest import dev_module
from typer.testing import CliRunner

from motiontool.cli import schemas
from motiontool.cli.app import app
from motiontool.cli.config import KEYS
from motiontool.cli.lint_run import _FIXED_BY_CHECK
from motiontool.cli.rule import checks_table, codes_table
from motiontool.cli.rules import RULES
from motiontool.errors import MotionToolError
from motiontool.kinematics.checks import (
    CHECKS,
    DEFAULT_CHECKS,
    CheckUnavailableError,
    robot_checks,
)
from motiontool.kinematics.checks.registry import (
    ALWAYS,
    CHECK_REGISTRY,
    NOTE_CODES,
    check_of_code,
)
from motiontool.kinematics.robots import pick_robot
from motiontool.motionfmt import diagnostics
from motiontool.motionfmt.diagnostics import CODES, FixKind
from motiontool.motionfmt.fixes import ROBOT_CODES, SAFE_CODES, UNSAFE_CODES
from motiontool.motionfmt.validate import check_codes

ROOT = Path(__file__).resolve().parents[2]
runner = CliRunner()

RULE_MODULES = {"MT1": "rules_syntax.py", "MT2": "rules_traps.py", "MT3": "rules_robot.py"}
RULE_MODULES["MT9"] = RULE_MODULES["MT3"]


def _rule_codes(module: str) -> list[str]:
    """The codes of the ``Rule(...)`` records written in ``cli/<module>``."""
    tree = ast.parse((ROOT / "cli" / module).read_text(encoding="utf-8"))
    return [
        node.args[0].value
        for node in ast.walk(tree)
        if isinstance(node, ast.Call)
        and getattr(node.func, "id", None) == "Rule"
        and isinstance(node.args[0], ast.Constant)
    ]


def test_every_code_has_one_rule_in_the_module_of_its_range() -> None:
    written = [c for module in sorted(set(RULE_MODULES.values())) for c in _rule_codes(module)]
    assert sorted(written) == sorted(CODES), "a code without a Rule, or with two"
    for code in CODES:
        assert code in _rule_codes(RULE_MODULES[code[:3]]), code


def test_every_code_has_a_row_in_the_codes_table_and_the_docs_are_generated() -> None:
    page = (ROOT / "docs" / "commands.md").read_text(encoding="utf-8")
    stale = "docs/commands.md is stale: run python dev/rules_doc.py"
    assert codes_table() in page, stale
    assert checks_table() in page, stale
    assert RULES[next(iter(CODES))].row is not None
    table = codes_table()
    for code, entry in RULES.items():
        if entry.row is not None:
            assert f"| {code}" in table and entry.row in table
        else:  # it shares the row of the code before it: a range or a pair
            assert code in table or re.search(r"MT\d+–MT\d+ \|", table)


def test_every_robot_code_is_reported_by_exactly_one_check() -> None:
    entries = (*CHECK_REGISTRY, *ALWAYS)
    for code in CODES:
        reporting = [c.name for c in entries if code in c.codes]
        if code.startswith("MT3"):
            assert len(reporting) == 1, (code, reporting)
            assert check_of_code(code) is not None
        else:
            assert reporting == [], (code, reporting)
    for entry in entries:
        assert entry.codes and set(entry.codes) <= set(CODES), entry.name
    assert set(NOTE_CODES) == {c for c in CODES if c.startswith("MT9")}


def test_every_fix_kind_has_its_fix_and_every_robot_fix_its_check() -> None:
    kinds = {code: info.fix for code, info in CODES.items() if info.fix is not None}
    assert {c for c, k in kinds.items() if k is FixKind.SAFE} == SAFE_CODES
    assert {c for c, k in kinds.items() if k is FixKind.UNSAFE} == UNSAFE_CODES
    assert {c for c, k in kinds.items() if k is FixKind.ROBOT} == ROBOT_CODES
    assert set(_FIXED_BY_CHECK) == ROBOT_CODES  # each robot fix runs with the check finding it
    for code in ROBOT_CODES:
        entry = check_of_code(code)
        assert entry is not None and _FIXED_BY_CHECK[code] == entry.name
    for code in kinds:
        assert RULES[code].fixed is not None, f"{code} is fixed: its Rule shows the fixed file"
        assert RULES[code].autofix == ("safe" if kinds[code] is FixKind.SAFE else "unsafe")


def test_checks_and_defaults_are_the_registry_in_order() -> None:
    assert tuple(c.name for c in CHECK_REGISTRY) == CHECKS
    assert tuple(c.name for c in CHECK_REGISTRY if c.default) == DEFAULT_CHECKS
    assert len(set(CHECKS)) == len(CHECKS)
    spec = pick_robot("nao")
    made = robot_checks(spec, CHECKS)
    assert [type(c) for c in made] == [c.kind for c in (*ALWAYS, *CHECK_REGISTRY)]


def _enums(node: object, key: str | None = None) -> list[tuple[str | None, list[object]]]:
    """Every ``enum`` of a JSON Schema, with the property it is under."""
    found: list[tuple[str | None, list[object]]] = []
    if isinstance(node, dict):
        for k, v in node.items():
            if k == "enum" and isinstance(v, list):
                found.append((key, v))
            else:
                found += _enums(v, k if k not in ("items", "properties") else key)
    elif isinstance(node, list):
        for v in node:
            found += _enums(v, key)
    return found


def test_the_schemas_check_enums_are_the_registry() -> None:
    checks = [name for name in CHECKS]
    config = [v for k, v in _enums(schemas.load("config")) if k == "checks"]
    assert config == [[*checks, "all"]]
    validate = [v for k, v in _enums(schemas.load("validate")) if k in ("checks", "check")]
    assert validate == [checks, checks]
    described = json.dumps(schemas.load("config"))
    assert f"default {', '.join(DEFAULT_CHECKS)}." in described
    for name in ("config", "validate"):  # no other enum names a check
        others = [v for k, v in _enums(schemas.load(name)) if k not in ("checks", "check")]
        assert not any(set(v) & set(CHECKS) for v in others), name


def _rules_doc() -> Any:
    return dev_module("rules_doc")


def test_the_schemas_check_enums_are_written_from_the_registry() -> None:
    rules_doc = _rules_doc()
    for name in rules_doc.CHECK_SCHEMAS:
        committed = (ROOT / "cli" / "schemas" / f"{name}.schema.json").read_text("utf-8")
        assert committed == rules_doc.schema_text(name), f"{name}: run python dev/rules_doc.py"
    stale = {"properties": {"checks": {"items": {"enum": ["limits"]}, "description": "default x."}}}
    fresh = rules_doc._with_checks(stale, "config")["properties"]["checks"]
    assert fresh["items"]["enum"] == [*CHECKS, "all"]
    assert fresh["description"] == f"default {', '.join(DEFAULT_CHECKS)}."


def test_checks_help_and_messages_name_every_check() -> None:
    text = runner.invoke(app, ["validate", "--help"], terminal_width=400).stdout
    flat = " ".join(text.split())
    assert f"comma-separated: {', '.join(CHECKS)} (or all)" in flat
    assert f"Default: {','.join(DEFAULT_CHECKS)}," in flat
    with pytest.raises(MotionToolError, match="choose from " + ", ".join(CHECKS) + " or all"):
        robot_checks(pick_robot("nao"), ["limitz"])
    listed = ", ".join(f'"{name}"' for name in CHECKS)
    assert KEYS["checks"][1] == f"a list of checks ({listed})"  # the configuration's message


def test_a_check_that_needs_feet_is_refused_for_a_robot_without() -> None:
    footed = [c.name for c in CHECK_REGISTRY if c.needs_feet]
    assert footed == ["balance"]
    for name in footed:
        with pytest.raises(CheckUnavailableError, match=f"the {name} check needs a humanoid"):
            robot_checks(pick_robot("ur5e"), [name])


@pytest.mark.parametrize("code", ["MT399", "MT1000", "302", "MT3"])
def test_an_unknown_code_is_refused_with_the_closest(code: str) -> None:
    with pytest.raises(MotionToolError, match="unknown diagnostic code"):
        check_codes([code])
    assert check_codes([" mt302 "]) == {"MT302"}


def test_ignore_of_an_unknown_code_is_one_usage_line(tmp_path: Path) -> None:
    motion = tmp_path / "a.motion"
    motion.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,P1,0\n")
    result = runner.invoke(app, ["validate", "--isolated", "--ignore", "MT399", str(motion)])
    assert result.exit_code == 2
    assert result.stderr == (
        "motiontool: error: --ignore: unknown code 'MT399'; did you mean 'MT309'?\n"
    )


def test_library_modules_name_the_fixed_codes_once() -> None:
    """A code that library modules compare findings with (every fixed one, and those the
    fixes and the reader test for) is a named constant of motionfmt/diagnostics.py: its
    string is written there alone."""
    named = {v for k, v in vars(diagnostics).items() if isinstance(v, str) and v in CODES}
    assert named >= SAFE_CODES | UNSAFE_CODES | ROBOT_CODES
    for code in sorted(named):
        spelt = [
            str(path.relative_to(ROOT))
            for package in ("motionfmt", "kinematics", "sim")
            for path in (ROOT / package).rglob("*.py")
            if f'"{code}"' in path.read_text(encoding="utf-8")
        ]
        assert spelt == ["motionfmt/diagnostics.py"], (code, spelt)


def test_the_recipes_name_every_home_the_tests_iterate() -> None:
    page = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    code = page[page.index("- **a code**") : page.index("- **a check**")]
    check = page[page.index("- **a check**") : page.index("- **a robot**")]
    for home in (
        "motionfmt/diagnostics.py",
        *(f"cli/{m}" for m in sorted(set(RULE_MODULES.values()))),
        "kinematics/checks/registry.py",
        "motionfmt/fixes.py",
        "dev/rules_doc.py",
        "docs/commands.md",
        "tests/cli/test_registries.py",
    ):
        assert home in code, home
        assert (ROOT / home).exists(), home
    for home in (
        "kinematics/checks/registry.py",
        "cli/schemas/config.schema.json",
        "cli/schemas/validate.schema.json",
        "dev/rules_doc.py",
        "tests/cli/test_registries.py",
    ):
        assert home in check, home
        assert (ROOT / home).exists(), home


RECIPES = {
    "- **a robot**": (
        "kinematics/models/",
        "kinematics/builtin_robots.py",
        "kinematics/limbs.py",
        "docs/robots.md",
        "README.md",
        "cli/schemas/robot.schema.json",
        "tests/kinematics/test_models.py",
        "tests/cli/test_recipes.py",
    ),
    "- **a subcommand**": (
        "cli/app.py",
        "README.md",
        "docs/",
        "docs/commands.md",
        "cli/schemas/",
        "dev/writers.py",
        "tests/cli/test_special_outputs.py",
        "tests/cli/test_recipes.py",
    ),
    "- **a report format of `validate`**": (
        "cli/reports/",
        "cli/reports/__init__.py",
        "dev/writers.py",
        "README.md",
        "docs/commands.md",
        "cli/schemas/validate.schema.json",
        "tests/data/sarif/",
        "tests/data/junit/",
        "tests/data/invalid/",
        "tests/cli/test_recipes.py",
        "tests/cli/test_report_formats.py",
    ),
}
"""The homes each recipe names: what tests/cli/test_recipes.py reads or iterates for it."""

ITERATED = {
    "- **a robot**": "BUILTIN_ROBOTS",
    "- **a subcommand**": "_COMMANDS",
    "- **a report format of `validate`**": "REPORTS",
}
"""The registry tests/cli/test_recipes.py iterates for each recipe."""


@pytest.mark.parametrize("recipe", list(RECIPES))
def test_the_robot_subcommand_and_format_recipes_name_their_homes(recipe: str) -> None:
    page = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    start = page.index(recipe)
    text = page[start : page.index("\n- **", start + 1)]
    for home in RECIPES[recipe]:
        assert home in text, (recipe, home)
        assert (ROOT / home).exists(), home
    assert "Not checked mechanically" in text or "not checked" in text, recipe
    iterated = f"`tests/cli/test_recipes.py` iterates `{ITERATED[recipe]}`"
    assert iterated in " ".join(text.split()), recipe
