"""``validate --fix``, ``--unsafe-fixes`` and ``--diff`` (issue #17 item 2), and the fixes in the
text, JSON and SARIF reports: the file is rewritten atomically, only where a fix applies, and
Webots' command stream is unchanged by the safe fixes."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path
from typing import Any

import jsonschema
import pytest
from conftest import DATA
from typer.testing import CliRunner

from motiontool.cli import schemas
from motiontool.cli.app import app
from motiontool.motionfmt import read_bytes, sample

runner = CliRunner()
SARIF_SCHEMA = json.loads((DATA / "sarif" / "sarif-schema-2.1.0.json").read_text())


def errors(doc: Any, schema: Any) -> list[str]:
    validator = jsonschema.validators.validator_for(schema)(schema)
    return [f"{list(e.absolute_path)}: {e.message}" for e in validator.iter_errors(doc)]


FIXABLE = b"#WEBOTS_MOTION,V1.0,A,B\r\n0,P,2rad,-9999999.9\r\n100,Q,1,  1\r\n\r\n200,R,0,0\r\n"
SAFE = b"#WEBOTS_MOTION,V1.0,A,B\r\n0,P,2,*\r\n100,Q,1,  1\r\n\r\n200,R,0,0\r\n"
UNSAFE = b"#WEBOTS_MOTION,V1.0,A,B\r\n0,P,2,*\r\n100,Q,1,  1\r\n200,R,0,0\r\n"


@pytest.fixture
def motion(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "m.motion"
    path.write_bytes(FIXABLE)
    return path


def invoke(*args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, list(args))
    return result.exit_code, result.stdout, result.stderr


def test_fix_applies_the_safe_fixes_only_and_keeps_the_rest_byte_for_byte(motion: Path) -> None:
    os.chmod(motion, 0o640)
    code, out, err = invoke("validate", "m.motion", "--fix")
    assert motion.read_bytes() == SAFE  # CRLF, spacing and the blank line are the user's
    assert err == "motiontool: fixed 2 findings in 1 file (MT203, MT204)\n"
    assert oct(motion.stat().st_mode & 0o777) == "0o640"
    assert code == 0 and "MT203" not in out and "MT201" in out  # what remains is reported
    for step in (1, 20, 32):
        a, b = sample(read_bytes(FIXABLE).motion, step), sample(read_bytes(SAFE).motion, step)
        assert a.targets.tobytes() == b.targets.tobytes()
        assert (a.commanded == b.commanded).all()
    assert invoke("validate", "m.motion", "--fix")[2] == "motiontool: nothing to fix\n"


def test_unsafe_fixes_also_remove_the_blank_line(motion: Path) -> None:
    code, _, err = invoke("validate", "m.motion", "--fix", "--unsafe-fixes")
    assert code == 0
    assert motion.read_bytes() == UNSAFE
    assert err == "motiontool: fixed 3 findings in 1 file (MT201, MT203, MT204)\n"


def test_diff_shows_the_fixes_writes_nothing_and_exits_1(motion: Path) -> None:
    result = runner.invoke(app, ["validate", "m.motion", "--diff"])
    out = result.stdout_bytes  # bytes: the CRLF line ends are the file's
    assert result.exit_code == 1 and motion.read_bytes() == FIXABLE
    assert out.startswith(b"--- a/m.motion\n+++ b/m.motion\n@@ -1,5 +1,5 @@\n")
    assert b"-0,P,2rad,-9999999.9\r\n+0,P,2,*\r\n" in out
    # git apply reads it and gives what --fix writes.
    subprocess.run(["git", "init", "-q"], check=True)
    patch = Path("fix.patch")
    patch.write_bytes(out)
    subprocess.run(["git", "apply", str(patch)], check=True)
    assert motion.read_bytes() == SAFE
    assert invoke("validate", "m.motion", "--diff")[:2] == (0, "")


def test_the_diff_is_written_file_by_file_as_it_is_made(motion: Path) -> None:
    """--diff never holds the whole diff: each file's goes out before the next is read."""
    from motiontool.cli.fixing import fix_files

    other = motion.with_name("n.motion")
    other.write_bytes(FIXABLE)
    events: list[str] = []

    def robot(path: Path, data: bytes) -> None:
        events.append(f"read {path.name}")

    run = fix_files(
        [Path(motion.name), Path(other.name)],  # the fixture works in their folder
        unsafe=True,
        write=False,
        robot=robot,
        diff=lambda block: events.append(block.split(b"\n")[0].decode()),
    )
    assert events == ["read m.motion", "--- a/m.motion", "read n.motion", "--- a/n.motion"]
    assert run.files == ["m.motion", "n.motion"]


