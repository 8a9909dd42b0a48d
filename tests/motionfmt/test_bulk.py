"""The bulk path (numpy's ``loadtxt``) reads exactly what the line-by-line path reads, or steps
aside."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import corpus_params, golden
from hypothesis import example, given, settings
from hypothesis import strategies as st
from strategies import motion_files

from motiontool.motionfmt import reader


def assert_same(data: bytes) -> None:
    """The bulk path reads ``data`` as the line-by-line path does, keeping its values or not
    (read again when asked for)."""
    exact = reader._Reader(data, "f.motion", 20, bulk_min_bytes=1 << 62).read()
    for keep in (True, False):
        bulk = reader._Reader(data, "f.motion", 20, bulk_min_bytes=0, keep_values=keep).read()
        assert bulk.diagnostics == exact.diagnostics
        assert bulk.accepted == exact.accepted
        assert bulk.times_ms == exact.times_ms
        assert bulk.pose_names == exact.pose_names
        assert list(bulk.pose_lines) == list(exact.pose_lines)
        a, b = bulk.values, exact.values
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
    assert got is not None and got[0][:3].tolist() == [0, 40, 80] and got[2].shape == (100, 2)
    assert_same(data)


@pytest.mark.parametrize("block", [4096, 1 << 20])
def test_a_file_read_a_block_at_a_time_reads_as_the_exact_path(
    block: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Parsed a block of lines at a time into arrays of their final size: block boundaries
    change nothing, bit for bit."""
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


@pytest.mark.parametrize(
    ("piece", "bulk_reads_it"),
    [
        (b"80,,1,2\n", False),  # an empty name: Webots reads 1 as the name
        (b"\n", False),  # a blank line ends the motion
        (b"80,P,1,2,\n", False),  # a trailing comma
        (b",80,P,1,2\n", False),  # a leading comma
        (b"80,P,1,,2\n", False),  # an empty cell between values
        (b"80,P\x00Q,1,2\n", False),  # a NUL ends the line for Webots
        (b"80,P,1,2\r120,Q,1,2\n", False),  # a lone CR: one line for Webots, two for loadtxt
        (b"80,P,1,2\r\r\n", False),
        (b"80,P,*,2\n", False),
        (b"80,P*,1,2\n", False),  # harmless, but '*' anywhere takes the exact path
        (b"80,P,1,2\r\n", True),  # CRLF
        (b"80,P Q,1 ,\t2\n", True),  # spaces and tabs stay inside tokens
        (b"80,P,1,2,3\n", False),  # a cell too many (loadtxt reads the columns it is given)
        (b"80,P,1\n", False),  # a cell too few
        (b"80,P,1_0,2\n", False),  # Python's float reads 10, C reads 1
        (b"80,P_1,1,2\n", True),  # '_' in a name
        (b"80,P,\x1c1,2\n", False),  # whitespace to loadtxt, not to C
        (b"80,P,1\xa0,2\n", False),
        (b"80,P,1\x85,2\n", False),
        (b"80,P\xc3\xa0,1,2\n", False),  # "\xa0" in a name (à): the exact path
        (b"80,P\xc3\xa8,1,2\n", True),  # UTF-8 in a name
        (b"80,P\xe8,1,2\n", False),  # not UTF-8: the exact path
        (b"80,P,1e2,-.5\n", True),
        (b"80,P,0x1p3,2\n", False),  # C reads hexadecimal, Python does not
        (b"80," + b"P" * 4087 + b",1,2\n", True),  # 4094 bytes: one fgets piece
        (b"80," + b"P" * 4088 + b",1,2\n", False),  # 4095 bytes: Webots reads it in pieces
    ],
)
def test_what_only_the_exact_path_reads_right_steps_aside(
    piece: bytes, bulk_reads_it: bool
) -> None:
    from motiontool.motionfmt import _bulk

    head = b"#WEBOTS_MOTION,V1.0,A,B\n0,P0,0,0\n40,P1,0.5,-0.5\n"
    data = head + piece + b"160,P3,1,1\n"
    got = _bulk.read_clean_body(data, 2, reader.NO_VALUE_MARKER, 4094, start=data.index(b"\n") + 1)
    assert (got is not None) == bulk_reads_it
    assert_same(data)


def _times_reference(tokens: list[bytes], fields: int | None) -> tuple[list[int], int] | None:
    """What ``_bulk._times`` must answer, token by token: every token 1 to 5 digits, up to
    twice ':' and 1 to 5 digits, all with the same number of ':'."""
    import re

    if not tokens:
        return [], fields or 0
    if not all(re.fullmatch(rb"[0-9]{1,5}(:[0-9]{1,5}){0,2}", t) for t in tokens):
        return None
    k = tokens[0].count(b":") if fields is None else fields
    if any(t.count(b":") != k for t in tokens):
        return None
    scale = [60000, 1000, 1][-(k + 1) :]
    return [sum(int(f) * s for f, s in zip(t.split(b":"), scale, strict=True)) for t in tokens], k


