"""Configuration: ``[tool.motiontool]`` in pyproject.toml or motiontool.toml, the closest one
up from each file, the command line over it; errors name the file, the line and the key."""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import jsonschema
import pytest
from typer.testing import CliRunner

from motiontool.cli import schemas
from motiontool.cli.app import app
from motiontool.cli.config import KEYS

runner = CliRunner()

# Nao: HeadYaw past its limit (2.5 > 2.0857 rad: MT302, an error), '0.1rad' (MT203, a warning).
NAO = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,P1,0,0.1rad\n00:00:400,P2,2.5,0\n"
# UR5e joints: fine on the UR5e, unknown joints for the Nao.
UR5E = (
    b"#WEBOTS_MOTION,V1.0,shoulder_pan_joint,elbow_joint\n00:00:000,P1,0,0\n00:00:800,P2,0.1,0.1\n"
)


def invoke(*args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, list(args))
    return result.exit_code, result.stdout, result.stderr


def codes(out: str) -> list[str]:
    doc = json.loads(out)
    return [d["code"] for f in doc["files"] for d in f["diagnostics"]]


@pytest.fixture
def repo(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    (tmp_path / "motions" / "nao").mkdir(parents=True)
    (tmp_path / "motions" / "ur5e").mkdir()
    (tmp_path / "motions" / "nao" / "wave.motion").write_bytes(NAO)
    (tmp_path / "motions" / "ur5e" / "reach.motion").write_bytes(UR5E)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def pyproject(repo: Path, body: str) -> None:
    (repo / "pyproject.toml").write_text(f"[project]\nname = 'x'\n\n[tool.motiontool]\n{body}")


def test_without_configuration_the_defaults_apply(repo: Path) -> None:
    code, out, _ = invoke("validate", "motions", "-f", "json")
    assert code == 1 and codes(out) == ["MT203", "MT302"]


def test_ignore_strict_and_robots_per_glob(repo: Path) -> None:
    pyproject(
        repo,
        'robot = "nao"\nignore = ["MT302"]\nstrict = true\n\n'
        '[tool.motiontool.robots]\n"motions/ur5e/**" = "ur5e"\n',
    )
    code, out, _ = invoke("validate", "motions", "-f", "json")
    doc = json.loads(out)
    assert codes(out) == ["MT203"]  # MT302 ignored; the UR5e file checked on the UR5e
    assert {r["name"]: r["files"] for r in doc["robot"]["robots"]} == {
        "nao": ["motions/nao/wave.motion"],
        "ur5e": ["motions/ur5e/reach.motion"],
    }
    assert code == 1  # strict: the MT203 warning fails the run
    assert invoke("validate", "motions", "--no-strict")[0] == 0  # the command line wins
    code, out, _ = invoke("validate", "motions", "-f", "json", "--robot", "none")
    assert codes(out) == ["MT203"] and json.loads(out)["robot"]["checks"] == []


def test_the_closest_configuration_wins(repo: Path) -> None:
    pyproject(repo, 'ignore = ["MT203"]\n')
    (repo / "motions" / "nao" / "motiontool.toml").write_text('select = ["MT2"]\n')
    out = invoke("validate", "motions", "-f", "json")[1]
    assert codes(out) == ["MT203"]  # the nao folder's file: only MT2xx, its MT203 kept
    assert codes(invoke("validate", "motions/ur5e", "-f", "json")[1]) == []


def test_per_file_ignores_extend_ignore_and_select_prefix(repo: Path) -> None:
    pyproject(
        repo,
        'extend-ignore = ["MT3"]\n\n[tool.motiontool.per-file-ignores]\n"wave.motion" = ["MT203"]\n',
    )
    assert codes(invoke("validate", "motions", "-f", "json")[1]) == []
    assert codes(invoke("validate", "motions", "-f", "json", "--isolated")[1]) == [
        "MT203",
        "MT302",
    ]


@pytest.mark.needs("kinematics")
def test_checks_timestep_exclude_and_max_findings(repo: Path) -> None:
    (repo / "motions" / "generated").mkdir()
    (repo / "motions" / "generated" / "g.motion").write_bytes(NAO)
    pyproject(
        repo,
        'checks = ["velocity"]\ntimestep = 40\nexclude = ["generated"]\nmax-findings = 1\n',
    )
    code, out, _ = invoke("validate", "motions", "-f", "json")
    doc = json.loads(out)
    assert [f["path"] for f in doc["files"]] == [
        "motions/nao/wave.motion",
        "motions/ur5e/reach.motion",
    ]
    assert doc["robot"]["checks"] == ["velocity"]
    assert {r["timestep_ms"] for r in doc["robot"]["robots"]} == {40}
    assert codes(out) == ["MT203"] and doc["summary"]["warnings"] >= 1
    pyproject(repo, 'max-findings = 1\nexclude = ["generated"]\n')
    code, out, _ = invoke("validate", "motions")
    assert code == 1  # the MT302 error is not shown but fails the run
    assert out.splitlines()[-1] == (
        "checked 2 files: 1 error, 1 warning, 0 notes; 1 finding not shown (max-findings);"
        " 1 fixable with --fix"
    )
    # A file named on the command line is checked even where a folder search excludes it.
    assert invoke("validate", "motions/generated/g.motion", "-f", "json")[0] == 1


def test_config_option_and_show_settings(repo: Path) -> None:
    (repo / "ci.toml").write_text('robot = "none"\n[robots]\n"**/ur5e/*" = "ur5e"\n')
    code, out, _ = invoke("validate", "motions", "--config", "ci.toml", "-f", "json")
    assert codes(out) == ["MT203"]
    code, out, _ = invoke(
        "validate", "--config", "ci.toml", "--show-settings", "motions/ur5e/reach.motion"
    )
    doc = json.loads(out)
    assert code == 0 and doc["source"] == str((repo / "ci.toml").resolve())
    assert doc["robot-for-this-file"] == "ur5e" and doc["robot"] == "none"
    code, out, _ = invoke("validate", "--isolated", "--show-settings", "motions")
    assert json.loads(out)["source"] is None


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ("strictt = true\n", "pyproject.toml:5: unknown key 'strictt'; did you mean 'strict'?"),
        ('robot = "nao"\ntimestep = "20"\n', "pyproject.toml:6: 'timestep' must be a whole"),
        ('checks = ["limit"]\n', "pyproject.toml:5: 'checks': unknown check 'limit'; did you"),
        ('ignore = ["MT2O3"]\n', "pyproject.toml:5: 'ignore': unknown code 'MT2O3'; did you"),
        ("\n[tool.motiontool.robots]\nwalk = 3\n", "pyproject.toml:6: 'robots' must be a table"),
        ("strict = yes\n", "pyproject.toml: not valid TOML"),
    ],
)
def test_a_bad_configuration_is_one_error_naming_file_line_and_key(
    repo: Path, body: str, message: str
) -> None:
    pyproject(repo, body)
    code, out, err = invoke("validate", "motions")
    assert (code, out) == (2, "")
    assert err.startswith("motiontool: error: ") and message in err, err
    assert err.count("\n") == 1