def test_fix_of_standard_input_prints_it_fixed(motion: Path) -> None:
    result = runner.invoke(app, ["validate", "-", "--fix"], input=FIXABLE)
    assert result.exit_code == 0 and result.stdout_bytes == SAFE  # as ruff: the fixed text


def test_text_report_offers_the_fix_under_the_finding(motion: Path) -> None:
    _, out, _ = invoke("validate", "m.motion")
    lines = out.splitlines()
    at = next(i for i, line in enumerate(lines) if "MT203" in line)
    assert lines[at].startswith("m.motion:2:6: warning MT203: ")  # problem matchers unchanged
    assert "   = fix (--fix): write '2'" in lines[at : at + 6]
    assert "   = fix (--fix --unsafe-fixes): remove the blank line" in lines
    assert lines[-1].endswith("; 2 fixable with --fix (1 more with --fix --unsafe-fixes)")


def test_json_report_carries_each_fix_and_conforms(motion: Path) -> None:
    _, out, _ = invoke("validate", "m.motion", "-f", "json")
    doc = json.loads(out)
    assert errors(doc, schemas.load("validate")) == []
    by_code = {d["code"]: d["fix"] for d in doc["files"][0]["diagnostics"]}
    assert by_code["MT203"] == {
        "safe": True,
        "title": "write '2'",
        "edits": [{"line": 2, "column": 6, "end_column": 9, "replacement": ""}],
    }
    assert by_code["MT201"] == {
        "safe": False,
        "title": "remove the blank line",
        "edits": [{"line": 4, "column": 1, "end_column": None, "replacement": None}],
    }
    assert by_code["MT207"] is None


def test_sarif_report_carries_fixes_that_conform(motion: Path) -> None:
    _, out, _ = invoke("validate", "m.motion", "-f", "sarif")
    doc = json.loads(out)
    assert errors(doc, SARIF_SCHEMA) == []
    results = {r["ruleId"]: r for r in doc["runs"][0]["results"]}
    (fix,) = results["MT204"]["fixes"]
    (change,) = fix["artifactChanges"]
    assert change["replacements"] == [
        {
            "deletedRegion": {"startLine": 2, "startColumn": 10, "endColumn": 20},
            "insertedContent": {"text": "*"},
        }
    ]
    assert "unsafe" in results["MT201"]["fixes"][0]["description"]["text"]
    assert "fixes" not in results["MT207"]


FAST = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,A,0,0\n00:00:040,B,2.5,0.1\n00:00:080,C,2.6,-0.1\n00:01:000,D,0,0\n"
"""HeadYaw past the Nao's limit (MT302 on two poses) and far too fast (MT303)."""


def test_unsafe_fixes_clamp_to_the_limit_and_stretch_too_fast_segments(motion: Path) -> None:
    path = motion.parent / "fast.motion"
    path.write_bytes(FAST)
    code, _, err = invoke("validate", "fast.motion", "--robot", "nao", "--fix")
    assert (
        code == 1 and err == "motiontool: nothing to fix\n" and path.read_bytes() == FAST
    )  # unsafe only
    _, _, err = invoke("validate", "fast.motion", "--robot", "nao", "--fix", "--unsafe-fixes")
    assert err.startswith("motiontool: fixed ") and "MT302 x2" in err and "MT303" in err
    fixed = path.read_bytes()
    assert fixed.split(b"\n")[2].endswith(b",2.08567,0.1")  # the model's bound, as spelt there
    assert fixed.split(b"\n")[0] == FAST.split(b"\n")[0]
    _, out, _ = invoke("validate", "fast.motion", "--robot", "nao", "-f", "json")
    codes = {d["code"] for d in json.loads(out)["files"][0]["diagnostics"]}
    assert not codes & {"MT302", "MT303", "MT209"}, codes  # stretched on the 20 ms step
    times = [line.split(b",")[0] for line in fixed.split(b"\n")[1:] if line]
    assert all(int(t.replace(b":", b"")[-3:]) % 20 == 0 for t in times), times


