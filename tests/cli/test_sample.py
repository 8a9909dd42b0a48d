"""``motiontool sample``: CSV through csv.writer, NaN commands vs no command, JSON, size cap."""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path

from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.cli.sample import MAX_CELLS

runner = CliRunner()

NAN_FILE = b"#WEBOTS_MOTION,V1.0,A,B,C,D\n0,P1,nan,inf,*,1\n100,P2,1,inf,-9999999.9,-inf\n"


def invoke(*args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, list(args))
    return result.exit_code, result.stdout, result.stderr


def test_csv_prints_nan_where_webots_sends_nan_and_empty_where_nothing(tmp_path: Path) -> None:
    path = tmp_path / "nan.motion"
    path.write_bytes(NAN_FILE)
    code, out, _ = invoke("sample", str(path), "-t", "50")
    assert code == 0
    # 50 ms: nan + ..., inf + 50 * (inf - inf) / 100 = nan, 1 + 50 * (-inf - 1) / 100 = -inf.
    assert out == "time_ms,A,B,C,D\n0,nan,inf,,1.0\n50,nan,nan,,-inf\n100,1.0,inf,,-inf\n"


def test_json_null_for_no_command_and_strings_for_non_finite(tmp_path: Path) -> None:
    path = tmp_path / "nan.motion"
    path.write_bytes(NAN_FILE)
    code, out, _ = invoke("sample", str(path), "-t", "50", "-f", "json")
    assert code == 0
    doc = json.loads(out)  # strict JSON: no bare NaN / Infinity
    assert doc["targets"] == [
        ["nan", "inf", None, 1.0],
        ["nan", "nan", None, "-inf"],
        [1.0, "inf", None, "-inf"],
    ]
    assert "null = no command" in doc["units"]["targets"]


def test_csv_round_trips_through_csv_reader(tmp_path: Path) -> None:
    path = tmp_path / "q.motion"
    path.write_bytes(b'#WEBOTS_MOTION,V1.0,He said "hi",Head Yaw\n0,P,0.1,*\n40,Q,0.3,2\n')
    code, out, _ = invoke("sample", str(path), "-t", "20")
    assert code == 0
    rows = list(csv.reader(io.StringIO(out)))
    assert rows[0] == ["time_ms", 'He said "hi"', "Head Yaw"]
    middle = repr(0.1 + 20 * (0.3 - 0.1) / 40)
    assert rows[1:] == [["0", "0.1", ""], ["20", middle, ""], ["40", "0.3", "2.0"]]


def test_a_huge_stream_is_refused_before_it_is_built(tmp_path: Path) -> None:
    path = tmp_path / "a.motion"
    path.write_bytes(b"#WEBOTS_MOTION,V1.0,A,B\n0,P,0,0\n200,Q,1,1\n")
    code, out, err = invoke("sample", "-t", "1", "--loop", "1000000", str(path))
    assert (code, out) == (2, "")
    assert err == (
        f"motiontool: error: {path}: sampling 200 ms every 1 ms for 1000000 cycle(s) gives"
        f" 201000000 steps x 2 joints = 402000000 cells, above the limit of {MAX_CELLS}; use a"
        " larger --timestep or fewer --loop cycles\n"
    )


def test_format_accepts_only_csv_and_json(tmp_path: Path) -> None:
    path = tmp_path / "a.motion"
    path.write_bytes(b"#WEBOTS_MOTION,V1.0,A\n0,P,0\n")
    code, _, err = invoke("sample", str(path), "-f", "text")
    assert code == 2 and "'text' is not one of 'csv', 'json'" in err
    code, out, _ = invoke("sample", "--help")
    assert code == 0 and "<csv|json>" in out and "-t, --timestep" in out
