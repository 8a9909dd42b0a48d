"""The bulk (pyarrow) fast path reads exactly what the line-by-line path reads, or steps aside."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import corpus_params, golden
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import motion_files

from motiontool.motionfmt import reader

pytest.importorskip("pyarrow", reason="the bulk path needs pyarrow")


def assert_same(data: bytes) -> None:
    bulk = reader._Reader(data, "f.motion", 20, bulk_min_bytes=0).read()
    exact = reader._Reader(data, "f.motion", 20, bulk_min_bytes=1 << 62).read()
    assert bulk.diagnostics == exact.diagnostics
    assert bulk.accepted == exact.accepted
    assert bulk.times_ms == exact.times_ms
    assert bulk.pose_names == exact.pose_names
    assert bulk.pose_lines == exact.pose_lines
    a = np.asarray(bulk.rows, dtype=np.float64)
    b = np.asarray(exact.rows, dtype=np.float64)
    assert a.shape == b.shape and a.tobytes() == b.tobytes()  # bit for bit


@pytest.mark.parametrize("path", corpus_params())
def test_corpus(path: Path) -> None:
    assert_same(path.read_bytes())


@pytest.mark.parametrize("path", golden("valid") + golden("invalid"), ids=lambda p: p.stem)
def test_golden(path: Path) -> None:
    assert_same(path.read_bytes())


@settings(max_examples=150, deadline=None)
@given(
    data=motion_files(),
    junk=st.sampled_from([b"", b" ", b"1e", b"+", b"\t", b"0x1", b"nan", b"\xe9", b"1.5.", b"inf"]),
    draw=st.data(),
)
def test_generated_and_mutated(data: bytes, junk: bytes, draw: st.DataObject) -> None:
    assert_same(data)
    pos = draw.draw(st.integers(data.index(b"\n") + 1, len(data)))
    assert_same(data[:pos] + junk + data[pos:])


def test_bulk_path_is_taken_on_a_clean_file() -> None:
    from motiontool.motionfmt import _bulk

    rows = "\n".join(f"{t},P{t},{t / 1000!r},-1.25" for t in range(0, 4000, 40))
    data = f"#WEBOTS_MOTION,V1.0,A,B\n{rows}\n".encode()
    body = data[data.index(b"\n") + 1 :]
    got = _bulk.read_clean_body(body, 2, reader.NO_VALUE_MARKER, 4094)
    assert got is not None and got[0][:3] == [0, 40, 80] and got[2].shape == (100, 2)
    assert_same(data)


@pytest.mark.parametrize("block", [4096, 1 << 20])
def test_a_file_read_a_block_at_a_time_reads_as_the_exact_path(
    block: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Parsed in record batches (a block of the file each) into arrays of their final size:
    batch boundaries change nothing, bit for bit."""
    from motiontool.motionfmt import _bulk

    monkeypatch.setattr(_bulk, "_BLOCK", block)
    rng = np.random.default_rng(3)
    rows = "\n".join(
        f"{t // 60000:02d}:{t // 1000 % 60:02d}:{t % 1000:03d},Pose{t},"
        + ",".join(repr(round(float(v), 6)) for v in rng.uniform(-2, 2, 5))
        for t in range(0, 40 * 3000, 40)
    )
    data = f"#WEBOTS_MOTION,V1.0,A,B,C,D,E\n{rows}".encode()  # no final newline
    got = _bulk.read_clean_body(data, 5, reader.NO_VALUE_MARKER, 4094, start=data.index(b"\n") + 1)
    assert got is not None and len(got[0]) == 3000 and got[2].shape == (3000, 5)
    assert_same(data)
    assert_same(data + b"\n")
    late = data.replace(b"01:59:960", b"01:59:900")  # the last time no longer increases
    assert _bulk.read_clean_body(late, 5, reader.NO_VALUE_MARKER, 4094, start=30) is None
    assert_same(late)