_TIME_TOKENS = st.one_of(
    st.sampled_from([b"00:00:040", b"1:500", b"1500", b"99999", b"0:0:0", b"00:00:1500"]),
    st.text("0123456789:", min_size=1, max_size=8).map(str.encode),
    st.text("0123456789", min_size=4, max_size=7).map(str.encode),
    st.binary(max_size=6),
)


@settings(max_examples=400, deadline=None)
@given(
    tokens=st.lists(_TIME_TOKENS, max_size=4),
    fields=st.sampled_from([None, 0, 1, 2]),
    offset=st.integers(0, 2),
)
@example(tokens=[b"123456"], fields=None, offset=0)
@example(tokens=[b"0:0:0", b"0", b"0:0"], fields=None, offset=0)
@example(tokens=[b"1:2:3:4"], fields=None, offset=0)
@example(tokens=[b"1:2:3:4", b"5"], fields=None, offset=0)
@example(tokens=[b"0::5", b"1:2:3"], fields=None, offset=1)
def test_time_tokens_read_as_the_pattern_says(
    tokens: list[bytes], fields: int | None, offset: int
) -> None:
    """The times of tokens (after other bytes, as a block's may be) are those of the pattern
    Webots' ``str_to_time`` accepts, or None."""
    from motiontool.motionfmt import _bulk

    raw = np.frombuffer(b"junk" * offset + b"".join(tokens), dtype=np.uint8)
    offsets = np.cumsum([4 * offset, *(len(t) for t in tokens)], dtype=np.int64)
    got = _bulk._times(offsets, raw, fields)
    want = _times_reference(tokens, fields)
    assert (None if got is None else (got[0].tolist(), got[1])) == want


def test_blocks_whose_times_are_written_differently_take_the_exact_path(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Webots reads ``m:s:ms`` and ``ms`` times alike; the bulk path reads one way per file."""
    from motiontool.motionfmt import _bulk

    monkeypatch.setattr(_bulk, "_BLOCK", 4096)
    # 1,001 lines m:s:ms then 1,000 lines ms: many blocks, the later ones in ms.
    early = "\n".join(f"00:{t // 1000:02d}:{t % 1000:03d},P,0.5" for t in range(0, 40040, 40))
    late = "\n".join(f"{t},PP,0.5000" for t in range(40040, 80040, 40))
    data = f"#WEBOTS_MOTION,V1.0,A\n{early}\n{late}\n".encode()
    assert _bulk.read_clean_body(data, 1, reader.NO_VALUE_MARKER, 4094, start=22) is None
    same = data.replace(b"00:", b"").replace(b":", b"")  # every time in ms
    got = _bulk.read_clean_body(same, 1, reader.NO_VALUE_MARKER, 4094, start=22)
    assert got is not None and got[0][-1] == 80000 and len(got[0]) == 2001
    assert_same(data)
    assert_same(same)


def test_a_read_that_keeps_no_values_reads_them_again_when_asked() -> None:
    """``keep_values=False`` (a syntax check): the values are checked but not held; asked for,
    they are read again, bit for bit; the read pickles either way."""
    import pickle

    rng = np.random.default_rng(5)
    rows = "\n".join(
        f"{t},P{t}," + ",".join(repr(float(v)) for v in rng.uniform(-2, 2, 3))
        for t in range(0, 40 * 500, 40)
    )
    data = f"#WEBOTS_MOTION,V1.0,A,B,C\n{rows}\n".encode()
    kept = reader._Reader(data, "f.motion", None, bulk_min_bytes=0).read()
    lazy = reader._Reader(data, "f.motion", None, bulk_min_bytes=0, keep_values=False).read()
    assert len(lazy._cells) == 0 and lazy._cells_later is not None  # nothing held
    assert lazy.times_ms == kept.times_ms and lazy.pose_names == kept.pose_names
    again = pickle.loads(pickle.dumps(lazy))
    assert lazy.values.tobytes() == kept.values.tobytes()
    assert lazy._cells_later is None  # read once
    assert again.values.tobytes() == kept.values.tobytes()
    bad = data.replace(b",P40,", b",P40,*,")  # not clean: read line by line, values kept
    assert reader.read_bytes(bad, keep_values=False)._cells_later is None


def test_a_syntax_only_validate_keeps_no_values() -> None:
    """``validate_bytes`` without checks (``--robot none``) holds a large clean file's bytes
    but not its values; with a check it reads them once."""
    from motiontool.kinematics.checks import Limits
    from motiontool.kinematics.robots import resolve_robot
    from motiontool.motionfmt import validate_bytes

    rows = "\n".join(
        f"{t // 60000}:{t // 1000 % 60}:{t % 1000},P,{(t % 997) / 1000!r},-0.25"
        for t in range(0, 40 * 60_000, 40)
    )
    data = f"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n{rows}\n".encode()
    assert len(data) >= reader.BULK_MIN_BYTES
    syntax = validate_bytes(data, "f.motion").read
    assert syntax._cells_later is not None and len(syntax._cells) == 0
    checked = validate_bytes(data, "f.motion", checks=[Limits(resolve_robot("nao"))]).read
    assert checked._cells_later is None and len(checked.cells) == 2 * 60_000
    assert syntax.values.tobytes() == checked.values.tobytes()
