"""``motiontool sample``: CSV through csv.writer, NaN commands vs no command, JSON, streamed in
chunks (the first rows out at once, memory flat), an opt-in --max-rows guard."""

from __future__ import annotations

import contextlib
import csv
import io
import json
import math
import tempfile
from collections.abc import Iterator
from pathlib import Path
from unittest import mock

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from strategies import motion_files
from typer.testing import CliRunner

from motiontool.cli import sample as sample_module
from motiontool.cli.app import app
from motiontool.motionfmt import CommandStream, read_bytes, sample

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


def test_max_rows_refuses_a_longer_stream_before_writing(tmp_path: Path) -> None:
    path = tmp_path / "a.motion"
    path.write_bytes(b"#WEBOTS_MOTION,V1.0,A,B\n0,P,0,0\n200,Q,1,1\n")
    out_file = tmp_path / "out.csv"
    args = ("sample", "-t", "1", "--loop", "1000000", str(path), "-o", str(out_file))
    code, out, err = invoke(*args, "--max-rows", "1000")
    assert (code, out) == (2, "") and not out_file.exists()
    assert err == (
        f"motiontool: error: {path}: sampling 200 ms every 1 ms for 1000000 cycle(s) gives"
        " 201000000 rows, above --max-rows 1000; use a larger --timestep, fewer --loop cycles"
        " or a larger --max-rows\n"
    )
    code, _, _ = invoke("sample", "-t", "1", "--loop", "5", str(path), "--max-rows", "1005")
    assert code == 0


def reference_csv(stream: CommandStream) -> str:
    """The whole stream through csv.writer at once: what the streamed output must equal."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(["time_ms", *stream.joints])
    for t, values, sent in zip(
        stream.elapsed_ms.tolist(), stream.targets.tolist(), stream.commanded.tolist(), strict=True
    ):
        writer.writerow([t, *(repr(v) if s else "" for v, s in zip(values, sent, strict=True))])
    return buffer.getvalue()


def reference_json_targets(stream: CommandStream) -> list[list[object]]:
    return [
        [
            (v if math.isfinite(v) else repr(v)) if s else None
            for v, s in zip(row, sent, strict=True)
        ]
        for row, sent in zip(stream.targets.tolist(), stream.commanded.tolist(), strict=True)
    ]


@settings(max_examples=40, deadline=None, suppress_health_check=list(HealthCheck))
@given(motion_files(), st.integers(1, 40), st.integers(1, 7), st.booleans(), st.integers(1, 3))
def test_the_streamed_output_is_the_whole_stream_chunk_by_chunk(
    data: bytes, timestep: int, chunk_cells: int, reverse: bool, loops: int
) -> None:
    """Chunks of a few cells (many chunks per file) give, byte for byte, what one pass over
    the whole stream gives: CSV as csv.writer writes it, JSON that parses to the same values."""
    result = read_bytes(data)
    assume(result.accepted and result.motion.n_joints > 0)
    motion = result.motion
    assume((motion.duration_ms // timestep + 1) * loops < 5000)
    whole = sample(motion, timestep, reverse=reverse, loops=loops)
    with (
        tempfile.TemporaryDirectory() as tmp,
        mock.patch.object(sample_module, "CHUNK_CELLS", chunk_cells),
    ):
        path = Path(tmp) / "m.motion"
        path.write_bytes(data)
        extra = ["--reverse"] if reverse else []
        args = ["sample", str(path), "-t", str(timestep), "--loop", str(loops), *extra]
        code, out, err = invoke(*args)
        assert (code, err) == (0, "")
        assert out == reference_csv(whole)
        code, out, err = invoke(*args, "-f", "json")
        assert (code, err) == (0, "")
        doc = json.loads(out)
        assert doc["elapsed_ms"] == whole.elapsed_ms.tolist()
        assert doc["targets"] == reference_json_targets(whole)
        assert out.count("\n") == 1


def test_the_first_rows_come_before_the_stream_is_computed(tmp_path: Path) -> None:
    """A 24-day motion at 1 ms: the first chunk is written while the rest is not computed yet
    (the sink sees a write before the player is asked for its second chunk)."""
    path = tmp_path / "long.motion"
    path.write_bytes(b"#WEBOTS_MOTION,V1.0,A,B,C\n0,P,0,0,0\n2073600000,Q,1,1,1\n")
    events: list[str] = []
    real = sample_module.iter_commands

    def spy(*args: object, **kwargs: object) -> Iterator[CommandStream]:
        for k, chunk in enumerate(real(*args, **kwargs)):  # type: ignore[arg-type]
            events.append(f"chunk {k}")
            if k == 3:
                raise KeyboardInterrupt  # stop the 2-billion-row stream here
            yield chunk

    writes = io.BytesIO()

    class Sink:
        def write(self, data: bytes) -> None:
            events.append("write")
            writes.write(data)

    @contextlib.contextmanager
    def fake_output(_: object) -> Iterator[Sink]:
        yield Sink()

    with (
        mock.patch.object(sample_module, "iter_commands", spy),
        mock.patch.object(sample_module, "open_output", fake_output),
        pytest.raises(KeyboardInterrupt),
    ):
        sample_module.sample_command(path, timestep=1, format=sample_module.SampleFormat.csv)
    assert events[:4] == ["write", "chunk 0", "write", "chunk 1"]
    rows = writes.getvalue().decode().splitlines()
    assert rows[1] == "0,0.0,0.0,0.0" and len(rows) == 1 + 3 * (sample_module.CHUNK_CELLS // 3)


def test_format_accepts_only_csv_and_json(tmp_path: Path) -> None:
    path = tmp_path / "a.motion"
    path.write_bytes(b"#WEBOTS_MOTION,V1.0,A\n0,P,0\n")
    code, _, err = invoke("sample", str(path), "-f", "text")
    assert code == 2 and "'text' is not one of 'csv', 'json'" in err
    code, out, _ = invoke("sample", "--help")
    assert code == 0 and "<csv|json>" in out and "-t, --timestep" in out
