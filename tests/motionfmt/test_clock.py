"""Webots' playback clock is a C int (issue #15 item 7): where ``elapsed += timestep`` passes
2147483647 ms before the motion ends, the time wraps negative, Webots sends the first pose again
and may never stop. The player, ``validate`` (MT115) and ``sample`` follow it."""

from __future__ import annotations

import ctypes
import itertools
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from oracle import webots_load, webots_play

from motiontool.motionfmt import (
    PlaybackNeverEndsError,
    iter_commands,
    read_bytes,
    sample,
    step_count,
)
from motiontool.motionfmt.clock import _first_multiple_in, clock_overflow, end_step, wrap_int
from motiontool.motionfmt.cscan import INT_MAX

#: The issue's example: Webots sends 0, 0.4657, 0.9313, then 0 at -1294967296 ms, for ever.
ENDLESS = b"#WEBOTS_MOTION,V1.0,A\n0,P1,0\n2147483647,P2,1\n"
#: Wraps at 3e9 ms but lands on 2005032704 ms >= the duration at step 15: it ends after all.
ENDS_LATE = b"#WEBOTS_MOTION,V1.0,A\n0,P1,0\n2000000001,P2,1\n"


def brute_end_step(duration: int, timestep: int, limit: int) -> int | None:
    """Webots' loop, literally: the step at which it stops, None if not within ``limit``."""
    elapsed = 0
    for k in range(limit):
        if elapsed >= duration:
            return k
        elapsed = ctypes.c_int(elapsed + timestep).value
    return None


@settings(max_examples=500, deadline=None)
@given(st.integers(1, 400), st.data())
def test_first_multiple_in_is_the_least_one(m: int, data: st.DataObject) -> None:
    a = data.draw(st.integers(0, 3 * m))
    lo = data.draw(st.integers(0, m - 1))
    hi = data.draw(st.integers(lo, m - 1))
    want = next((k for k in range(m + 1) if lo <= a * k % m <= hi), None)
    assert _first_multiple_in(a, m, lo, hi) == want


@settings(max_examples=300, deadline=None)
@given(st.integers(INT_MAX - 2**24, INT_MAX), st.integers(2**20, INT_MAX))
def test_end_step_is_where_webots_stops(duration: int, timestep: int) -> None:
    got = end_step(duration, timestep)
    limit = 5000
    assert brute_end_step(duration, timestep, limit) == (
        got if got is not None and got < limit else None
    )


def test_wrap_int_is_c_int_arithmetic() -> None:
    for ms in (0, INT_MAX, INT_MAX + 1, 3_000_000_000, -(2**31) - 1, 2**40 + 5):
        assert wrap_int(ms) == ctypes.c_int(ms).value


def test_no_overflow_where_the_motion_ends_in_time() -> None:
    assert clock_overflow(INT_MAX, 1) is None
    assert clock_overflow(2_000_000_000, 1_000_000_000) is None  # ends exactly at step 2
    assert end_step(150, 32) == 5 and step_count(150, 32) == 6


def test_the_endless_example_plays_like_webots() -> None:
    motion = read_bytes(ENDLESS).motion
    assert step_count(motion.duration_ms, 1_000_000_000) is None
    rows = webots_play([0, INT_MAX], [[0.0], [1.0]], 1_000_000_000, max_rows=8)
    first = next(iter_commands(motion, 1_000_000_000, chunk_steps=8))
    assert first.elapsed_ms.tolist() == [e for e, _ in rows]
    assert first.elapsed_ms.tolist()[:4] == [0, 1_000_000_000, 2_000_000_000, -1_294_967_296]
    assert first.targets[:, 0].tolist() == [v[0] for _, v in rows]
    assert [round(v, 4) for v in first.targets[:4, 0].tolist()] == [0.0, 0.4657, 0.9313, 0.0]
    with pytest.raises(PlaybackNeverEndsError, match="never ends"):
        sample(motion, 1_000_000_000)
    bounded = sample(motion, 1_000_000_000, max_steps=5)
    assert bounded.elapsed_ms.tolist() == [e for e, _ in rows[:5]]


