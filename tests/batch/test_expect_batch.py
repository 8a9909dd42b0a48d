"""Expectations in a batch (sidecar and --expect; every report format; judged after the cache)
and ``motiontool expect --infer``."""

from __future__ import annotations

import json
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import jsonschema
import pytest
from conftest import CORPUS, corpus_files
from typer.testing import CliRunner

from motiontool.cli import schemas
from motiontool.cli.app import app
from motiontool.sim.infer import infer, words
from motiontool.sim.sidecar import load_sidecar

runner = CliRunner()

NOD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,A,0,0\n00:00:300,B,0.6,-0.3\n00:00:600,C,0,0\n"
WRONG = "expected dx >= 0.3 m, measured"


def batch(*args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, ["batch", *args])
    return result.exit_code, result.stdout, result.stderr


@pytest.mark.needs("sim")
def test_a_wrong_expectation_fails_with_its_reason_in_every_report(tmp_path: Path) -> None:
    motions = tmp_path / "motions"
    motions.mkdir()
    (motions / "nod.motion").write_bytes(NOD)
    (motions / "shake.motion").write_bytes(NOD.replace(b"HeadYaw,HeadPitch", b"HeadPitch,HeadYaw"))
    (motions / "motions.toml").write_text('[nod]\nexpect = ["upright", "dx>=0.3"]\n')
    out = tmp_path / "out"
    cache = ["--cache-dir", str(tmp_path / "cache")]
    reports = ["--json", f"{out}.json", "--junit", f"{out}.xml", "--markdown", f"{out}.md"]
    code, stdout, _ = batch(str(motions), "--expect", "feet-planted", *cache, *reports)
    assert code == 1, stdout
    nod_line = next(line for line in stdout.splitlines() if "nod.motion" in line)
    assert f"failed: {WRONG}" in nod_line
    assert "1 clean, 1 not clean" in stdout

    doc = json.loads(Path(f"{out}.json").read_text())
    jsonschema.validate(doc, schemas.load("batch"), registry=schemas.registry())
    runs = {Path(r["spec"]["path"]).name: r for r in doc["runs"]}
    assert runs["nod.motion"]["spec"]["expect"] == ["upright", "dx>=0.3", "feet-planted"]
    assert runs["shake.motion"]["spec"]["expect"] == ["feet-planted"]  # --expect: every motion
    nod = runs["nod.motion"]
    assert nod["status"] == "failed" and nod["reason"].startswith(WRONG)
    judged = nod["report"]["expectations"]
    assert [(e["text"], e["passed"]) for e in judged] == [
        ("upright", True),
        ("dx>=0.3", False),
        ("feet-planted", True),
    ]
    assert judged[1]["reason"] == nod["reason"] and judged[1]["measured"]["unit"] == "m"
    jsonschema.validate(nod["report"], schemas.load("play"))

    cases = {c.get("name"): c for c in ET.parse(f"{out}.xml").getroot().iter("testcase")}
    (nod_case,) = [c for name, c in cases.items() if name and "nod.motion" in name]
    failure = nod_case.find("failure")
    assert failure is not None and failure.get("message", "").startswith(WRONG)
    (shake_case,) = [c for name, c in cases.items() if name and "shake.motion" in name]
    assert shake_case.find("failure") is None

    markdown = Path(f"{out}.md").read_text()
    assert f"| failed: {WRONG}" in markdown

    # Expectations are judged after the cache: a corrected sidecar passes without a re-run.
    (motions / "motions.toml").write_text('[nod]\nexpect = ["upright", "dx<0.3"]\n')
    code, stdout, _ = batch(str(motions), *cache)
    assert code == 0, stdout
    assert "2 from cache" in stdout
    assert "none simulated" in stdout and "runs/s" not in stdout  # was '0.00 runs/s'
    code, stdout, _ = batch(str(motions), "--no-sidecar", "--expect", "yaw>5", *cache)
    assert code == 1 and "expected yaw > 5 deg, measured" in stdout


@pytest.mark.needs("sim")
def test_a_bad_sidecar_or_expect_exits_2_before_anything_runs(tmp_path: Path) -> None:
    (tmp_path / "nod.motion").write_bytes(NOD)
    (tmp_path / "motions.toml").write_text('[nod]\nexpect = ["upright"]\nstart = "lying"\n')
    code, stdout, stderr = batch(str(tmp_path), "--no-cache")
    assert code == 2 and stdout == ""
    assert stderr == (
        f"motiontool: error: {tmp_path / 'motions.toml'}:3: start 'lying' in [nod]: "
        "choose standing, lying-front, lying-back\n"
    )
    code, _, stderr = batch(str(tmp_path), "--no-sidecar", "--expect", "uprite", "--no-cache")
    assert code == 2
    assert stderr.startswith(
        "motiontool: error: expectation 'uprite': unknown quantity 'uprite'; "
        "did you mean 'upright'?"
    )


