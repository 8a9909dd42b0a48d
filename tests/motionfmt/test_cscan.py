"""The C-library emulation against the C library itself (glibc through ctypes)."""

from __future__ import annotations

import math
import struct

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from oracle import c_scan_double, c_scan_time, strtok

from motiontool.motionfmt import cscan
from motiontool.motionfmt.cscan import scan_double, scan_time
from motiontool.motionfmt.lines import token_spans

NUMBERISH = st.text(alphabet="0123456789+-.eEpPxXaAfFiInNtTyY *\t_", max_size=12)


def _same(a: float | None, b: float | None) -> bool:
    if a is None or b is None:
        return a is b
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    return struct.pack("<d", a) == struct.pack("<d", b)  # bit for bit, -0.0 included


@pytest.mark.parametrize(
    "token",
    [
        "2rad", "1e+", "1e", ".5", "5.", "0x10", "0x", "0x.", "0x1p", "-Infinity", "infinit",
        "infx", "nanx", "nan(12)", " 1.5", "*", " ", "-", ".", "e5", "1.5.3", "1E2", "-0", "0e5",
        "1e400", "1e-400", "0x1p99999", "+.5e-3x", "1_0", "\t-2", "INFINITY", "-nan",
        "4.9406564584124654e-324", "0.1", "-9999999.9", "1,5",
    ],
)  # fmt: skip
def test_known_tokens(token: str) -> None:
    raw = token.encode()
    got = scan_double(raw)
    assert _same(got.value if got else None, c_scan_double(raw))


@settings(max_examples=3000, deadline=None)
@given(NUMBERISH)
def test_scan_double_matches_glibc(token: str) -> None:
    raw = token.encode()
    got = scan_double(raw)
    assert _same(got.value if got else None, c_scan_double(raw))


@pytest.mark.slow  # 3000 examples: 11-13 s on this 2-core machine
@settings(max_examples=3000, deadline=None)
@given(
    NUMBERISH
    | st.floats(allow_nan=False).map(repr)
    | st.from_regex(r"[+-]?(\d{1,30}\.?\d{0,30}|\.\d{1,30})([eE][+-]?\d{1,4})?", fullmatch=True)
)
def test_a_plain_decimal_reads_as_the_walk_reads_it(token: str) -> None:
    """The shortcut for a cell that is a plain decimal alone gives the value (bit for bit) and
    the end that glibc's walk gives (the end says where trailing text starts: MT203)."""
    raw = token.encode()
    got, walked = scan_double(raw), cscan._scan_double(raw)
    if got is None or walked is None:
        assert got is walked
    else:
        assert got.end == walked.end and _same(got.value, walked.value)


@settings(max_examples=500, deadline=None)
@given(st.floats(allow_nan=False))
def test_repr_of_any_double_reads_back(x: float) -> None:
    got = scan_double(repr(x).encode())
    assert got is not None and _same(got.value, x)


@settings(max_examples=2000, deadline=None)
@given(st.text(alphabet="0123456789: +-.", max_size=14))
def test_scan_time_matches_glibc(token: str) -> None:
    raw = token.encode()
    got = scan_time(raw)
    assert (got.ms if got else None) == c_scan_time(raw)


def test_scan_time_overflow_wraps_like_c() -> None:
    assert scan_time(b"4294967297") == (1, 4294967297)
    assert scan_time(b"4294967295") is None  # wraps to -1, Webots' "undefined time"


@settings(max_examples=500, deadline=None)
@given(st.lists(st.sampled_from([b",", b"a", b"1", b".", b" ", b"\r", b"\n", b"\0", b"\xff"])))
def test_token_spans_are_the_tokens_strtok_finds(parts: list[bytes]) -> None:
    """The tokeniser (its regex path with CR or LF, its split path without) cuts a piece as
    the oracle's C-like strtok loop does."""
    piece = b"".join(parts)
    assert [piece[a:b] for a, b in token_spans(piece)] == strtok(piece)
