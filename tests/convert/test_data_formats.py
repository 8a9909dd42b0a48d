"""CSV and NPZ, both ways: Webots' command stream survives ``motion -> X -> motion`` bit for
bit (corpus, the motion library, Hypothesis files), and bad input is one located error."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT, corpus_params
from hypothesis import given, settings
from strategies import motion_files

from motiontool.errors import MotionSyntaxError, MotionToolError
from motiontool.motionfmt import read_bytes, sample
from motiontool.motionfmt.convert import FORMATS, format_named, format_of
from motiontool.motionfmt.convert.base import ExportOptions
from motiontool.motionfmt.motion import Motion
from motiontool.motionfmt.player import CommandStream

LOSSLESS = ("csv", "npz")
LIBRARY = sorted((ROOT / "motions").rglob("*.motion"))


def _through(motion: Motion, name: str) -> Motion:
    """``motion`` written as ``name``, read back, written as a .motion and read as Webots."""
    fmt, back = format_named(name), format_named("motion")
    assert fmt is not None and back is not None and fmt.write and fmt.read
    assert back.write is not None
    imported = fmt.read(fmt.write(motion, ExportOptions()).data, f"x.{name}")
    text = back.write(imported.motion, ExportOptions()).data
    return read_bytes(text, "back.motion").motion


def _same_stream(a: CommandStream, b: CommandStream) -> None:
    assert np.array_equal(a.elapsed_ms, b.elapsed_ms)
    assert np.array_equal(a.commanded, b.commanded)
    assert np.array_equal(a.targets.view(np.int64), b.targets.view(np.int64))  # bit for bit


def _finite(motion: Motion) -> bool:
    return bool(np.isfinite(motion.values[motion.commanded]).all())


@pytest.mark.parametrize("name", LOSSLESS)
@pytest.mark.parametrize("path", [*corpus_params(), *LIBRARY])
def test_round_trip_keeps_the_stream_bit_identical(path: Path, name: str) -> None:
    motion = read_bytes(path.read_bytes(), str(path)).motion
    if not _finite(motion):
        pytest.skip("a nan/inf command: no writer of motions has a spelling for it")
    back = _through(motion, name)
    assert back.joints == motion.joints
    for step in (1, 20):
        _same_stream(sample(motion, step), sample(back, step))


@pytest.mark.parametrize("name", LOSSLESS)
@settings(max_examples=150, deadline=None)
@given(data=motion_files())
def test_round_trip_of_generated_files(name: str, data: bytes) -> None:
    motion = read_bytes(data, "gen.motion").motion
    back = _through(motion, name)
    _same_stream(sample(motion, 1), sample(back, 1))


def test_the_registry_reads_the_formats_it_names() -> None:
    names = [f.name for f in FORMATS]
    assert len(names) == len(set(names))
    for fmt in FORMATS:
        for suffix in fmt.suffixes:
            assert format_of(f"dir/file{suffix.upper()}") is fmt
        assert fmt.read is not None or fmt.write is not None
    assert format_of("walk.json") is None


def test_csv_spelling() -> None:
    data = b"#WEBOTS_MOTION,V1.0,A,B\n0,P,0.1,*\n40,Q,-0,-9999999.9\n"
    motion = read_bytes(data, "m.motion").motion
    fmt = format_named("csv")
    assert fmt is not None and fmt.write is not None
    out = fmt.write(motion, ExportOptions()).data
    assert out == b"time_ms,A,B\n0,0.1,\n40,-0.0,\n"


@pytest.mark.parametrize(
    ("text", "where", "message"),
    [
        ("time_ms,A\n0,1\n0,2\n", (3, 1), "time 0 ms is not after the previous row's 0 ms"),
        ("time_ms,A\n0,1\n40.5,2\n", (3, 1), "time_ms must be whole milliseconds"),
        ("time_ms,A\n-1,1\n", (2, 1), "time_ms must be whole milliseconds"),
        ("time_ms,A\n2147483648,1\n", (2, 1), "beyond 2147483647 ms"),
        ("time_ms,A,B\n0,1,nan\n", (2, 5), "B = 'nan' is not a finite number"),
        ("time_ms,A,B\n0,1,-Inf\n", (2, 5), "B = '-Inf' is not a finite number"),
        ("time_ms,A,B\n0,1,2rad\n", (2, 5), "expected a number or an empty cell for B, got '2rad'"),
        ("time_ms,A,B\n0,1\n", (2, 4), "2 cells where the header has 3"),
        ("time_ms,A,B\n0,1,2,3\n", (2, 7), "4 cells where the header has 3"),
        ("time,A\n0,1\n", (1, 1), "expected 'time_ms' as the first column, got 'time'"),
        ("time_ms,A,\n0,1,2\n", (1, 11), "joint name '' cannot be a motion's"),
        ('time_ms,"A\n', (1, 9), "unterminated quoted cell"),
        ("time_ms,A\n0,1\n\n40,2\n", (3, 1), "blank line"),
        ("time_ms,A\n", (2, 1), "no rows"),
        ("time_ms,A\n0,1e999\n", (2, 3), "too large"),
    ],
)
def test_bad_csv_is_one_located_error(text: str, where: tuple[int, int], message: str) -> None:
    fmt = format_named("csv")
    assert fmt is not None and fmt.read is not None
    with pytest.raises(MotionSyntaxError) as caught:
        fmt.read(text.encode(), "bad.csv")
    assert (caught.value.line, caught.value.column) == where
    assert message in str(caught.value)
    assert str(caught.value).startswith(f"bad.csv:{where[0]}:{where[1]}: ")


def test_csv_reads_quotes_crlf_a_bom_and_star() -> None:
    fmt = format_named("csv")
    assert fmt is not None and fmt.read is not None
    got = fmt.read(b'\xef\xbb\xbf"time_ms","A"\r\n0,*\r\n40," 0.5"\r\n', "q.csv")
    assert got.motion.joints == ("A",)
    assert got.motion.commanded.tolist() == [[False], [True]]
    assert got.motion.values[1, 0] == 0.5
    assert got.cells is not None and got.cells[1, 0].tolist() == [3, 4]


def _npz(**arrays: object) -> bytes:
    out = io.BytesIO()
    np.savez(out, **arrays)  # type: ignore[arg-type]
    return out.getvalue()


GOOD = {
    "times_ms": np.array([0, 40]),
    "names": np.array(["A"]),
    "positions": np.array([[0.1], [np.nan]]),
    "commanded": np.array([[True], [False]]),
}


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"times_ms": None}, "has no array 'times_ms'"),
        ({"times_ms": np.array([40, 0])}, "times_ms must strictly increase"),
        ({"names": np.array([1])}, "array 'names' must be 1-D strings"),
        ({"positions": np.array([[0.1], [0.2], [0.3]])}, "has shape (3, 1), expected (2, 1)"),
        ({"commanded": np.array([[True], [True]])}, "A at 40 ms is commanded but not a finite"),
        ({"names": np.array(["A,B"])}, "joint 'A,B' cannot be written"),
        ({"names": np.array([{"a": 1}], dtype=object)}, "cannot read 'bad.npz' as a .npz file"),
    ],
)
def test_bad_npz_names_the_array(change: dict[str, object], message: str) -> None:
    arrays = {k: v for k, v in {**GOOD, **change}.items() if v is not None}
    fmt = format_named("npz")
    assert fmt is not None and fmt.read is not None
    with pytest.raises(MotionToolError, match=None) as caught:
        fmt.read(_npz(**arrays), "bad.npz")
    assert message in str(caught.value)
    assert "bad.npz" in str(caught.value)


def test_npz_holds_the_four_arrays() -> None:
    motion = read_bytes(b"#WEBOTS_MOTION,V1.0,A,B\n0,P,0.1,*\n40,Q,0.2,0.3\n", "m").motion
    fmt = format_named("npz")
    assert fmt is not None and fmt.write is not None
    with np.load(io.BytesIO(fmt.write(motion, ExportOptions()).data)) as npz:
        assert npz["times_ms"].dtype == np.int64 and npz["times_ms"].tolist() == [0, 40]
        assert npz["names"].tolist() == ["A", "B"]
        assert npz["commanded"].tolist() == [[True, False], [True, True]]
        assert np.isnan(npz["positions"][0, 1]) and npz["positions"][1, 1] == 0.3
        assert npz["pose_names"].tolist() == ["P", "Q"]
