"""The JSON Schemas shipped in the package, checked against REAL output of every command."""

from __future__ import annotations

import copy
import json
from pathlib import Path
from typing import Any

import jsonschema
import pytest
from conftest import DATA, golden
from typer.testing import CliRunner

from motiontool.cli import schemas
from motiontool.cli.app import app
from motiontool.kinematics.robots import builtin_robots, load_robot

runner = CliRunner()

NOD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,A,0,0\n00:00:040,B,0.1,-0.1\n"
NOD2 = b"#WEBOTS_MOTION,V1.0,HeadPitch,HeadYaw\n00:00:000,A,0,0\n00:00:040,B,-0.1,*\n00:00:080,C,0,0.2\n"
BAD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,Pose1,0,0\n00:00:040,Pose2,-1.5,abc\n"
WARN = b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:01:000,Pose1,0.5\n"
OUT_OF_LIMITS = b"#WEBOTS_MOTION,V1.0,HeadYaw,NotAJoint\n0,A,0,0\n500,B,3,1\n"


def errors(doc: Any, name: str) -> list[str]:
    """Every way ``doc`` breaks schema ``name`` (empty when it conforms)."""
    schema = schemas.load(name)
    validator = jsonschema.Draft202012Validator(schema, registry=schemas.registry())
    return [f"{list(e.absolute_path)}: {e.message}" for e in validator.iter_errors(doc)]


def run_json(*args: str, exit_codes: tuple[int, ...] = (0, 1)) -> Any:
    result = runner.invoke(app, list(args))
    assert result.exit_code in exit_codes, result.output
    return json.loads(result.stdout)