def test_a_pyproject_that_never_names_motiontool_is_not_read(repo: Path) -> None:
    """Another tool's ``pyproject.toml`` (one that cannot hold ``[tool.motiontool]``) is left
    unparsed, broken TOML included; a key spelled with ``\\u`` escapes is still ours."""
    (repo / "pyproject.toml").write_text("[project]\nname = 'x'\nbroken = [\n")
    assert invoke("validate", "motions")[0] == 1  # the defaults: MT302 fails the run
    (repo / "pyproject.toml").write_text("tool = 'motiontool'\n")  # no table: the defaults
    assert invoke("validate", "motions")[0] == 1
    (repo / "pyproject.toml").write_text('[tool."\\u006dotiontool"]\nignore = ["MT302"]\n')
    code, out, _ = invoke("validate", "motions", "-f", "json")
    assert code == 0 and codes(out) == ["MT203"]


@pytest.fixture
def parses(repo: Path, monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The configuration files parsed as TOML from here on (a fresh cache folder)."""
    from motiontool.motionfmt import structured_text

    monkeypatch.setenv("XDG_CACHE_HOME", str(repo / "cache"))
    parsed: list[str] = []
    real = structured_text.load_toml

    def load_toml(text: str, name: str, what: str) -> dict[str, object]:
        parsed.append(Path(name).name)
        return real(text, name, what)

    monkeypatch.setattr(structured_text, "load_toml", load_toml)
    return parsed


def test_a_configuration_read_before_with_the_same_text_is_not_parsed_again(
    repo: Path, parses: list[str]
) -> None:
    pyproject(repo, 'ignore = ["MT302"]\n')
    assert invoke("validate", "motions/nao", "-f", "json")[0] == 0
    assert parses == ["pyproject.toml"]
    code, out, _ = invoke("validate", "motions/nao", "-f", "json")
    assert (code, codes(out), parses) == (0, ["MT203"], ["pyproject.toml"])
    # An edit (the same length: only the text tells) is read again; so is another file.
    pyproject(repo, 'ignore = ["MT203"]\n')
    code, out, _ = invoke("validate", "motions/nao", "-f", "json")
    assert (code, codes(out), parses[1:]) == (1, ["MT302"], ["pyproject.toml"])
    (repo / "motions" / "nao" / "motiontool.toml").write_text('ignore = ["MT203", "MT302"]\n')
    assert invoke("validate", "motions/nao")[0] == 0
    assert parses[2:] == ["motiontool.toml"]
    assert invoke("cache", "info")[1].count("config: 2 results") == 1
    invoke("cache", "clean")
    assert invoke("cache", "info")[1].count("config: 0 results") == 1


def test_a_configuration_cache_that_cannot_be_used_is_no_error(
    repo: Path, parses: list[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """A damaged entry, a FIFO where an entry should be, a date no entry can hold, a cache
    folder that cannot be made: the file is parsed, as without a cache."""
    import os

    from motiontool.cli import config_cache

    pyproject(repo, 'ignore = ["MT302"]\nrobot = 1979-05-27\n')
    for _ in range(2):
        code, _, err = invoke("validate", "motions/nao")
        assert (code, err.count("pyproject.toml:6: 'robot' must be")) == (2, 1)
    assert parses == ["pyproject.toml"] * 2  # a table with a date is not kept
    pyproject(repo, 'ignore = ["MT302"]\n')
    invoke("validate", "motions/nao")
    (entry,) = (repo / "cache" / "motiontool" / "config").glob("*/*.marshal")
    entry.write_bytes(b"\x00garbage")
    assert invoke("validate", "motions/nao")[0] == 0
    entry.unlink()
    os.mkfifo(entry)
    assert invoke("validate", "motions/nao")[0] == 0  # not opened: no reader would come
    assert entry.is_file()  # replaced by the entry
    assert len(parses) == 5
    assert config_cache.lookup(repo / "pyproject.toml", "another text") is None
    (repo / "cache").rename(repo / "old-cache")
    (repo / "cache").write_text("a file where the cache folder should be")
    code, out, _ = invoke("validate", "motions/nao", "-f", "json")
    assert (code, codes(out), len(parses)) == (0, ["MT203"], 6)


def test_the_schema_ships_and_agrees_with_the_reader(repo: Path) -> None:
    schema = schemas.load(schemas.CONFIG)
    assert set(schema["properties"]) == set(KEYS)
    good = tomllib.loads(
        'robot = "nao"\nstrict = true\nmax-findings = 5\nchecks = ["limits"]\n'
        '[robots]\n"ur5e/**" = "ur5e"\n[per-file-ignores]\n"*.motion" = ["MT206"]\n'
    )
    jsonschema.validate(good, schema)
    (repo / "motiontool.toml").write_text(
        'robot = "nao"\nstrict = true\nmax-findings = 5\nchecks = ["limits"]\n'
        '[robots]\n"ur5e/**" = "ur5e"\n[per-file-ignores]\n"*.motion" = ["MT206"]\n'
    )
    assert invoke("validate", "--show-settings", "motions")[0] == 0
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate({"strictt": True}, schema)


@pytest.mark.needs("sim")
def test_play_and_batch_read_the_same_configuration(repo: Path) -> None:
    pyproject(
        repo,
        'robot = "nao"\ntimestep = 16\nexclude = ["nao"]\n\n'
        '[tool.motiontool.robots]\n"motions/ur5e/**" = "ur5e"\n',
    )
    code, out, err = invoke("play", "motions/ur5e/reach.motion", "--headless", "--hold", "0")
    assert code == 0, out + err
    assert out.startswith("reach.motion on ur5e: 0.82 s simulated (51 control steps of 16 ms")
    code, out, err = invoke("batch", "motions", "--no-cache", "--json", "batch.json")
    assert code == 0, out + err
    runs = json.loads((repo / "batch.json").read_text())["runs"]
    assert [(r["spec"]["path"], r["spec"]["robot"]) for r in runs] == [
        ("motions/ur5e/reach.motion", "ur5e")
    ]
    assert runs[0]["spec"]["options"] == [["timestep_ms", 16]]
    code, out, err = invoke("batch", "motions", "--no-cache", "--isolated", "--json", "all.json")
    assert len(json.loads((repo / "all.json").read_text())["runs"]) == 2


def test_max_findings_is_what_every_format_shows(repo: Path) -> None:
    """Two findings (MT203, MT302), one shown: in every format, the first in file order; the
    summaries count both."""
    pyproject(repo, 'max-findings = 1\nexclude = ["generated"]\n')
    _, out, _ = invoke("validate", "motions", "-f", "json")
    doc = json.loads(out)
    assert codes(out) == ["MT203"] and doc["summary"]["errors"] == 1
    _, out, _ = invoke("validate", "motions", "-f", "sarif")
    assert [r["ruleId"] for r in json.loads(out)["runs"][0]["results"]] == ["MT203"]
    _, out, _ = invoke("validate", "motions", "-f", "gitlab")
    assert [i["check_name"] for i in json.loads(out)] == ["MT203"]
    _, out, _ = invoke("validate", "motions", "-f", "junit")
    assert out.count(" MT203: ") == 1 and " MT302: " not in out
    _, out, _ = invoke("validate", "motions", "--statistics")
    assert "MT203" in out and "MT302" not in out