@pytest.mark.needs("sim")
def test_the_sidecar_start_reaches_the_run(tmp_path: Path) -> None:
    (tmp_path / "nod.motion").write_bytes(NOD)
    (tmp_path / "motions.toml").write_text('["n*"]\nstart = "lying-back"\n')
    out = tmp_path / "run.json"
    code, stdout, _ = batch(str(tmp_path), "--no-cache", "--json", str(out))
    assert code == 1 and "started down and did not get up" in stdout
    (run,) = json.loads(out.read_text())["runs"]
    assert ["start", "lying-back"] in run["spec"]["options"]
    assert run["report"]["options"]["start"] == "lying-back"
    code, stdout, _ = batch(str(tmp_path), "--no-cache", "--start", "standing")
    assert code == 0, stdout  # the command line beats the sidecar


# ------------------------------------------------------------------------------- infer


@pytest.mark.parametrize(
    ("name", "expect", "start"),
    [
        ("Forwards50", ["dx_heading>=0.03", "upright"], None),
        ("Backwards", ["dx_heading<=-0.03", "upright"], None),
        ("forward", ["dx_heading>=0.03", "upright"], None),
        ("SideStepLeft", ["dy_heading>=0.03", "upright"], None),
        ("SideStepRight", ["dy_heading<=-0.03", "upright"], None),
        ("TurnLeft60", ["yaw=60±9", "upright"], None),
        ("TurnRight40", ["yaw=-40±6", "upright"], None),
        ("TurnLeft180", ["yaw=180±27", "upright"], None),
        ("TurnLeft10", ["yaw=10±5", "upright"], None),  # turns ~32 deg: the review says 'check'
        ("StandUpFromFront", ["upright"], "lying-front"),
        ("stand_up_from_back", ["upright"], "lying-back"),
        ("Fall", ["fell"], None),
        ("HandWave", ["upright", "feet-planted"], None),
        ("WipeForehead", ["upright", "feet-planted"], None),
        ("wave_right", ["upright", "feet-planted"], None),
        ("TaiChi", ["upright"], None),
        ("Shoot", ["no-fall"], None),
    ],
)
def test_infer_from_corpus_names(name: str, expect: list[str], start: str | None) -> None:
    inference = infer(name)
    assert (inference.expect, inference.start) == (expect, start)
    assert inference.notes


def test_words_split_camel_case_snake_case_and_numbers() -> None:
    assert words("TurnLeft60") == ["turn", "left", "60"]
    assert words("HandsUpNoWiggle") == ["hands", "up", "no", "wiggle"]
    assert words("stand_wave_return") == ["stand", "wave", "return"]
    assert infer("sorting", floating_base=False).expect == ["no-self-collision"]


def test_expect_infer_writes_a_sidecar_that_loads(tmp_path: Path) -> None:
    files = corpus_files()
    if not files:
        pytest.skip("Webots corpus not vendored")
    out = tmp_path / "motions.toml"
    result = runner.invoke(app, ["expect", "--infer", str(CORPUS), "TurnLeft10", "-o", str(out)])
    assert result.exit_code == 0, result.output
    text = out.read_text(encoding="utf-8")
    assert text.startswith("# motions.toml: expectations proposed") and "REVIEW" in text
    sidecar = load_sidecar(out)
    keys = [s.key for s in sidecar.sections]
    assert len(keys) == len(set(keys)) == len({f.stem for f in files})  # TurnLeft10 once
    by_key = {s.key: s for s in sidecar.sections}
    assert by_key["TurnLeft60"].expect == ("yaw=60±9", "upright")
    assert by_key["StandUpFromFront"].start == "lying-front"
    assert by_key["TurnLeft10"].expect == ("yaw=10±5", "upright")
    assert "TurnLeft10 turns about 32 deg" in text
    assert "[hand_high]  # upper body only" in text and "batch it with --robot" in text
    stdout = runner.invoke(app, ["expect", "--infer", "TurnRight60"]).stdout
    assert (
        '[TurnRight60]  # turns right 60 deg if 60 is degrees: check\nexpect = ["yaw=-60±9"'
        in stdout
    )