def test_robot_fixes_follow_the_settings(motion: Path) -> None:
    path = motion.parent / "fast.motion"
    path.write_bytes(FAST)
    _, out, _ = invoke(
        "validate", "fast.motion", "--robot", "nao", "--diff", "--unsafe-fixes", "--ignore", "MT302"
    )
    assert "2.08567" not in out and "+00:00:" in out  # stretched, not clamped
    _, out, _ = invoke("validate", "fast.motion", "--robot", "none", "--diff", "--unsafe-fixes")
    assert out == ""  # no robot: nothing to fix
    _, out, _ = invoke(
        "validate",
        "fast.motion",
        "--robot",
        "nao",
        "--checks",
        "limits",
        "--diff",
        "--unsafe-fixes",
    )
    assert "2.08567" in out and "00:00:040" in out  # velocity not checked: not stretched


def test_a_grouped_finding_carries_the_fix_of_each_of_its_poses(motion: Path) -> None:
    path = motion.parent / "fast.motion"
    path.write_bytes(FAST)
    _, out, _ = invoke("validate", "fast.motion", "--robot", "nao", "-f", "json")
    doc = json.loads(out)
    assert errors(doc, schemas.load("validate")) == []
    (limit,) = [d for d in doc["files"][0]["diagnostics"] if d["code"] == "MT302"]
    assert limit["count"] == 2 and limit["fix"]["safe"] is False
    assert [(e["line"], e["replacement"]) for e in limit["fix"]["edits"]] == [
        (3, "2.08567"),
        (4, "2.08567"),
    ]


def test_one_retiming_is_the_fix_of_the_first_too_fast_segment_only(motion: Path) -> None:
    """Every MT303 of a file is fixed by one retiming: it is carried by the first finding, so
    that a report of n too-fast segments stays linear in size (not n retimings of n poses)."""
    lines = [f"{k * 40},P{k},{1.0 if k % 2 else -1.0}" for k in range(12)]
    path = motion.parent / "zigzag.motion"
    path.write_text("#WEBOTS_MOTION,V1.0,HeadPitch\n" + "\n".join(lines) + "\n")
    _, out, _ = invoke("validate", "zigzag.motion", "--robot", "nao", "--no-group", "-f", "json")
    stretches = [d for d in json.loads(out)["files"][0]["diagnostics"] if d["code"] == "MT303"]
    assert len(stretches) == 11
    assert len(stretches[0]["fix"]["edits"]) == 11  # every later pose moves
    assert all(d["fix"] is None for d in stretches[1:])
    _, text, _ = invoke("validate", "zigzag.motion", "--robot", "nao", "--no-group")
    assert text.count("= fix (--fix --unsafe-fixes): stretch") == 1


def test_a_joint_that_crosses_both_limits_many_times_gets_one_finding_a_side(
    motion: Path,
) -> None:
    """HeadPitch (the Nao's range about [-0.67, 0.51] rad) above its limit on 12 separate poses
    and below it on 12 others: grouped, one finding a side (more than MAX_RUNS runs each),
    whose fix clamps exactly that side's cells; the JSON report says how many runs."""
    values = [0.9 if k % 4 == 0 else -0.9 if k % 4 == 2 else 0.0 for k in range(48)]
    lines = [f"{k * 1000},P{k},{v}" for k, v in enumerate(values)]
    path = motion.parent / "dither.motion"
    path.write_text("#WEBOTS_MOTION,V1.0,HeadPitch\n" + "\n".join(lines) + "\n")
    _, out, _ = invoke("validate", "dither.motion", "--robot", "nao", "-f", "json")
    doc = json.loads(out)
    assert errors(doc, schemas.load("validate")) == []
    limits = [d for d in doc["files"][0]["diagnostics"] if d["code"] == "MT302"]
    assert [(d["line"], d["end_line"], d["count"], d["runs"]) for d in limits] == [
        (2, 46, 12, 12),  # above: poses 0, 4, ..., 44
        (4, 48, 12, 12),  # below: poses 2, 6, ..., 46
    ]
    above, below = ({e["replacement"] for e in d["fix"]["edits"]} for d in limits)
    assert len(above) == len(below) == 1 and float(above.pop()) > 0 > float(below.pop())
    assert [len(d["fix"]["edits"]) for d in limits] == [12, 12]
    assert "in 12 runs, lines 2\u201346" in limits[0]["message"]
    code, _, _ = invoke("validate", "dither.motion", "--robot", "nao", "--fix", "--unsafe-fixes")
    assert code == 0


