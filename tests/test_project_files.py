"""The project's own files beside the code: the changelog and the pre-commit configuration for
developing motiontool (run for real, offline, with the venv's ruff)."""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
from conftest import ROOT
from pre_commit.clientlib import load_config

DEV_CONFIG = ROOT / ".pre-commit-config.yaml"


def test_the_changelog_keeps_a_changelog_and_names_the_version() -> None:
    text = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    version = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    headings = re.findall(r"^## \[([^\]]+)\]", text, flags=re.MULTILINE)
    assert headings[0] == "Unreleased" and version in headings, headings
    assert re.search(rf"^## \[{re.escape(version)}\] - \d{{4}}-\d\d-\d\d$", text, re.MULTILINE)
    sections = set(re.findall(r"^### (\w+)$", text, flags=re.MULTILINE))
    assert sections <= {"Added", "Changed", "Deprecated", "Removed", "Fixed", "Security"}


def test_the_dev_pre_commit_config_is_valid_and_local() -> None:
    config = load_config(str(DEV_CONFIG))
    (repo,) = config["repos"]
    assert repo["repo"] == "local"  # no network: the venv's tools
    assert [h["id"] for h in repo["hooks"]] == ["ruff", "ruff-format"]


def _git(repo: Path, *args: str) -> None:
    env = {**os.environ, "GIT_CONFIG_GLOBAL": os.devnull, "GIT_CONFIG_NOSYSTEM": "1"}
    subprocess.run(["git", *args], cwd=repo, env=env, check=True, capture_output=True)


@pytest.mark.parametrize(
    ("source", "hook"),
    [("import os\n", "ruff"), ("x = [1,2]\n", "ruff-format")],
    ids=["unused-import", "unformatted"],
)
def test_the_dev_hooks_fail_a_bad_file(tmp_path: Path, source: str, hook: str) -> None:
    venv = Path(sys.executable).parent.parent
    (tmp_path / ".venv").symlink_to(venv)
    (tmp_path / ".gitignore").write_text(".venv\n")
    (tmp_path / ".pre-commit-config.yaml").write_text(DEV_CONFIG.read_text())
    (tmp_path / "pyproject.toml").write_text((ROOT / "pyproject.toml").read_text())
    (tmp_path / "good.py").write_text('"""Fine."""\n\nX = [1, 2]\n')
    (tmp_path / "bad.py").write_text(source)
    _git(tmp_path, "init", "-q")
    _git(tmp_path, "add", ".")
    env = {**os.environ, "PRE_COMMIT_HOME": str(tmp_path / ".cache")}
    run = [sys.executable, "-m", "pre_commit", "run", "--color", "never", hook, "--files"]
    good = subprocess.run([*run, "good.py"], cwd=tmp_path, env=env, capture_output=True)
    assert good.returncode == 0, good.stdout.decode()
    bad = subprocess.run([*run, "bad.py"], cwd=tmp_path, env=env, capture_output=True)
    assert bad.returncode == 1, bad.stdout.decode()
