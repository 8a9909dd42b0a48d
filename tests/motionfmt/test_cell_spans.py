"""Where a cell is, for many cells at once (``ReadResult.cell_spans``: the lines of a block of
poses tokenised together in numpy where they are plain) against one cell at a time
(``ReadResult.cell_span``, Webots' tokenizer on the line), on files in varied spelling."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import motion_files

from motiontool.motionfmt import read_bytes, read_result

#: What a line may hold that is not plain: each sends its block of poses down the line path.
_ODD = [b",,", b" ", b"\t", b",", b"\r"]


@settings(max_examples=150, deadline=None)
@given(
    data=motion_files(),
    odd=st.lists(st.tuples(st.integers(0, 10**6), st.sampled_from(_ODD)), max_size=3),
    block=st.sampled_from([1, 2, 3, 4096]),
)
def test_cells_found_together_are_where_the_tokenizer_finds_them(
    data: bytes, odd: list[tuple[int, bytes]], block: int
) -> None:
    head = data.index(b"\n") + 1
    for at, piece in sorted(odd, reverse=True):  # after the header only
        cut = head + at % (len(data) - head + 1)
        data = data[:cut] + piece + data[cut:]
    result = read_bytes(data, "f.motion")
    if not result.accepted:
        return
    cells = [
        (p, j) for p in range(len(result.times_ms)) for j in [None, *range(len(result.joints))]
    ]
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(read_result, "_SPAN_BLOCK", block)
        got = list(result.cell_spans([p for p, _ in cells], [j for _, j in cells]))
    assert got == [result.cell_span(p, j) for p, j in cells]


def test_plain_lines_are_found_together() -> None:
    """A block of plain lines is tokenised at once, without the line-by-line tokenizer."""
    rows = "".join(f"{40 * p},P{p},{p / 7!r},-1\n" for p in range(100))
    result = read_bytes(f"#WEBOTS_MOTION,V1.0,A,B\n{rows}".encode(), "f.motion")
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(read_result, "token_spans", None)  # any call fails
        got = list(result.cell_spans([0, 50, 99], [None, 0, 1]))
    assert got[0] == (2, 1, 2)
    assert got == [result.cell_span(0, None), result.cell_span(50, 0), result.cell_span(99, 1)]


def test_a_block_is_tokenised_once_for_cells_asked_one_at_a_time() -> None:
    """A report asks for its findings' cells one call each, in file order: each block of poses
    is tokenised once, not once a cell (a JSON report of 67,000 findings took 48 s so)."""
    rows = "".join(f"{40 * p},P{p},{p / 7!r},-1\n" for p in range(100))
    result = read_bytes(f"#WEBOTS_MOTION,V1.0,A,B\n{rows}".encode(), "f.motion")
    calls = []
    plain = result._plain_spans
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(read_result, "_SPAN_BLOCK", 40)
        mp.setattr(result, "_plain_spans", lambda lo: calls.append(lo) or plain(lo))
        got = [next(result.cell_spans([p], [p % 2])) for p in range(100)]
    assert calls == [0, 40, 80]
    assert got == [result.cell_span(p, p % 2) for p in range(100)]