def test_expect_refuses_to_overwrite_an_input_and_needs_infer(tmp_path: Path) -> None:
    motion = tmp_path / "nod.motion"
    motion.write_bytes(NOD)
    result = runner.invoke(app, ["expect", "--infer", str(motion), "-o", str(motion)])
    assert result.exit_code == 2 and motion.read_bytes() == NOD
    assert "is the input file" in result.stderr
    result = runner.invoke(app, ["expect", "Forwards"])
    assert result.exit_code == 2 and "expect needs --infer" in result.stderr
    result = runner.invoke(app, ["expect", "--infer", "missing/Forwards.motion"])
    assert result.exit_code == 2 and "cannot read 'missing/Forwards.motion'" in result.stderr


# ------------------------------------------------------------------------------- corpus


@pytest.mark.needs("sim")
@pytest.mark.slow
@pytest.mark.usefixtures("corpus")
def test_inferred_expectations_pass_on_the_corpus_and_a_wrong_one_fails(tmp_path: Path) -> None:
    names = ("TurnLeft60", "SideStepRight", "HandWave", "Forwards")
    folder = tmp_path / "corpus"
    folder.mkdir()
    for name in names:
        (source,) = [f for f in corpus_files() if f.stem == name]
        shutil.copy(source, folder)
    sidecar = folder / "motions.toml"
    result = runner.invoke(app, ["expect", "--infer", str(folder), "-o", str(sidecar)])
    assert result.exit_code == 0, result.output
    cache = ["--cache-dir", str(tmp_path / "cache"), "--jobs", "2"]
    out = tmp_path / "batch.json"
    code, stdout, _ = batch(str(folder), *cache, "--json", str(out))
    assert code == 0, stdout
    for run in json.loads(out.read_text())["runs"]:
        judged = run["report"]["expectations"]
        assert judged and all(e["passed"] for e in judged), run["spec"]["path"]
    # Reviewed the wrong way round: TurnLeft60 turns left, not right.
    text = sidecar.read_text(encoding="utf-8")
    sidecar.write_text(text.replace('"yaw=60±9"', '"yaw=-60±10"'), encoding="utf-8")
    code, stdout, _ = batch(str(folder), *cache)
    assert code == 1
    (line,) = [line for line in stdout.splitlines() if "TurnLeft60" in line]
    assert "failed: expected yaw = -60 ± 10 deg, measured 58." in line
    assert "3 clean, 1 not clean, 4 from cache" in stdout


@pytest.mark.needs("sim")
def test_a_sidecar_after_makes_a_batch_run_a_chain_named_in_every_report(
    tmp_path: Path,
) -> None:
    """The run of Walk_Loop plays Walk_Start then Walk_Loop; the reports name
    both; a changed Walk_Start is played again, not answered from the cache."""
    motions = tmp_path / "motions"
    motions.mkdir()
    (motions / "Walk_Start.motion").write_bytes(NOD)
    (motions / "Walk_Loop.motion").write_bytes(NOD.replace(b"0.6,-0.3", b"-0.6,-0.3"))
    (motions / "motions.toml").write_text('[Walk_Loop]\nafter = "Walk_Start"\n')
    out = tmp_path / "out"
    cache = ["--cache-dir", str(tmp_path / "cache")]
    reports = ["--json", f"{out}.json", "--junit", f"{out}.xml", "--markdown", f"{out}.md"]
    loop = str(motions / "Walk_Loop.motion")
    code, stdout, _ = batch(loop, *cache, *reports)
    assert code == 0, stdout
    chain = f"{motions / 'Walk_Start.motion'} + {loop}"
    assert chain in stdout
    doc = json.loads(Path(f"{out}.json").read_text())
    jsonschema.validate(doc, schemas.load("batch"), registry=schemas.registry())
    (run,) = doc["runs"]
    assert run["spec"]["chain"] == [str(motions / "Walk_Start.motion")]
    assert [Path(f["path"]).name for f in run["report"]["files"]] == [
        "Walk_Start.motion",
        "Walk_Loop.motion",
    ]
    assert run["report"]["options"]["chain"] is True
    assert doc["motions"][0]["motion"] == chain
    (case,) = ET.parse(f"{out}.xml").getroot().iter("testcase")
    assert chain in (case.get("name") or "")
    assert "Walk_Start.motion + " in Path(f"{out}.md").read_text()
    code, stdout, _ = batch(loop, *cache)
    assert code == 0 and "1 from cache" in stdout
    (motions / "Walk_Start.motion").write_bytes(NOD.replace(b"0.6,-0.3", b"0.5,-0.3"))
    code, stdout, _ = batch(loop, *cache)
    assert code == 0 and "0 from cache" in stdout
