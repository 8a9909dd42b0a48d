"""The report formats (``REPORTS``), the built-in robots (``BUILTIN_ROBOTS``) and the commands
(``_COMMANDS``), each iterated here, so that docs/architecture.md's "To add a report format",
"To add a robot" and "To add a subcommand" recipes are complete: an entry that skips a step
fails here (the code and check recipes: tests/cli/test_registries.py)."""

from __future__ import annotations

import ast
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import jsonschema
import pytest
import xmlschema
from conftest import DATA, dev_module
from typer.testing import CliRunner

from motiontool.cli import schemas
from motiontool.cli.app import _COMMANDS, app
from motiontool.cli.reports import REPORTS
from motiontool.kinematics.builtin_robots import (
    BUILTIN_ROBOTS,
    BuiltinRobot,
    builtin_robots,
    models_dir,
)
from motiontool.kinematics.limbs import limb_of
from motiontool.kinematics.robots import load_robot

ROOT = Path(__file__).resolve().parents[2]
runner = CliRunner()
WRITERS: list[list[str]] = dev_module("writers").WRITERS
"""dev/writers.py: every output option, which tests/cli/test_special_outputs.py proves."""

BAD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,P1,0,2rad\n00:00:080,P2,nan,0\n"
"""Webots accepts it; 'nan' is an error (MT1xx), '2rad' a warning."""

CHECKED_BY = {
    "text": "tests/data/invalid",  # its goldens: each .expected's first line is in the text
    "json": "cli/schemas/validate.schema.json",
    "sarif": "tests/data/sarif/sarif-schema-2.1.0.json",
    "github": None,  # workflow commands: a line each, no schema exists
    "gitlab": None,  # GitLab publishes no schema of Code Quality reports to vendor
    "junit": "tests/data/junit/junit-10.xsd",
}
"""What a report format is read against: its schema or golden files, or None where its kind has
neither. A new format is placed here, or this file fails."""


def _page(name: str) -> str:
    return (ROOT / name).read_text(encoding="utf-8")


def _block(text: str, fence: str, after: str) -> str:
    """The first fenced ``fence`` block of ``text`` after the line ``after``."""
    start = text.index(f"```{fence}\n", text.index(after)) + len(fence) + 4
    return text[start : text.index("```", start)]


def _validate(here: Path, *args: str) -> tuple[int, str, str]:
    (here / "bad.motion").write_bytes(BAD)
    result = runner.invoke(app, ["validate", "--robot", "none", *args])
    return result.exit_code, result.stdout, result.stderr


@pytest.mark.parametrize("fmt", list(REPORTS))
def test_every_report_format_has_its_writer_choice_docs_and_synopsis(fmt: str) -> None:
    entry = REPORTS[fmt]
    module = sys.modules[entry.writer.__module__].__file__
    assert module is not None and Path(module).parent == ROOT / "cli" / "reports", fmt
    help_text = " ".join(runner.invoke(app, ["validate", "--help"]).stdout.split())
    assert f"{fmt}: {entry.help}" in help_text
    formats = _page("docs/commands.md")
    formats = " ".join(formats[formats.index("\nFormats: ") :].split("\n\n")[0].split())
    assert f"`{fmt}` (" in formats, "docs/commands.md's Formats paragraph names every format"
    synopsis = _block(_page("README.md"), "text", "## Commands")
    assert f"[-f {'|'.join(REPORTS)}]" in synopsis


@pytest.mark.parametrize("fmt", list(REPORTS))
def test_every_report_format_is_read_against_its_schema_or_goldens(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, fmt: str
) -> None:
    assert set(CHECKED_BY) == set(REPORTS)
    monkeypatch.chdir(tmp_path)
    code, out, _ = _validate(tmp_path, "-f", fmt, "bad.motion")
    assert code == 1 and "MT" in out
    home = CHECKED_BY[fmt]
    if home is None:
        return
    assert (ROOT / home).exists(), home
    if home.endswith(".xsd"):
        xmlschema.XMLSchema(str(ROOT / home)).validate(out)
    elif home.startswith("cli/schemas/"):
        schema = schemas.load(Path(home).name.removesuffix(".schema.json"))
        jsonschema.validate(json.loads(out), schema, registry=schemas.registry())
    elif home.endswith(".json"):
        jsonschema.validate(json.loads(out), json.loads((ROOT / home).read_text()))
    else:  # golden files of the text format
        golden = DATA / "invalid" / "bom.expected"
        monkeypatch.chdir(golden.parent)
        code, out, _ = _validate(tmp_path, "-f", fmt, "bom.motion")
        assert code == 1 and golden.read_text(encoding="utf-8").splitlines()[0] in out


@pytest.mark.parametrize("fmt", list(REPORTS))
def test_every_report_format_writes_to_o_what_it_prints(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, fmt: str
) -> None:
    """``-o`` goes through one writer whatever the format, so dev/writers.py lists ``validate
    -o`` twice (text and sarif), not once a format: here each format's file is its stdout."""
    monkeypatch.chdir(tmp_path)
    _code, printed, _ = _validate(tmp_path, "-f", fmt, "bad.motion")
    code, out, err = _validate(tmp_path, "-f", fmt, "-o", "report.out", "bad.motion")
    assert (code, out) == (1, "")
    assert (tmp_path / "report.out").read_text(encoding="utf-8") == printed
    assert err.startswith(f"motiontool: wrote report.out ({REPORTS[fmt].label} report of 1 file")
    assert [line[:5] for line in WRITERS if line[0] == "validate"] == [
        ["validate", "in.motion", "-o", "OUT"],
        ["validate", "in.motion", "-f", "sarif", "-o"],
    ]