@pytest.fixture
def files(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    for name, data in {
        "nod.motion": NOD,
        "nod2.motion": NOD2,
        "bad.motion": BAD,
        "warn.motion": WARN,
        "limits.motion": OUT_OF_LIMITS,
    }.items():
        (tmp_path / name).write_bytes(data)
    return tmp_path


@pytest.mark.parametrize("name", schemas.NAMES)
def test_every_schema_is_a_valid_draft_2020_12_schema(name: str) -> None:
    schema = schemas.load(name)
    jsonschema.Draft202012Validator.check_schema(schema)
    assert schema["$schema"] == "https://json-schema.org/draft/2020-12/schema"
    assert schema["properties"]["schema"] == {"const": f"motiontool.{name}"}
    assert "escaped_bytes" in schema["properties"]


def test_load_names_the_schemas_on_a_typo() -> None:
    with pytest.raises(ValueError, match="schemas: validate, info, sample, diff, play, batch, "):
        schemas.load("valdate")


def test_the_registry_holds_every_shipped_schema_by_its_id() -> None:
    shipped = sorted(p.name for p in Path(schemas.__file__).parent.glob("*.schema.json"))
    names = (*schemas.NAMES, schemas.CONFIG, schemas.DEFS)
    assert shipped == sorted(schemas.path_of(n) for n in names)
    registry = schemas.registry()
    for name in names:
        schema = schemas.load(name)
        assert registry.contents(schema["$id"]) == schema
    # Every $ref of every schema resolves (to a shipped schema or within the same one).
    for name in names:
        jsonschema.Draft202012Validator.check_schema(schemas.load(name))
        resolver = registry.resolver(base_uri=schemas.load(name)["$id"])
        for ref in _refs(schemas.load(name)):
            resolver.lookup(ref)


def _refs(node: Any) -> list[str]:
    if isinstance(node, dict):
        own = [node["$ref"]] if "$ref" in node else []
        return own + [r for v in node.values() for r in _refs(v)]
    if isinstance(node, list):
        return [r for v in node for r in _refs(v)]
    return []


@pytest.mark.parametrize(
    "args",
    [
        ["."],
        ["--robot", "none", "."],
        ["--checks", "limits,velocity", "--timestep", "20", "limits.motion", "bad.motion"],
    ],
    ids=["auto", "robot-none", "limits"],
)
def test_validate_json_conforms(files: Path, args: list[str]) -> None:
    doc = run_json("validate", "--format", "json", *args)
    assert doc["summary"]["errors"] >= 1
    assert errors(doc, "validate") == []


def test_validate_json_of_every_golden_invalid_file_conforms(tmp_path: Path) -> None:
    invalid = golden("invalid")
    assert invalid
    doc = run_json("validate", "--robot", "none", "--format", "json", *map(str, invalid))
    assert len(doc["files"]) == len(invalid)
    assert errors(doc, "validate") == []


def test_the_schema_catches_a_wrong_type_and_a_missing_key(files: Path) -> None:
    doc = run_json("validate", "--format", "json", "bad.motion")
    broken = copy.deepcopy(doc)
    broken["summary"]["errors"] = "1"
    assert any("summary" in e for e in errors(broken, "validate"))
    broken = copy.deepcopy(doc)
    del broken["files"][0]["diagnostics"][0]["severity"]
    assert any("'severity' is a required property" in e for e in errors(broken, "validate"))
    broken = copy.deepcopy(doc)
    broken["files"][0]["diagnostics"][0]["severity"] = "fatal"
    assert errors(broken, "validate")
    # Objects meant to grow admit new fields; a closed one does not.
    grown = copy.deepcopy(doc)
    grown["files"][0]["diagnostics"][0]["suggestion"] = {"text": "0"}
    assert errors(grown, "validate") == []
    grown["summary"]["skipped"] = 0
    assert errors(grown, "validate")


def test_info_json_conforms(files: Path) -> None:
    for name in ("nod.motion", "nod2.motion", "warn.motion"):
        assert errors(run_json("info", "--format", "json", name), "info") == []


def test_sample_json_conforms(files: Path) -> None:
    doc = run_json("sample", "--format", "json", "-t", "20", "nod2.motion")
    assert None in doc["targets"][1]  # '*': no command
    assert errors(doc, "sample") == []
    doc = run_json(
        "sample", "--format", "json", "-t", "20", "--reverse", "--loop", "2", "nod.motion"
    )
    assert errors(doc, "sample") == []


def test_diff_json_conforms(files: Path) -> None:
    doc = run_json("diff", "--format", "json", "nod.motion", "nod2.motion")
    assert doc["same"] is False
    assert errors(doc, "diff") == []
    doc = run_json("diff", "--format", "json", "nod.motion", "nod.motion")
    assert doc["same"] is True
    assert errors(doc, "diff") == []


@pytest.mark.needs("sim")
def test_play_json_conforms(files: Path) -> None:
    result = runner.invoke(
        app,
        ["play", "--headless", "--hold", "0", "--json", "run.json", "nod.motion", "nod2.motion"],
    )
    assert result.exit_code == 0, result.output
    doc = json.loads(Path("run.json").read_text())
    assert doc["control_steps"] > 0 and doc["base"] is not None
    assert errors(doc, "play") == []
    # A run that could not start has a short report of its own.
    result = runner.invoke(app, ["play", "--headless", "--json", "bad.json", "bad.motion"])
    assert result.exit_code == 2
    doc = json.loads(Path("bad.json").read_text())
    assert doc["exit_code"] == 2
    assert errors(doc, "play") == []
    del doc["error"]
    assert errors(doc, "play")


@pytest.mark.needs("sim")
def test_play_json_physics_section_conforms(files: Path) -> None:
    result = runner.invoke(
        app,
        [
            *("play", "--headless", "--hold", "0", "--json", "webots.json", "nod.motion"),
            *("--profile", "webots", "--friction", "2", "--physics-step", "4"),
        ],
    )
    assert result.exit_code in (0, 1), result.output
    doc = json.loads(Path("webots.json").read_text())
    assert doc["physics"]["timestep_ms"] == 4.0 and doc["physics"]["friction"] == 2.0
    assert doc["physics"]["profile"] == "webots" and doc["physics"]["profile_note"]
    assert errors(doc, "play") == []
    for key, bad in [("friction", "2"), ("friction", 0), ("profile", "ode"), ("timestep_ms", None)]:
        broken = copy.deepcopy(doc)
        broken["physics"][key] = bad
        assert any("physics" in e for e in errors(broken, "play")), (key, bad)
    broken = copy.deepcopy(doc)
    del broken["physics"]["timestep_ms"]
    assert errors(broken, "play")


@pytest.mark.needs("sim")
def test_play_json_of_an_arm_conforms(files: Path) -> None:
    # A fixed-base arm's report has an end_effector section (keyframes, lags, the tool trail).
    Path("arm.motion").write_bytes(
        b"#WEBOTS_MOTION,V1.0,shoulder_lift_joint,elbow_joint\n0,A,0,0\n240,B,-0.2,0.2\n"
    )
    result = runner.invoke(
        app,
        [
            *("play", "--headless", "--hold", "0.1", "--json", "arm.json", "arm.motion"),
            *("--expect", "ee_lag<1s", "--expect", "ee[B]=[0,0,0]±1mm"),
        ],
    )
    assert result.exit_code == 1, result.output  # the second expectation fails
    doc = json.loads(Path("arm.json").read_text())
    assert [k["name"] for k in doc["end_effector"]["keyframes"]] == ["A", "B"]
    assert errors(doc, "play") == []
    broken = copy.deepcopy(doc)
    broken["end_effector"]["keyframes"][0]["commanded_position_m"] = [0.0, 0.0]
    assert errors(broken, "play")


@pytest.mark.needs("sim")
def test_batch_json_conforms(files: Path) -> None:
    result = runner.invoke(
        app, ["batch", "nod.motion", "--jobs", "1", "--no-cache", "--json", "batch.json"]
    )
    assert result.exit_code == 0, result.output
    doc = json.loads(Path("batch.json").read_text())
    assert errors(doc, "batch") == []
    (run,) = doc["runs"]
    assert run["status"] == "clean"
    assert errors(run["report"], "play") == []  # each report is a play report
    # batch's schema checks each run's report against play's, through its $id.
    broken = copy.deepcopy(doc)
    broken["runs"][0]["report"]["control_steps"] = "many"
    assert any("control_steps" in e or "'many'" in e for e in errors(broken, "batch"))
    broken["runs"][0]["report"] = None  # a run that did not play
    assert errors(broken, "batch") == []


def _times(doc: Any, path: str = "") -> list[tuple[str, float]]:
    """Every number under a key ending ``_s`` (times and durations, s) in ``doc``."""
    if isinstance(doc, dict):
        out = []
        for k, v in doc.items():
            if k.endswith("_s") and isinstance(v, float | int) and not isinstance(v, bool):
                out.append((f"{path}.{k}", float(v)))
            elif k.endswith("_s") and isinstance(v, list):
                out += [(f"{path}.{k}[{i}]", float(x)) for i, x in enumerate(v)]
            else:
                out += _times(v, f"{path}.{k}")
        return out
    if isinstance(doc, list):
        return [t for i, v in enumerate(doc) for t in _times(v, f"{path}[{i}]")]
    return []


@pytest.mark.needs("sim")
def test_play_and_batch_times_are_whole_ms_without_float_noise(files: Path) -> None:
    """201 control steps of 20 ms were written ``4.0200000000000005`` s (201 * 0.02): every
    time and duration of a play or batch report is its whole ms / 1000, so it reads as written
    (``4.02``). The batch's own stamps name the robot model it ran (null) now too: the model's
    hash where one model ran every run, ``models`` each robot's."""
    four_s = b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n2000,B,0.3\n4000,C,0\n"
    Path("four.motion").write_bytes(four_s)
    result = runner.invoke(
        app, ["play", "--headless", "--json", "run.json", "four.motion", "nod.motion"]
    )
    assert result.exit_code == 0, result.output
    text = Path("run.json").read_text()
    doc = json.loads(text)
    assert [f["start_s"] for f in doc["files"]] == [0.0, 4.02]  # 201 steps of 20 ms
    assert '"start_s": 4.02,' in text and doc["simulated_s"] == 5.08  # 201 + 3 + 50 steps
    noisy = [(k, v) for k, v in _times(doc) if repr(v) != repr(round(v * 1000) / 1000)]
    assert noisy == [] and len(_times(doc)) > 20
    args = ["batch", "four.motion", "--jobs", "1", "--no-cache", "--json", "batch.json"]
    result = runner.invoke(app, [*args, "--robot", "nao"])
    assert result.exit_code == 0, result.output
    doc = json.loads(Path("batch.json").read_text())
    nao, ur5e = (load_robot(r).model_hash for r in ("nao", "ur5e"))
    assert doc["stamps"]["model_sha256"] == nao and doc["models"] == {"nao": nao}
    assert doc["runs"][0]["report"]["simulated_s"] == 5.02 and errors(doc, "batch") == []
    assert [(k, v) for k, v in _times(doc) if repr(v) != repr(round(v * 1000) / 1000)] == []
    result = runner.invoke(app, [*args, "--robot", "nao", "--robot", "ur5e"])
    doc = json.loads(Path("batch.json").read_text())
    assert doc["stamps"]["model_sha256"] is None and doc["models"] == {"nao": nao, "ur5e": ur5e}
    assert errors(doc, "batch") == []


def test_the_docs_point_at_every_schema() -> None:
    doc = (DATA.parent.parent / "docs" / "json-report.md").read_text()
    for name in schemas.NAMES:
        assert f"`{name}.schema.json`" in doc


@pytest.mark.parametrize("robot", builtin_robots())
def test_robots_show_json_conforms(robot: str) -> None:
    doc = run_json("robots", "show", robot, "--format", "json", exit_codes=(0,))
    assert doc["name"] == robot and doc["joints"]
    assert errors(doc, "robot") == []
    broken = copy.deepcopy(doc)
    broken["joints"][0]["kind"] = "ball"
    assert errors(broken, "robot")


FAST = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n0,A,0,0\n40,B,1.0,0.1\n80,C,0,0\n"


@pytest.mark.parametrize(
    ("name", "args"),
    [
        ("resample", ["nod2.motion", "--step", "20"]),
        ("resample", ["nod2.motion", "--max-error", "0.01"]),
        ("retime", ["nod.motion", "--speed", "0.5"]),
        ("retime", ["fast.motion", "--fit-limits", "--accel", "50"]),
        ("mirror", ["nod2.motion"]),
        ("scale", ["nod.motion", "--amplitude", "30"]),
        ("scale", ["fast.motion", "--amplitude", "2", "--robot", "none"]),
        ("trim", ["nod2.motion", "--from", "20", "--to", "60"]),
        ("concat", ["nod.motion", "nod2.motion"]),
        ("concat", ["nod.motion", "fast.motion", "--transition", "100", "--robot", "none"]),
    ],
)
def test_authoring_json_conforms(files: Path, name: str, args: list[str]) -> None:
    Path("fast.motion").write_bytes(FAST)
    doc = run_json(name, *args, "--format", "json", "-o", "out.motion")
    assert doc["output"] == "out.motion" and Path("out.motion").is_file()
    assert errors(doc, name) == []
    # -o -: the motion on stdout, the report on stderr, its output null.
    result = runner.invoke(app, [name, *args, "--format", "json", "-o", "-"])
    assert result.exit_code in (0, 1), result.output
    doc = json.loads(result.stderr)
    assert doc["output"] is None
    assert errors(doc, name) == []
    broken = copy.deepcopy(doc)
    del broken["stamps"]["model_sha256"]
    assert errors(broken, name)


def test_authoring_json_details_conform(files: Path) -> None:
    Path("fast.motion").write_bytes(FAST)
    retimed = run_json("retime", "fast.motion", "--fit-limits", "-f", "json", "-o", "r.motion")
    assert {s["reason"] for s in retimed["stretches"]} == {"velocity"}
    scaled = run_json("scale", "nod.motion", "-k", "30", "-f", "json", "-o", "s.motion")
    assert scaled["clipped"] > 0 and scaled["clips"]
    concat = run_json("concat", "nod.motion", "nod2.motion", "-f", "json", "-o", "c.motion")
    assert concat["reordered"] and concat["transitions"][0]["fitted"] is True
    for doc, name, key in [
        (retimed, "retime", "stretches"),
        (scaled, "scale", "clips"),
        (concat, "concat", "transitions"),
    ]:
        broken = copy.deepcopy(doc)
        del broken[key][0][next(iter(broken[key][0]))]
        assert errors(broken, name), name


def test_mirror_show_map_json_conforms() -> None:
    doc = run_json("mirror", "--show-map", "--robot", "nao", "--format", "json", exit_codes=(0,))
    assert doc["schema"] == "motiontool.mirror_map" and doc["robot"] == "nao"
    assert errors(doc, "mirror_map") == []
    doc["map"][0]["sign"] = 0
    assert errors(doc, "mirror_map")
