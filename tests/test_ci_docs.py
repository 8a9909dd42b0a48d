"""docs/ci.md and .pre-commit-hooks.yaml: the examples are valid for the tools that read them
(GitHub's workflow schema, pre-commit's own validator), offline."""

from __future__ import annotations

import json
import re
import subprocess
import sys
import tomllib
from pathlib import Path
from typing import Any

import jsonschema
import pytest
import yaml
from conftest import DATA, ROOT, pre_commit_env
from pre_commit import lang_base
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
    (found,) = blocks(key)
    return found


def blocks(key: str) -> list[str]:
    return [b for b in yaml_blocks() if key in load_yaml(b)]


def pre_commit_blocks() -> tuple[str, str]:
    """The pre-commit examples: (the hooks from the repository at its release tag, the local
    hook on PATH)."""
    remote, local = blocks("repos")
    return remote, local


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
    from motiontool.cli.reports.github import SHOWN_PER_KIND

    n = SHOWN_PER_KIND  # the closing notice counts from it: the doc says the same number
    assert f"{n} error, {n} warning and {n} notice annotations per step" in CI_DOC.read_text()


def _steps() -> list[dict[str, Any]]:
    steps: list[dict[str, Any]] = workflow()["jobs"]["motions"]["steps"]
    return steps


def test_simulation_and_reports_run_even_when_lint_fails() -> None:
    steps = _steps()
    lint = next(i for i, s in enumerate(steps) if "motiontool validate" in s.get("run", ""))
    for step in steps[lint + 1 :]:
        assert step.get("if") == "always()", step
    assert any(s.get("uses", "").startswith("github/codeql-action/upload-sarif@") for s in steps)


def test_the_workflow_keeps_batchs_default_cache(monkeypatch: pytest.MonkeyPatch) -> None:
    from motiontool.sim.batch import default_cache_dir

    monkeypatch.delenv("XDG_CACHE_HOME", raising=False)
    steps = _steps()
    batch = next(i for i, s in enumerate(steps) if "motiontool batch" in s.get("run", ""))
    restore = next(i for i, s in enumerate(steps) if "actions/cache/restore@" in s.get("uses", ""))
    save = next(i for i, s in enumerate(steps) if "actions/cache/save@" in s.get("uses", ""))
    assert restore < batch < save
    for i in (restore, save):
        path = steps[i]["with"]["path"]
        assert Path(path).expanduser() == default_cache_dir(), path
        assert "--cache-dir" not in steps[batch]["run"]
    assert steps[save]["with"]["key"].startswith(steps[restore]["with"]["restore-keys"])


def test_the_workflow_installs_the_extras_its_commands_need() -> None:
    # The core has no MuJoCo: a workflow that runs batch must install the [sim] extra.
    runs = [s.get("run", "") for s in workflow()["jobs"]["motions"]["steps"]]
    installs = " ".join(r for r in runs if r.startswith("pip install"))
    extras = set(re.findall(r"\.whl\[([a-z,]+)\]", installs))
    names = {name for group in extras for name in group.split(",")}
    assert any("motiontool batch" in r for r in runs)
    assert names & {"sim", "all"}, installs


def _release_tag() -> str:
    """The tag dev/release.sh gives a release: v + pyproject.toml's version."""
    return "v" + tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]


def test_the_pre_commit_config_examples_are_valid(tmp_path: Path) -> None:
    remote_text, local_text = pre_commit_blocks()
    manifest = {h["id"]: h for h in load_manifest(str(ROOT / ".pre-commit-hooks.yaml"))}
    config = tmp_path / ".pre-commit-config.yaml"
    config.write_text(remote_text)
    (remote,) = load_config(str(config))["repos"]
    # The rev is the tag the documented release step makes (the slow test below runs it).
    assert remote["rev"] == _release_tag() and "dev/release.sh" in CI_DOC.read_text()
    assert [h["id"] for h in remote["hooks"]] == ["motiontool-validate"]
    config.write_text(local_text)
    (local,) = load_config(str(config))["repos"]
    (hook,) = local["hooks"]
    assert local["repo"] == "local"
    for key in ("entry", "files", "require_serial"):
        assert hook[key] == manifest[hook["id"]][key], key
    for hook_id in ("motiontool-validate", "motiontool-validate-strict"):
        assert hook_id in CI_DOC.read_text()


def test_the_docs_install_the_wheel_pip_builds(tmp_path: Path) -> None:
    # The wheel named in the docs is the one 'pip wheel' writes for this version.
    version = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    text = CI_DOC.read_text()
    named = set(re.findall(r"motiontool-[^/\s\[']+\.whl", text))
    assert named == {f"motiontool-{version}-py3-none-any.whl"}
    runs = [s.get("run", "") for s in workflow()["jobs"]["motions"]["steps"]]
    assert any(r.startswith("pip install 'tools/motiontool-") for r in runs)
    assert "motiontool[" not in " ".join(r for r in runs if r.startswith("pip install"))