def test_a_motion_whose_clock_wraps_and_then_lands_late_ends_there() -> None:
    motion = read_bytes(ENDS_LATE).motion
    overflow = clock_overflow(motion.duration_ms, 1_000_000_000)
    assert overflow is not None and overflow.end_step == 15
    rows = webots_play([0, 2_000_000_001], [[0.0], [1.0]], 1_000_000_000, max_rows=100)
    assert len(rows) == 16 == step_count(motion.duration_ms, 1_000_000_000)
    stream = sample(motion, 1_000_000_000)
    assert stream.elapsed_ms.tolist() == [e for e, _ in rows]
    assert stream.targets[:, 0].tolist() == [v[0] for _, v in rows]
    chunks = list(iter_commands(motion, 1_000_000_000, chunk_steps=3))
    assert [len(c.elapsed_ms) for c in chunks] == [3, 3, 3, 3, 3, 1]


@settings(max_examples=200, deadline=None)
@given(
    st.integers(INT_MAX - 2**28, INT_MAX),
    st.integers(2**24, INT_MAX),
    st.lists(st.floats(-3, 3), min_size=3, max_size=3),
)
def test_wrapping_streams_match_the_oracle(duration: int, timestep: int, v: list[float]) -> None:
    mid = duration // 2
    data = f"#WEBOTS_MOTION,V1.0,A\n0,P,{v[0]!r}\n{mid},Q,{v[1]!r}\n{duration},R,{v[2]!r}\n"
    loaded = webots_load(data.encode())
    motion = read_bytes(data.encode()).motion
    rows = webots_play(loaded.times, loaded.values, timestep, max_rows=300)
    got = list(itertools.islice(iter_commands(motion, timestep, chunk_steps=64), 5))
    elapsed = [e for c in got for e in c.elapsed_ms.tolist()][:300]
    targets = [t for c in got for t in c.targets[:, 0].tolist()][:300]
    assert elapsed == [e for e, _ in rows]
    assert targets == [r[0] for _, r in rows]
    count = step_count(duration, timestep)
    assert count is None or count >= len(rows)
    if count is not None and count < 300:
        assert len(rows) == count


@pytest.mark.parametrize("timestep", [20, 1_000_000_000])
def test_the_three_read_paths_report_the_wrap_alike(timestep: int) -> None:
    from readpaths import differences, read_all

    body = b"".join(b"%d,P,%d\n" % (k * 1000, k % 3) for k in range(40_000))
    data = b"#WEBOTS_MOTION,V1.0,A\n" + body + b"2147483647,Z,1\n"
    results = read_all(data, timestep)
    assert differences(results) == []
    assert [d.code for d in results["exact"].diagnostics][-1] == "MT115"


def test_validate_and_sample_say_it_never_ends(tmp_path: Path) -> None:
    from typer.testing import CliRunner

    from motiontool.cli.app import app

    path = tmp_path / "wraps.motion"
    path.write_bytes(ENDLESS)
    runner = CliRunner()
    out = runner.invoke(app, ["validate", str(path), "--timestep", "1000000000"])
    assert out.exit_code == 1 and f"{path}:3:1: error MT115: " in out.stdout
    assert "the motion never ends" in out.stdout
    out = runner.invoke(app, ["sample", str(path), "-t", "1000000000"])
    assert (out.exit_code, out.stdout) == (2, "")
    assert out.stderr.startswith(f"motiontool: error: {path}:3:1: at a 1000000000 ms time step")
    assert out.stderr.rstrip().endswith("[MT115]")
    late = tmp_path / "late.motion"
    late.write_bytes(ENDS_LATE)
    out = runner.invoke(app, ["sample", str(late), "-t", "1000000000"])
    assert out.exit_code == 0
    times = [int(row.split(",")[0]) for row in out.stdout.splitlines()[1:]]
    assert times[:4] == [0, 1_000_000_000, 2_000_000_000, -1_294_967_296] and len(times) == 16
