"""docs/ci.md and .pre-commit-hooks.yaml: the examples are valid for the tools that read them
(GitHub's workflow schema, pre-commit's own validator), offline."""

from __future__ import annotations

import json
import re
import tomllib
from pathlib import Path
from typing import Any

import jsonschema
import pytest
import yaml
from conftest import DATA, ROOT
from pre_commit.clientlib import InvalidManifestError, load_config, load_manifest

CI_DOC = ROOT / "docs" / "ci.md"
WORKFLOW_SCHEMA = json.loads((DATA / "ci" / "github-workflow.json").read_text())


class Yaml12Loader(yaml.SafeLoader):
    """YAML 1.2 booleans (only true / false), as GitHub reads workflows: PyYAML's YAML 1.1
    would read the key ``on:`` as True."""


Yaml12Loader.yaml_implicit_resolvers = {
    first: [(tag, regexp) for tag, regexp in resolvers if tag != "tag:yaml.org,2002:bool"]
    for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()
}
Yaml12Loader.add_implicit_resolver(
    "tag:yaml.org,2002:bool", re.compile(r"^(?:true|false)$"), list("tf")
)


def load_yaml(text: str) -> Any:
    return yaml.load(text, Loader=Yaml12Loader)  # a SafeLoader: no arbitrary objects


def yaml_blocks() -> list[str]:
    return re.findall(r"^```yaml\n(.*?)^```", CI_DOC.read_text(), flags=re.MULTILINE | re.DOTALL)


def block(key: str) -> str:
    (found,) = [b for b in yaml_blocks() if key in load_yaml(b)]
    return found


def workflow() -> dict[str, Any]:
    doc: dict[str, Any] = load_yaml(block("jobs"))
    return doc


def test_the_workflow_example_is_a_valid_github_workflow() -> None:
    validator = jsonschema.Draft7Validator(WORKFLOW_SCHEMA)
    problems = [f"{list(e.absolute_path)}: {e.message}" for e in validator.iter_errors(workflow())]
    assert problems == []


def test_the_workflow_schema_catches_a_broken_step() -> None:
    broken = workflow()
    broken["jobs"]["motions"]["steps"].append({"uses": "actions/checkout@v4", "run": "x"})
    assert list(jsonschema.Draft7Validator(WORKFLOW_SCHEMA).iter_errors(broken))


def test_upload_artifact_lists_one_path_per_line() -> None:
    (upload,) = [
        s
        for s in workflow()["jobs"]["motions"]["steps"]
        if s.get("uses", "").startswith("actions/upload-artifact@")
    ]
    paths = upload["with"]["path"].splitlines()
    assert paths == ["batch.*", "motiontool.sarif"]
    assert all(len(p.split()) == 1 for p in paths)


def test_github_annotations_step_sorts_errors_first() -> None:
    runs = [s.get("run", "") for s in workflow()["jobs"]["motions"]["steps"]]
    assert any("--format github --sort severity" in r for r in runs)
    assert "10 error and 10 warning annotations per step" in CI_DOC.read_text()


def test_the_workflow_installs_the_extras_its_commands_need() -> None:
    # The core has no MuJoCo: a workflow that runs batch must install the [sim] extra.
    runs = [s.get("run", "") for s in workflow()["jobs"]["motions"]["steps"]]
    installs = " ".join(r for r in runs if r.startswith("pip install"))
    extras = set(re.findall(r"motiontool\[([a-z,]+)\]", installs))
    names = {name for group in extras for name in group.split(",")}
    assert any("motiontool batch" in r for r in runs)
    assert names & {"sim", "all"}, installs


def test_the_pre_commit_config_example_is_valid(tmp_path: Path) -> None:
    config = tmp_path / ".pre-commit-config.yaml"
    config.write_text(block("repos"))
    loaded = load_config(str(config))
    (repo,) = loaded["repos"]
    version = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    # A release tag of this version, or a full commit sha: never a branch.
    assert repo["rev"] == f"v{version}" or re.fullmatch(r"[0-9a-f]{40}", repo["rev"])
    ids = {h["id"] for h in load_manifest(str(ROOT / ".pre-commit-hooks.yaml"))}
    assert {h["id"] for h in repo["hooks"]} <= ids
    for hook_id in ids:
        assert hook_id in CI_DOC.read_text()


def test_the_hooks_manifest_is_valid_for_pre_commit() -> None:
    hooks = load_manifest(str(ROOT / ".pre-commit-hooks.yaml"))
    assert [h["id"] for h in hooks] == ["motiontool-validate", "motiontool-validate-strict"]
    for hook in hooks:
        assert hook["entry"].startswith("motiontool validate")
        assert hook["language"] == "python" and re.search(hook["files"], "a/walk.motion")


def test_pre_commits_validator_rejects_a_broken_manifest(tmp_path: Path) -> None:
    broken = tmp_path / ".pre-commit-hooks.yaml"
    broken.write_text("- id: x\n  name: x\n  language: python\n")  # no entry
    with pytest.raises(InvalidManifestError):
        load_manifest(str(broken))


def test_the_gitlab_example_writes_the_code_quality_report_it_uploads() -> None:
    (job,) = [load_yaml(b)["motions"] for b in yaml_blocks() if "motions" in load_yaml(b)]
    report = job["artifacts"]["reports"]["codequality"]
    assert any(f"--format gitlab -o {report}" in line for line in job["script"])
    assert job["artifacts"]["when"] == "always"
