"""``validate``'s selection of files and codes as teams adopt it, after ruff:
``force-exclude``, ``.gitignore`` and hidden folders in folder walks, ``--select`` /
``--extend-select`` / ``--ignore`` with prefixes, ``--exit-zero``, ``--quiet``,
``--stdin-filename`` and ``--statistics --format json``."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import jsonschema
import pytest
from typer.testing import CliRunner

from motiontool.cli import schemas
from motiontool.cli.app import app

runner = CliRunner()

# Nao: '0.1rad' (MT203, a warning, fixable), HeadYaw past its limit (MT302, an error).
NAO = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,P1,0,0.1rad\n00:00:400,P2,2.5,0\n"
WARN = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,P1,0,0.1rad\n00:00:400,P2,0.5,0\n"
GOOD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,P1,0,0.1\n00:00:400,P2,0.5,0\n"


def invoke(*args: str, input: bytes | None = None) -> tuple[int, str, str]:
    result = runner.invoke(app, list(args), input=input)
    return result.exit_code, result.stdout, result.stderr


def paths(out: str) -> list[str]:
    return [f["path"] for f in json.loads(out)["files"]]


def codes(out: str) -> list[str]:
    return [d["code"] for f in json.loads(out)["files"] for d in f["diagnostics"]]


@pytest.fixture
def repo(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    for folder in ("motions", "motions/generated", "motions/build", "motions/.cache"):
        (tmp_path / folder).mkdir()
    for name in (
        "motions/a.motion",
        "motions/generated/g.motion",
        "motions/build/b.motion",
        "motions/build/keep.motion",
        "motions/.cache/c.motion",
        "motions/scratch.motion",
    ):
        (tmp_path / name).write_bytes(NAO)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def git_repo(repo: Path) -> None:
    subprocess.run(["git", "init", "-q", str(repo)], check=True)
    (repo / ".gitignore").write_text("scratch.motion\nbuild/\n")
    (repo / "motions" / ".gitignore").write_text("!scratch.motion\n*.motion\n!a.motion\n")


# File selection ---------------------------------------------------------------------------


def test_force_exclude_applies_exclude_to_files_named_on_the_command_line(repo: Path) -> None:
    (repo / "motiontool.toml").write_text('exclude = ["generated"]\n')
    named = ["motions/a.motion", "motions/generated/g.motion"]
    code, out, _ = invoke("validate", "-f", "json", *named)
    assert paths(out) == named  # named: checked, as before (and as ruff does)
    code, out, _ = invoke("validate", "-f", "json", "--force-exclude", *named)
    assert paths(out) == ["motions/a.motion"]
    (repo / "motiontool.toml").write_text('exclude = ["generated"]\nforce-exclude = true\n')
    assert paths(invoke("validate", "-f", "json", *named)[1]) == ["motions/a.motion"]
    assert paths(invoke("validate", "-f", "json", "--no-force-exclude", *named)[1]) == named
    # Only excluded files named (pre-commit staging only those): nothing to check, exit 0.
    code, out, _ = invoke("validate", "motions/generated/g.motion")
    assert code == 0 and out.splitlines()[-1] == "checked 0 files: 0 errors, 0 warnings, 0 notes"


def test_exclude_names_a_folder_by_its_path_too(repo: Path) -> None:
    (repo / "motiontool.toml").write_text('exclude = ["motions/generated"]\n')
    assert "motions/generated/g.motion" not in paths(invoke("validate", "-f", "json", ".")[1])


def test_exclude_matches_only_below_the_configurations_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    project = tmp_path / "generated" / "project"  # a folder above it named as the glob
    (project / "motions").mkdir(parents=True)
    (project / "motions" / "a.motion").write_bytes(NAO)
    (project / "motiontool.toml").write_text('exclude = ["generated"]\nforce-exclude = true\n')
    monkeypatch.chdir(tmp_path)
    found = paths(invoke("validate", "-f", "json", "generated/project/motions")[1])
    assert found == ["generated/project/motions/a.motion"]
    named = "generated/project/motions/a.motion"
    assert paths(invoke("validate", "-f", "json", named)[1]) == [named]


def test_folder_walks_respect_gitignore_nested_and_negated(repo: Path) -> None:
    git_repo(repo)
    _code, out, _ = invoke("validate", "-f", "json", "--robot", "none", "motions")
    # build/ is ignored from the root (its keep.motion too: git cannot re-include a file whose
    # folder is ignored); motions/.gitignore ignores *.motion but a.motion; scratch.motion,
    # ignored at the root, is re-included there and then ignored again by '*.motion'; the
    # hidden folder is skipped.
    assert paths(out) == ["motions/a.motion"]
    _code, out, _ = invoke("validate", "-f", "json", "--no-respect-gitignore", "motions")
    assert sorted(paths(out)) == [
        "motions/.cache/c.motion",
        "motions/a.motion",
        "motions/build/b.motion",
        "motions/build/keep.motion",
        "motions/generated/g.motion",
        "motions/scratch.motion",
    ]
    # A file git tracks is not ignored (git's own rule), even where a pattern matches it.
    subprocess.run(["git", "add", "-f", "motions/build/b.motion"], check=True)
    assert paths(invoke("validate", "-f", "json", "motions")[1]) == [
        "motions/a.motion",
        "motions/build/b.motion",
    ]
    (repo / "motiontool.toml").write_text("respect-gitignore = false\n")
    assert len(paths(invoke("validate", "-f", "json", "motions")[1])) == 6
    # A file named on the command line is checked, ignored or not.
    assert paths(invoke("validate", "-f", "json", "motions/build/b.motion")[1]) == [
        "motions/build/b.motion"
    ]


def test_gitignore_counts_only_inside_a_repository_up_to_its_root(
    repo: Path, tmp_path: Path
) -> None:
    (repo / ".gitignore").write_text("*.motion\n")  # no .git: git reads no .gitignore
    assert len(paths(invoke("validate", "-f", "json", "motions")[1])) == 5  # hidden skipped
    subprocess.run(["git", "init", "-q", str(repo / "motions")], check=True)
    # The repository is motions/: the .gitignore above its root is not its own.
    assert len(paths(invoke("validate", "-f", "json", "motions")[1])) == 5
    (repo / "motions" / ".gitignore").write_text("generated/\n")
    assert "motions/generated/g.motion" not in paths(invoke("validate", "-f", "json", "motions")[1])


def test_what_a_search_leaves_out_is_neither_searched_nor_an_error(repo: Path) -> None:
    """A dangling link in an ignored or excluded folder, or one in a hidden folder, is no
    'cannot read' error: the search leaves those folders out (hidden ones are not even
    entered: a checkout's .git is never walked); outside them it still is one."""
    git_repo(repo)
    for folder in ("build", ".cache", "generated"):
        (repo / "motions" / folder / "gone.motion").symlink_to("nowhere.motion")
    (repo / "motions" / "build" / "loop.motion").symlink_to("loop.motion")  # to itself
    (repo / "motiontool.toml").write_text('exclude = ["motions/generated"]\n')
    code, out, err = invoke("validate", "-f", "json", "--robot", "none", "motions")
    assert (code, err) == (0, ""), err
    assert paths(out) == ["motions/a.motion"]
    code, _, err = invoke("validate", "--no-respect-gitignore", "--robot", "none", "motions")
    assert code == 2 and "cannot read 3 entries under 'motions'" in err, (code, err)
    assert "'motions/build/loop.motion': Too many levels of symbolic links" in err
    assert "'motions/build/gone.motion'" in err and "'motions/.cache/gone.motion'" in err
    (repo / "motions" / "sub").mkdir()  # a.motion: what motions/.gitignore keeps
    (repo / "motions" / "sub" / "a.motion").symlink_to("nowhere.motion")
    code, _, err = invoke("validate", "--robot", "none", "motions")
    assert code == 2 and "'motions/sub/a.motion': No such file" in err, err
    assert err.startswith("motiontool: error: cannot read 1 entry under 'motions'")


def test_a_hidden_folder_named_on_the_command_line_is_searched(repo: Path) -> None:
    assert paths(invoke("validate", "-f", "json", "motions/.cache")[1]) == [
        "motions/.cache/c.motion"
    ]


# The configuration and the codes ----------------------------------------------------------


def test_isolated_and_config_together_are_refused(repo: Path) -> None:
    (repo / "ci.toml").write_text('robot = "none"\n')
    code, out, err = invoke("validate", "--isolated", "--config", "ci.toml", "motions/a.motion")
    assert code == 2 and out == ""
    assert err == "motiontool: error: --isolated reads no configuration file: leave out --config\n"


def test_ignore_select_and_extend_select_take_prefixes_as_ruff(repo: Path) -> None:
    one = "motions/a.motion"
    assert codes(invoke("validate", "-f", "json", one)[1]) == ["MT203", "MT302"]
    assert codes(invoke("validate", "-f", "json", "--ignore", "MT2", one)[1]) == ["MT302"]
    assert codes(invoke("validate", "-f", "json", "--select", "MT3", one)[1]) == ["MT302"]
    # The more specific selector wins, whichever list it is in.
    args = ("--select", "MT2", "--ignore", "MT203")
    assert codes(invoke("validate", "-f", "json", *args, one)[1]) == []
    args = ("--select", "MT203", "--ignore", "MT2")
    assert codes(invoke("validate", "-f", "json", *args, one)[1]) == ["MT203"]
    (repo / "motiontool.toml").write_text('select = ["MT3"]\n')
    assert codes(invoke("validate", "-f", "json", one)[1]) == ["MT302"]
    assert codes(invoke("validate", "-f", "json", "--extend-select", "MT203", one)[1]) == [
        "MT203",
        "MT302",
    ]
    # --select replaces the configuration's selection (its ignores too).
    (repo / "motiontool.toml").write_text('ignore = ["MT203"]\n')
    assert codes(invoke("validate", "-f", "json", "--select", "MT2", one)[1]) == ["MT203"]
    (repo / "motiontool.toml").write_text('select = ["MT3"]\nextend-select = ["MT203"]\n')
    assert codes(invoke("validate", "-f", "json", one)[1]) == ["MT203", "MT302"]
    code, _, err = invoke("validate", "--select", "MT2O3", one)
    assert code == 2 and "unknown code 'MT2O3'; did you mean" in err


# Exit codes and output --------------------------------------------------------------------


@pytest.mark.needs("kinematics")
def test_exit_zero_and_quiet(repo: Path) -> None:
    one = "motions/a.motion"
    assert invoke("validate", one)[0] == 1
    code, out, _ = invoke("validate", "--exit-zero", one)
    assert code == 0 and "error MT302" in out
    code, out, err = invoke("validate", "-q", one)
    assert code == 1 and "error MT302" in out
    assert not out.startswith("robot:") and "checked 1 file" not in out
    (repo / "w.motion").write_bytes(WARN)
    code, out, err = invoke("validate", "--quiet", "--fix", "w.motion")
    assert (code, out, err) == (0, "", "")
    code, out, err = invoke("validate", "--quiet", "w.motion")
    assert (code, out, err) == (0, "", "")


def test_stdin_filename_names_standard_input_and_finds_its_settings(repo: Path) -> None:
    (repo / "motions" / "motiontool.toml").write_text('ignore = ["MT302"]\n')
    code, out, _ = invoke(
        "validate", "-f", "json", "--stdin-filename", "motions/x.motion", "-", input=NAO
    )
    assert paths(out) == ["motions/x.motion"] and codes(out) == ["MT203"]
    code, out, _ = invoke("validate", "--stdin-filename", "motions/x.motion", "-", input=NAO)
    assert out.splitlines()[1].startswith("motions/x.motion:2:19: warning MT203: [*] ")
    code, _, err = invoke("validate", "--stdin-filename", "x.motion", "a.motion")
    assert code == 2 and "--stdin-filename names standard input: give '-'" in err
    # Standard input is never left out (an editor replaces its text with what --fix prints).
    (repo / "motions" / "motiontool.toml").write_text('exclude = ["x.motion"]\n')
    args = ("--force-exclude", "--stdin-filename", "motions/x.motion", "-")
    assert paths(invoke("validate", "-f", "json", *args, input=NAO)[1]) == ["motions/x.motion"]


def test_diff_of_standard_input_names_it_as_stdin_filename_says(repo: Path) -> None:
    result = runner.invoke(
        app, ["validate", "--diff", "--stdin-filename", "motions/x.motion", "-"], input=WARN
    )
    assert result.exit_code == 1
    assert result.stdout.startswith("--- a/motions/x.motion\n+++ b/motions/x.motion\n")


def test_fix_of_standard_input_prints_the_fixed_text(repo: Path) -> None:
    result = runner.invoke(
        app, ["validate", "--fix", "--stdin-filename", "x.motion", "-"], input=WARN
    )
    assert result.exit_code == 0, result.output
    assert result.stdout_bytes == WARN.replace(b"0.1rad", b"0.1")
    assert "x.motion" not in result.stdout  # the report of what remains: on stderr
    assert "checked 1 file: 0 errors, 0 warnings" in result.stderr
    assert "motiontool: fixed 1 finding in 1 file (MT203)" in result.stderr
    result = runner.invoke(app, ["validate", "--fix", "-"], input=NAO)
    assert result.exit_code == 1 and result.stdout_bytes == NAO.replace(b"0.1rad", b"0.1")
    assert "<stdin>:3:14: error MT302" in result.stderr


@pytest.mark.needs("kinematics")
def test_statistics_as_json_conform_to_their_schema(repo: Path) -> None:
    code, out, _ = invoke("validate", "--statistics", "-f", "json", "motions/a.motion")
    doc = json.loads(out)
    schema = schemas.load("statistics")
    jsonschema.Draft202012Validator(schema, registry=schemas.registry()).validate(doc)
    assert code == 1 and doc["schema"] == "motiontool.statistics"
    assert [(s["code"], s["findings"], s["fixable"]) for s in doc["statistics"]] == [
        ("MT203", 1, 1),
        ("MT302", 1, 0),
    ]
    assert doc["summary"] == {"files": 1, "errors": 1, "warnings": 1, "notes": 0}
    code, _, err = invoke("validate", "--statistics", "-f", "sarif", "motions/a.motion")
    assert code == 2 and "--statistics: --format text or json" in err


def test_fix_leaves_the_codes_left_out_alone_as_ruff_fixes_only_selected_rules(
    repo: Path,
) -> None:
    (repo / "w.motion").write_bytes(WARN)
    code, _out, err = invoke("validate", "--fix", "--ignore", "MT2", "w.motion")
    assert (code, err) == (0, "motiontool: nothing to fix\n")
    assert (repo / "w.motion").read_bytes() == WARN
    (repo / "motiontool.toml").write_text('[per-file-ignores]\n"w.motion" = ["MT203"]\n')
    assert invoke("validate", "--fix", "w.motion")[2] == "motiontool: nothing to fix\n"
    assert invoke("validate", "--fix", "--isolated", "w.motion")[2] == (
        "motiontool: fixed 1 finding in 1 file (MT203)\n"
    )
