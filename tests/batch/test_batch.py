"""Planning, perturbation draws, caching and reports of a batch (the simulator itself is tested
in tests/sim; here a small deterministic runner stands in for it)."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import pytest

from motiontool.cli.batch_reports import render_json, render_markdown, render_summary, write_junit
from motiontool.motionfmt import MotionToolError, read_motion
from motiontool.sim.batch import RunSpec, parse_perturbation, plan, run_batch

CALLS: list[str] = []


def runner(spec: RunSpec) -> dict[str, Any]:
    """Deterministic stand-in: 'falls' when the motion is longer than 1 s or friction < 0.8."""
    motion = read_motion(spec.path)
    params = dict(spec.params)
    fell = motion.duration_ms > 1000 or params.get("friction", 1.0) < 0.8
    return {
        "clean": not fell,
        "reason": "fell at 0.5 s" if fell else "",
        "base": {"max_tilt_deg": 60.0 if fell else 2.0},
    }


@pytest.fixture
def motions(tmp_path: Path) -> list[Path]:
    short = tmp_path / "short.motion"
    short.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n500,B,0.5\n")
    long = tmp_path / "long.motion"
    long.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n2000,B,0.5\n")
    return [short, long]


def test_parse_perturbation() -> None:
    p = parse_perturbation("friction=0.7:1.3")
    assert (p.name, p.low, p.high) == ("friction", 0.7, 1.3)
    with pytest.raises(MotionToolError, match="NAME one of friction, mass, motor-strength"):
        parse_perturbation("gravity=1:2")
    with pytest.raises(MotionToolError, match="need finite LOW <= HIGH"):
        parse_perturbation("mass=1.1:0.9")


def test_plan_is_seeded_and_independent_of_order(motions: list[Path]) -> None:
    perturb = [parse_perturbation("friction=0.7:1.3"), parse_perturbation("mass=0.9:1.1")]
    a = plan(motions, ["nao"], perturbations=perturb, samples=4, seed=1)
    b = plan(motions, ["nao"], perturbations=perturb[::-1], samples=4, seed=1)
    c = plan(motions, ["nao"], perturbations=perturb, samples=4, seed=2)
    assert a == b and a != c and len(a) == 8
    for spec in a:
        params = dict(spec.params)
        assert 0.7 <= params["friction"] <= 1.3 and 0.9 <= params["mass"] <= 1.1
    assert plan(motions, ["nao", "nao-v5"], samples=5)[0].params == ()  # no perturbation: 1 sample
    assert len(plan(motions, ["nao", "nao-v5"], samples=5)) == 4


def test_cache_replays_only_what_is_missing(motions: list[Path], tmp_path: Path) -> None:
    specs = plan(
        motions, ["nao"], perturbations=[parse_perturbation("friction=0.6:1.0")], samples=3, seed=3
    )
    cache = tmp_path / "cache"
    first = run_batch(specs, runner, model_hash=lambda r: "h", jobs=2, cache_dir=cache)
    assert [r.cached for r in first.runs] == [False] * 6
    second = run_batch(specs, runner, model_hash=lambda r: "h", jobs=2, cache_dir=cache)
    assert [r.cached for r in second.runs] == [True] * 6
    assert [(r.status, r.report) for r in second.runs] == [(r.status, r.report) for r in first.runs]
    other_model = run_batch(
        specs[:1], runner, model_hash=lambda r: "other", jobs=1, cache_dir=cache
    )
    assert not other_model.runs[0].cached
    expected = [
        "failed"
        if (s.path.endswith("long.motion") or dict(s.params)["friction"] < 0.8)
        else "clean"
        for s in specs
    ]
    assert [r.status for r in first.runs] == expected


def test_reports(motions: list[Path], tmp_path: Path) -> None:
    specs = plan(motions, ["nao"])
    batch = run_batch(specs, runner, model_hash=lambda r: "h", jobs=2, cache_dir=None)
    summary = render_summary(batch)
    assert "long.motion" in summary and "failed: fell at 0.5 s" in summary
    assert summary.splitlines()[-1].startswith("2 runs: 1 clean, 1 not clean, 0 from cache;")
    doc = json.loads(render_json(batch))
    assert doc["summary"] == {"runs": 2, "clean": 1, "not_clean": 1, "cached": 0}
    assert doc["runs"][1]["report"]["base"]["max_tilt_deg"] == 60.0
    md = render_markdown(batch)
    assert "| motion | robot | runs | clean | worst case |" in md and "0 (0 %)" in md
    junit = tmp_path / "r.xml"
    write_junit(batch, junit)
    suite = ET.parse(junit).getroot().find("testsuite")
    assert suite is not None and suite.get("tests") == "2" and suite.get("failures") == "1"
    failure = suite.find("testcase/failure")
    assert failure is not None and failure.get("message") == "fell at 0.5 s"
