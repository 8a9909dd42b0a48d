"""The ``.rrd`` of a play in a Webots world states the world, read back with Rerun's reader: the
file and its sha256, each field applied and each field or node not applied, as the JSON report
has them."""

from __future__ import annotations

import hashlib
import json
import shutil
from pathlib import Path
from typing import Any

import pytest
from conftest import DATA, require
from rrds import rrd_contents
from typer.testing import CliRunner

from motiontool.cli.app import app

pytestmark = pytest.mark.needs("sim")

runner = CliRunner()


def _column(batches: list[Any], name: str) -> list[Any]:
    values: list[Any] = []
    for batch in batches:
        if name in batch.schema.names:
            for row in batch.column(name).to_pylist():
                values += row if isinstance(row, list) else [row]
    return values


def test_the_recording_states_the_world_as_the_report_does(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    folder = require(DATA / "worlds" / "MANIFEST.tsv", "Webots worlds").parent / "wrestling"
    shutil.copytree(folder, tmp_path / "wrestling")
    monkeypatch.chdir(tmp_path / "wrestling")
    world = Path("worlds", "wrestling.wbt")
    motion = Path("controllers", "motions", "HandWave.motion")
    args = ["--world", str(world), "--robot-node", "WRESTLER_BLUE", "--rrd", "run.rrd"]
    result = runner.invoke(
        app, ["play", "--headless", "--hold", "0", "--json", "run.json", *args, str(motion)]
    )
    assert result.exit_code in (0, 1), result.output
    doc = json.loads(Path("run.json").read_text(encoding="utf-8"))["world"]
    sha256 = hashlib.sha256(world.read_bytes()).hexdigest()
    assert doc["sha256"] == sha256

    contents = rrd_contents(Path("run.rrd"))
    facts = contents["/webots_world"]
    (text,) = _column(facts, "TextDocument:text")
    assert _column(facts, "TextDocument:media_type") == ["text/markdown"]
    assert f"- file: `{world}`" in text and f"- sha256: `{sha256}`" in text
    assert "robot node that played: Nao 'opponent' (DEF WRESTLER_BLUE)" in text
    applied = [e["field"] for e in doc["applied"]]
    not_applied = [e["field"] for e in doc["not_applied"]]
    assert {
        "WorldInfo.basicTimeStep",
        "WorldInfo.gravity",
        "ContactProperties.coulombFriction",
        "Nao 'opponent'.translation",
        "Nao 'opponent'.rotation",
        "Nao 'opponent'.selfCollision",
        "WrestlingRing 'wrestling ring'.boundingObject",
    } <= set(applied)
    assert {"WorldInfo.ERP", "WorldInfo.CFM", "WorldInfo.basicTimeStep as the physics step"} <= set(
        not_applied
    )
    for entry in doc["applied"]:
        assert f"| {entry['field']} |" in text and entry["applied_as"] in text
    for entry in doc["not_applied"]:
        assert f"| {entry['field']} |" in text and entry["reason"] in text
    assert text.index("## Applied") < text.index("| WorldInfo.gravity | 9.81 m/s^2 |")
    assert text.index("## Not applied") < text.index("| WorldInfo.ERP | 0.2 |")
    assert "| Nao 'opponent'.selfCollision | TRUE |" in text
    assert all(line in text for line in doc["skipped_nodes"]) and "RubberDuck" in text

    # The same facts as columns, for a script; the file and hash as a recording property.
    assert _column(facts, "path") == [str(world)] and _column(facts, "sha256") == [sha256]
    assert _column(facts, "applied") == applied
    assert _column(facts, "not_applied") == not_applied
    assert _column(facts, "reason") == [e["reason"] for e in doc["not_applied"]]
    assert _column(facts, "applied_value")[applied.index("WorldInfo.basicTimeStep")] == "10 ms"
    assert _column(facts, "skipped_nodes") == doc["skipped_nodes"]
    assert _column(contents["/__properties/world"], "sha256") == [sha256]


def test_a_recording_without_a_world_has_none(tmp_path: Path) -> None:
    motion = DATA / "worlds" / "wrestling" / "controllers" / "motions" / "HandWave.motion"
    rrd = tmp_path / "run.rrd"
    result = runner.invoke(
        app, ["play", "--headless", "--hold", "0", "--rrd", str(rrd), str(motion)]
    )
    assert result.exit_code in (0, 1), result.output
    contents = rrd_contents(rrd)
    assert "/webots_world" not in contents and "/__properties/world" not in contents
    assert "/__properties/stamps" in contents
