"""The exact, fast and bulk reading paths agree, on pose times above all: Webots reads a time
with C ``int`` arithmetic that wraps (``m * 60000 + s * 1000 + ms``), and every path must wrap,
or step aside to the exact path, exactly where it does."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from oracle import webots_load
from readpaths import differences, read_all
from strategies import motion_files, timed_files

from motiontool.motionfmt import read_bytes, sample

HEADER = b"#WEBOTS_MOTION,V1.0,A\n"


@pytest.mark.parametrize(
    ("body", "accepted", "times"),
    [
        # 35792 min = 2147520000 ms wraps negative: not after 0 ms, Webots rejects the file.
        (b"00:00:000,P1,0\n35792:00:000,P2,1\n", False, [0]),
        # 71582:47:296 = 2**32 ms wraps to 0: then 400 ms is after it, Webots accepts.
        (b"71582:47:296,P1,0\n00:00:400,P2,1\n", True, [0, 400]),
        # 71582:47:396 = 2**32 + 100 ms wraps to 100 ms: a 100 ms motion, not 4294967396 ms.
        (b"00:00:000,P1,0\n71582:47:396,P2,1\n", True, [0, 100]),
        # 2**32 - 1 ms wraps to -1, Webots' 'undefined time': rejected.
        (b"00:00:000,P1,0\n71582:47:295,P2,1\n", False, [0]),
        # The largest time that does not wrap.
        (b"00:00:000,P1,0\n35791:23:647,P2,1\n", True, [0, 2**31 - 1]),
    ],
    ids=["wraps-negative", "wraps-to-0", "wraps-to-100", "wraps-to-minus-1", "int-max"],
)
def test_wrapping_times_read_as_webots_reads_them(
    body: bytes, accepted: bool, times: list[int]
) -> None:
    data = HEADER + body
    results = read_all(data)
    assert differences(results) == []
    for result in results.values():
        assert result.accepted is accepted
        assert list(result.times_ms) == times
    oracle = webots_load(data)  # glibc's own sscanf, in C int arithmetic
    assert oracle.ok is accepted
    if accepted:
        assert oracle.times == times


def test_bulk_path_wraps_a_large_clean_file() -> None:
    rows = b"".join(b"00:00:%03d,P%d,0.5\n" % (t, t) for t in range(0, 1000, 10))
    data = HEADER + rows + b"71582:47:396,Last,1\n"  # wraps to 100 ms: not after 990 ms
    results = read_all(data)
    assert differences(results) == []
    assert not results["bulk"].accepted
    assert results["bulk"].rejected_at is not None and results["bulk"].rejected_at.line == 102


@pytest.mark.parametrize(
    "header",
    [b"\xef\xbb\xbf#WEBOTS_MOTION,V1.0,A\n", b"#WEBOTS_MOTION,V1.1,A\n"],
    ids=["bom", "v1.1"],
)
def test_bulk_path_stays_out_of_a_file_whose_header_webots_rejects(header: bytes) -> None:
    # Found by dev/fuzz.py: the bulk path read the clean body of a rejected file and added
    # MT206/MT209 warnings that the exact path (rightly) does not give once Webots stops.
    data = header + b"".join(b"00:01:%03d,P%d,0.5\n" % (t, t) for t in range(0, 1000, 10))
    results = read_all(data, 7)
    assert differences(results) == []
    assert [d.code for d in results["bulk"].diagnostics] in (["MT101"], ["MT102"])


def test_sample_of_a_wrapped_time_ends() -> None:
    data = HEADER + b"00:00:000,P1,0\n71582:47:396,P2,1\n"
    motion = read_bytes(data).motion
    assert motion.duration_ms == 100
    assert sample(motion, 50).elapsed_ms.tolist() == [0, 50, 100]


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(timed_files())
def test_paths_agree_on_times_with_1_to_5_digit_fields(data: bytes) -> None:
    results = read_all(data)
    assert differences(results) == []
    oracle = webots_load(data)
    assert results["exact"].accepted == oracle.ok
    if oracle.ok:
        assert list(results["exact"].times_ms) == oracle.times


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(motion_files(non_finite=True))
def test_paths_agree_on_non_finite_cells(data: bytes) -> None:
    assert differences(read_all(data)) == []
