"""The reader and the player against the plain-loop oracle: the corpus, the golden files, and
generated files. Targets must be bit-identical to Webots' own player."""

from __future__ import annotations

import math
import struct
from pathlib import Path

import numpy as np
import pytest
from conftest import corpus_params, golden
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from oracle import UNDEFINED, webots_load, webots_play
from strategies import motion_files

from motiontool.motionfmt import Motion, iter_commands, read_bytes, sample, step_count

TIMESTEPS = (1, 8, 16, 20, 32, 40, 64, 100)
MAX_ROWS = 100_000
"""Rows compared per time step (the oracle is a plain loop): every row of the corpus's and the
golden files' streams (60 s at 1 ms at most), the start of a longer or endless one."""


def _bits(x: float | None) -> bytes | None:
    if x is None:
        return None  # no command
    if math.isnan(x):
        return b"nan"  # a NaN command (any payload): Webots sends it
    return struct.pack("<d", x)


def check_against_oracle(data: bytes, timesteps: tuple[int, ...] = TIMESTEPS) -> None:
    result = read_bytes(data, "f.motion")
    oracle = webots_load(data)
    assert result.accepted == oracle.ok
    if not oracle.ok:
        if oracle.stop_line is not None:
            assert result.rejected_at is not None
            assert result.rejected_at.line == oracle.stop_line
        # The reason Webots stops is among the findings, also after a cut line (issue #36 item 16).
        assert any(d is result.rejected_at for d in result.diagnostics)
        return
    motion = result.motion
    assert list(motion.times_ms) == oracle.times
    expected_values = [[None if v == UNDEFINED else v for v in row] for row in oracle.values]
    got_values = [
        [v if sent else None for v, sent in zip(row, mask, strict=True)]
        for row, mask in zip(motion.values.tolist(), motion.commanded.tolist(), strict=True)
    ]
    assert [[_bits(v) for v in r] for r in got_values] == [
        [_bits(v) for v in r] for r in expected_values
    ]
    for step in timesteps:
        rows = webots_play(oracle.times, oracle.values, step, max_rows=MAX_ROWS)
        elapsed, got = played(motion, step, MAX_ROWS)
        assert elapsed == [e for e, _ in rows]
        want = [[_bits(v) for v in row] for _, row in rows]
        assert got == want, f"time step {step} ms"


def played(motion: Motion, step: int, max_rows: int) -> tuple[list[int], list[list[bytes | None]]]:
    """The first ``max_rows`` rows of the streamed command stream: elapsed times and targets as
    :func:`_bits`; the in-memory stream of :func:`sample` must be the same where it is whole."""
    elapsed: list[int] = []
    got: list[list[bytes | None]] = []
    for chunk in iter_commands(motion, step):
        elapsed += chunk.elapsed_ms.tolist()
        got += [
            [_bits(v if sent else None) for v, sent in zip(row, mask, strict=True)]
            for row, mask in zip(chunk.targets.tolist(), chunk.commanded.tolist(), strict=True)
        ]
        if len(elapsed) >= max_rows:
            break
    count = step_count(motion.duration_ms, step)
    if count is not None and count <= max_rows:
        whole = sample(motion, step)
        assert whole.elapsed_ms.tolist() == elapsed
        assert [
            [_bits(v if sent else None) for v, sent in zip(row, mask, strict=True)]
            for row, mask in zip(whole.targets.tolist(), whole.commanded.tolist(), strict=True)
        ] == got
    return elapsed[:max_rows], got[:max_rows]


@pytest.mark.parametrize("path", corpus_params())
def test_corpus_reads_and_plays_like_webots(path: Path) -> None:
    check_against_oracle(path.read_bytes())


@pytest.mark.parametrize("path", golden("valid") + golden("invalid"), ids=lambda p: p.stem)
def test_golden_files_read_and_play_like_webots(path: Path) -> None:
    check_against_oracle(path.read_bytes(), (7, 20, 32))


def test_format_md_example() -> None:
    data = b"#WEBOTS_MOTION,V1.0,A,B\n00:00:000,P1,0,*\n00:00:100,P2,1,2\n00:00:150,P3,0.5,1\n"
    stream = sample(read_bytes(data).motion, 32)
    assert stream.elapsed_ms.tolist() == [0, 32, 64, 96, 128, 160]
    a, b = stream.targets[:, 0], stream.targets[:, 1]
    assert [f"{x:.17g}" for x in a] == [
        "0", "0.32000000000000001", "0.64000000000000001", "0.95999999999999996",
        "0.71999999999999997", "0.5",
    ]  # fmt: skip
    assert np.isnan(b[:4]).all() and [f"{x:.17g}" for x in b[4:]] == ["1.4399999999999999", "1"]


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(motion_files())
def test_generated_files_play_like_webots(data: bytes) -> None:
    check_against_oracle(data, (8, 20, 33))


@settings(max_examples=300, deadline=None)
@given(motion_files(), st.data())
def test_mutated_files_are_judged_like_webots(data: bytes, draw: st.DataObject) -> None:
    pos = draw.draw(st.integers(0, len(data)))
    junk = draw.draw(
        st.sampled_from(
            [b"", b",", b"\n", b"\n\n", b" ", b"x", b"*", b"\r", b":", b"-", b"\0", b"\xe9"]
        )
    )
    cut = draw.draw(st.integers(0, 3))
    check_against_oracle(data[:pos] + junk + data[pos + cut :], (20,))