def test_clamps_are_listed_joint_by_joint_each_in_file_order() -> None:
    """clamp_fixes reads the cells pose by pose (a line is tokenised once) but lists the
    clamps joint by joint, each joint's in file order, as the reports show them."""
    from motiontool.kinematics.robot_fixes import clamp_fixes
    from motiontool.kinematics.robots import load_robot

    data = (
        b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n"
        b"0,A,3,1\n"  # both past their upper limits
        b"40,B,0,0\n"
        b"80,C,-3,-1\n"  # both past their lower limits
    )
    fixes = clamp_fixes(read_bytes(data, "m.motion"), load_robot("nao"))
    assert [(f.joint, f.line, f.column) for f in fixes] == [
        ("HeadYaw", 2, 5),
        ("HeadYaw", 4, 6),
        ("HeadPitch", 2, 7),
        ("HeadPitch", 4, 9),
    ]
    assert [f.replacement for f in fixes] == [b"2.08567", b"-2.08567", b"0.514872", b"-0.671952"]


def test_sarif_counts_a_large_fix_as_json_lists_its_edits(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A fix of more than MAX_FIX_EDITS cells is counted, not made, for SARIF's ``fixEdits``:
    the same number as the edits JSON lists, for a grouped run on either side of the limits
    and for one pose."""
    from motiontool.cli.reports.sarif import MAX_FIX_EDITS

    monkeypatch.chdir(tmp_path)
    n = MAX_FIX_EDITS + 100
    values = [3.0] * n + [0.0] * 5 + [-3.0] * (n + 7) + [0.0] * 5 + [2.5] + [0.0] * 5
    rows = "".join(f"{200 * p},P{p},{v},0\n" for p, v in enumerate(values))
    (tmp_path / "big.motion").write_text("#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n" + rows)
    _, out, _ = invoke("validate", "big.motion", "--robot", "nao", "-f", "json")
    edits = [
        len(d["fix"]["edits"])
        for f in json.loads(out)["files"]
        for d in f["diagnostics"]
        if d["code"] == "MT302"
    ]
    _, out, _ = invoke("validate", "big.motion", "--robot", "nao", "-f", "sarif")
    counted = [
        r.get("properties", {}).get("fixEdits")
        or len(r["fixes"][0]["artifactChanges"][0]["replacements"])
        for r in json.loads(out)["runs"][0]["results"]
        if r["ruleId"] == "MT302"
    ]
    assert edits == counted == [n, n + 7, 1]


UNPROVED_MERGE = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadYaw,HeadPitch\n0,P1,0,*,0.1rad\n400,P2,*,0,0\n"
"""HeadYaw named twice, each column with a '*' where the other commands: merged, the columns
would play differently, so --fix keeps them."""


def test_only_fixes_that_apply_are_advertised(motion: Path) -> None:
    path = motion.parent / "dup.motion"
    path.write_bytes(UNPROVED_MERGE)
    _, out, _ = invoke("validate", "dup.motion", "--robot", "none")
    assert out.splitlines()[-1].endswith("; 1 fixable with --fix"), out  # MT203 only
    assert "merge the columns" not in out
    _, out, _ = invoke("validate", "dup.motion", "--robot", "none", "-f", "json")
    fixes = {d["code"]: d["fix"] for d in json.loads(out)["files"][0]["diagnostics"]}
    assert fixes["MT205"] is None and fixes["MT203"] is not None
    assert (
        invoke("validate", "dup.motion", "--fix")[2]
        == "motiontool: fixed 1 finding in 1 file (MT203)\n"
    )
    _, out, _ = invoke("validate", "dup.motion", "--robot", "none")
    assert "fixable" not in out.splitlines()[-1], out
    assert invoke("validate", "dup.motion", "--fix")[2] == "motiontool: nothing to fix\n"


def test_fixable_findings_are_marked_as_ruff_marks_them(motion: Path) -> None:
    _, out, _ = invoke("validate", "m.motion")
    lines = out.splitlines()
    mt203 = next(line for line in lines if " MT203: " in line)
    assert mt203.startswith("m.motion:2:6: warning MT203: [*] "), mt203  # matchers: unchanged
    mt201 = next(line for line in lines if " MT201: " in line)  # unsafe: no mark, as ruff
    assert "[*]" not in mt201 and "[*]" not in next(line for line in lines if " MT207: " in line)