def _hook_output(files: list[str], require_serial: bool, monkeypatch: pytest.MonkeyPatch) -> str:
    """What pre-commit's own runner prints for the hook over ``files``, as on an 8-core machine."""
    monkeypatch.setattr(lang_base, "target_concurrency", lambda: 8)
    motiontool = str(Path(sys.executable).parent / "motiontool")
    code, out = lang_base.run_xargs(
        (motiontool, "validate"), files, require_serial=require_serial, color=False
    )
    assert code == 0, out.decode()
    return out.decode()


def test_the_hook_prints_one_header_and_one_summary(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    files = []
    for i in range(40):
        path = tmp_path / f"nod{i:02}.motion"
        path.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n0,A,0,0\n400,B,0.1,-0.1\n")
        files.append(str(path))
    for hook in load_manifest(str(ROOT / ".pre-commit-hooks.yaml")):
        assert hook["require_serial"] is True, hook["id"]
        out = _hook_output(files, hook["require_serial"], monkeypatch)
        assert out.count("robot: ") == 1 and out.count("checked 40 files") == 1, out
    # Without require_serial pre-commit runs chunks in parallel, each with its own summary.
    out = _hook_output(files, False, monkeypatch)
    assert out.count("checked ") > 1, out


def test_the_local_hook_example_runs_under_pre_commit(tmp_path: Path) -> None:
    repo = tmp_path / "assets"
    repo.mkdir()
    env = pre_commit_env(tmp_path / "cache")
    (repo / ".pre-commit-config.yaml").write_text(pre_commit_blocks()[1])
    (repo / "ok.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n400,B,0.1\n")
    (repo / "bad.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n40,B,abc\n")
    subprocess.run(["git", "init", "-q"], cwd=repo, env=env, check=True)
    subprocess.run(["git", "add", "."], cwd=repo, env=env, check=True)
    proc = subprocess.run(
        [sys.executable, "-m", "pre_commit", "run", "--all-files", "--color", "never"],
        cwd=repo,
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert "bad.motion:3:6: error MT108" in proc.stdout, proc.stdout
    assert proc.stdout.count("checked 2 files") == 1, proc.stdout


def test_the_hooks_manifest_is_valid_for_pre_commit() -> None:
    hooks = load_manifest(str(ROOT / ".pre-commit-hooks.yaml"))
    assert [h["id"] for h in hooks] == ["motiontool-validate", "motiontool-validate-strict"]
    for hook in hooks:
        # pre-commit names the staged files: --force-exclude applies the configuration's exclude.
        assert hook["entry"].startswith("motiontool validate --force-exclude")
        assert hook["language"] == "python" and re.search(hook["files"], "a/walk.motion")


OK_MOTION = b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n400,B,0.1\n"
BAD_MOTION = b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n40,B,abc\n"


def _pre_commit(repo: Path, env: dict[str, str]) -> subprocess.CompletedProcess[str]:
    subprocess.run(["git", "add", "."], cwd=repo, env=env, check=True)
    return subprocess.run(
        [sys.executable, "-m", "pre_commit", "run", "--all-files", "--color", "never"],
        cwd=repo,
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )


@pytest.mark.slow  # pre-commit installs the hook's environment with pip (numpy, typer): ~30 s
def test_the_documented_hook_runs_from_a_clone_at_its_release_tag(tmp_path: Path) -> None:
    """The ``rev:`` docs/ci.md gives is the tag the documented release step
    makes; in a clone of this repository so tagged, pre-commit installs the hook from it and
    runs it: a bad file fails, an excluded one is not checked, a good one passes."""
    env = pre_commit_env(tmp_path / "cache")
    clone = tmp_path / "motiontool"
    subprocess.run(["git", "clone", "-q", str(ROOT), str(clone)], env=env, check=True)
    release_env = {**env, "PYTHON": sys.executable}
    release = subprocess.run(
        ["bash", "dev/release.sh"], cwd=clone, env=release_env, capture_output=True, text=True
    )
    assert release.returncode == 0, release.stderr
    assert f" as {_release_tag()};" in release.stdout, release.stdout
    again = subprocess.run(
        ["bash", "dev/release.sh"], cwd=clone, env=release_env, capture_output=True, text=True
    )
    assert again.returncode == 2 and f"{_release_tag()} exists already" in again.stderr

    assets = tmp_path / "assets"
    (assets / "generated").mkdir(parents=True)
    config = load_yaml(pre_commit_blocks()[0])
    config["repos"][0]["repo"] = str(clone)  # the documented "/path/to/motiontool"
    (assets / ".pre-commit-config.yaml").write_text(yaml.safe_dump(config))
    (assets / "motiontool.toml").write_text('exclude = ["generated"]\n')
    (assets / "ok.motion").write_bytes(OK_MOTION)
    (assets / "bad.motion").write_bytes(BAD_MOTION)
    (assets / "generated" / "made.motion").write_bytes(BAD_MOTION)
    subprocess.run(["git", "init", "-q"], cwd=assets, env=env, check=True)
    proc = _pre_commit(assets, env)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert "bad.motion:3:6: error MT108" in proc.stdout, proc.stdout
    assert "made.motion" not in proc.stdout and "checked 2 files" in proc.stdout, proc.stdout
    (assets / "bad.motion").write_bytes(OK_MOTION)
    proc = _pre_commit(assets, env)
    assert proc.returncode == 0, proc.stdout + proc.stderr


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