@pytest.mark.parametrize("robot", BUILTIN_ROBOTS, ids=lambda r: r.name)
def test_every_builtin_robot_has_its_model_listing_limbs_and_docs(robot: BuiltinRobot) -> None:
    for file in (robot.model, robot.overrides):
        if file is not None:
            assert (models_dir() / file).is_file(), file
            assert f"`kinematics/models/{file}`" in _page("docs/robots.md"), file
    spec = load_robot(robot.name)
    assert spec.joints and spec.default_timestep_ms > 0
    listing = runner.invoke(app, ["robots"]).stdout
    step = f"{spec.default_timestep_ms} ms step: {robot.description}"
    assert any(line.split()[0] == robot.name and step in line for line in listing.splitlines())
    shown = runner.invoke(app, ["robots", "show", robot.name])
    assert shown.exit_code == 0
    assert re.search(rf"^time step +{spec.default_timestep_ms} ms ", shown.stdout, re.M)
    for joint in spec.joint_names:
        assert re.search(rf"^{re.escape(joint)}\s", shown.stdout, re.M), joint
        assert limb_of(joint, fallback="") != "", f"limb_of groups no limb for {joint}"
    doc = json.loads(runner.invoke(app, ["robots", "show", robot.name, "-f", "json"]).stdout)
    jsonschema.validate(doc, schemas.load("robot"), registry=schemas.registry())
    assert f"`{robot.name}`" in _page("docs/robots.md")


def test_the_readme_names_every_builtin_robot_where_it_lists_robot() -> None:
    examples = _block(_page("README.md"), "sh", "## Commands")
    said = " ".join(line.split("#", 1)[1] for line in examples.splitlines() if "#" in line)
    said = " ".join(said.split())
    assert f"robot: auto (default), {', '.join(builtin_robots())}, erd:<name>" in said


def _help(name: str) -> str:
    args = [name, "show", "--help"] if name == "robots" else [name, "--help"]
    result = runner.invoke(app, args, terminal_width=400)
    assert result.exit_code == 0, (name, result.output)
    return " ".join(result.stdout.split())


@pytest.mark.parametrize("name", list(_COMMANDS))
def test_every_command_has_its_module_help_exit_codes_and_schema(name: str) -> None:
    module, function, _summary = _COMMANDS[name]
    source = ROOT / "cli" / f"{module}.py"
    defined = {
        node.name
        for node in ast.parse(source.read_text(encoding="utf-8")).body
        if isinstance(node, ast.FunctionDef)
    }
    assert function in defined, (name, module, function)
    text = _help(name)
    code = source.read_text(encoding="utf-8")
    if "exit_codes.FINDINGS" in code or "strict_exit" in code:  # it may exit 1: --help says when
        assert re.search(r"\b([Ee]xits?|Exit code)\b[^.]*\b1\b", text), name
    if re.search(r"\|json>|--json", text):  # it writes JSON: its report has a schema
        assert {"robots": "robot"}.get(name, name) in schemas.NAMES, name
    paragraph = _page("docs/commands.md").split("\nExit codes: ", 1)[1].split("\n\n")[0]
    if "exit_codes.FINDINGS" in code or "strict_exit" in code:
        assert re.search(rf"\b{name}\b", paragraph.split("`2`")[0]), f"exit 1 of {name}"


def test_the_synopsis_and_completion_list_every_command() -> None:
    synopsis = _block(_page("README.md"), "text", "## Commands")
    named = [
        word
        for line in synopsis.splitlines()
        if line.startswith("motiontool ")
        for word in line.split()[1].split("|")
    ]
    assert sorted(named) == sorted(_COMMANDS), "README's synopsis: a line per command"
    assert {line[0] for line in WRITERS} <= set(_COMMANDS)
    script = shutil.which("motiontool", path=str(Path(sys.executable).parent))
    assert script is not None
    env = dict(os.environ, _MOTIONTOOL_COMPLETE="complete_bash", COMP_WORDS="motiontool ")
    proc = subprocess.run(
        [script], env={**env, "COMP_CWORD": "1"}, capture_output=True, text=True, check=False
    )
    assert (proc.returncode, proc.stdout.split()) == (0, list(_COMMANDS))


@pytest.mark.parametrize("name", list(_COMMANDS))
def test_every_command_has_a_docs_heading_the_readme_links(name: str) -> None:
    """A heading of a page of docs/ names the command in backticks, and that page's row of the
    README's documentation table names it too: a reader finds every command from the README."""
    table = _page("README.md").split("## Documentation", 1)[1]
    pages = [
        page
        for page in sorted((ROOT / "docs").glob("*.md"))
        if re.search(
            rf"^#+ .*`(motiontool )?{name}\b[^`]*`", page.read_text(encoding="utf-8"), re.M
        )
    ]
    assert pages, f"no page of docs/ has a heading naming `{name}`"
    rows = [line for line in table.splitlines() if any(f"(docs/{p.name})" in line for p in pages)]
    assert any(re.search(rf"`(motiontool )?{name}\b", row) for row in rows), (name, pages)
