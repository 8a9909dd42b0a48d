"""Golden pairs: every edge case of docs/webots-format.md with the exact diagnostics and parse expected."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from conftest import golden
from data.regen import expected_text  # the golden files' wording, shared with regen.py
from oracle import webots_load

from motiontool.motionfmt import CODES, MotionSyntaxError, Severity, read_bytes


@pytest.mark.parametrize("path", golden("valid") + golden("invalid"), ids=lambda p: p.stem)
def test_exact_diagnostics(path: Path) -> None:
    assert expected_text(path) == path.with_suffix(".expected").read_text(encoding="utf-8")


@pytest.mark.parametrize("path", golden("valid"), ids=lambda p: p.stem)
def test_valid_files_parse_as_expected(path: Path) -> None:
    result = read_bytes(path.read_bytes(), path.name)
    assert result.accepted
    expected = json.loads(path.with_suffix(".json").read_text(encoding="utf-8"))
    assert result.joints == expected["joints"]
    assert result.pose_names == expected["pose_names"]
    assert list(result.times_ms) == expected["times_ms"]
    rows = map(result.row, range(len(result.times_ms)))
    values = [[None if math.isnan(v) else repr(v) for v in row] for row in rows]
    assert values == expected["values"]


@pytest.mark.parametrize("path", golden("invalid"), ids=lambda p: p.stem)
def test_invalid_files_are_rejected_where_webots_stops(path: Path) -> None:
    data = path.read_bytes()
    result = read_bytes(data, path.name)
    oracle = webots_load(data)
    assert not oracle.ok, "golden invalid file must be rejected by the oracle"
    assert not result.accepted
    assert result.rejected_at is not None and result.rejected_at.severity is Severity.ERROR
    # The finding that decides the verdict is reported, also after a cut line (issue #36 item 16).
    assert any(d is result.rejected_at for d in result.diagnostics)
    if oracle.stop_line is not None:
        lines = {d.line for d in result.errors}
        assert oracle.stop_line in lines
        assert result.rejected_at.line == oracle.stop_line
    with pytest.raises(MotionSyntaxError) as info:
        _ = result.motion
    assert str(info.value).startswith(f"{path.name}:{result.rejected_at.line}:")


def test_the_code_table_says_which_codes_reject() -> None:
    assert {c.id for c in CODES.values() if c.rejects} == {f"MT{n}" for n in range(100, 111)}
    # MT112 is decided per finding: a time that wraps to a valid one is read, else rejected.
    head = b"#WEBOTS_MOTION,V1.0,A\n0,P1,0\n"
    wraps = read_bytes(head + b"4294967396,P2,1\n")  # 2^32 + 100: Webots reads 100 ms
    assert [d.code for d in wraps.diagnostics] == ["MT112"] and wraps.accepted
    assert list(wraps.times_ms) == [0, 100]
    invalid = read_bytes(head + b"4294967295,P2,1\n")  # wraps to -1: not a time
    assert [d.code for d in invalid.diagnostics] == ["MT112"]
    assert invalid.rejected_at is invalid.diagnostics[0]


@pytest.mark.parametrize("path", golden("valid") + golden("invalid"), ids=lambda p: p.stem)
def test_webots_stops_at_the_first_finding_that_rejects(path: Path) -> None:
    result = read_bytes(path.read_bytes(), path.name)
    rejecting = [
        d
        for d in result.diagnostics
        if CODES[d.code].rejects or (d.code == "MT112" and d.message.endswith("Webots rejects it"))
    ]
    assert result.rejected_at is (rejecting[0] if rejecting else None)


@pytest.mark.parametrize("path", golden("valid"), ids=lambda p: p.stem)
def test_valid_files_are_accepted_by_the_oracle(path: Path) -> None:
    assert webots_load(path.read_bytes()).ok


def test_every_code_is_exercised_by_a_golden_file() -> None:
    from motiontool.motionfmt.diagnostics import CODES

    seen = set()
    for path in golden("valid") + golden("invalid"):
        seen |= {
            line.split()[2].rstrip(":")
            for line in expected_text(path).splitlines()
            if ": " in line and not line.startswith("  ")
        }
    missing = {c for c in CODES if c.startswith(("MT1", "MT2"))} - seen
    assert not missing, f"codes without a golden file: {sorted(missing)}"
