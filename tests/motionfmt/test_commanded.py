"""NaN is not "no command": a ``nan`` / ``inf`` cell is a command Webots sends to the motor, only
``*`` and the -9999999.9 marker are not. ``Motion.commanded`` and ``CommandStream.commanded`` say
which is which, and every consumer uses them."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from oracle import UNDEFINED, webots_load, webots_play
from strategies import motion_files

from motiontool.motionfmt import (
    Motion,
    MotionSyntaxError,
    MotionToolError,
    commands_at,
    dumps,
    format_motion,
    loads,
    read_bytes,
    sample,
)
from motiontool.motionfmt.compare import compare_motions, held_targets
from motiontool.motionfmt.resample import resample

NAN_FILE = b"#WEBOTS_MOTION,V1.0,A,B,C,D\n0,P1,nan,inf,*,1\n100,P2,1,inf,-9999999.9,2\n"


def test_reader_masks_star_and_marker_but_not_nan_or_inf() -> None:
    motion = read_bytes(NAN_FILE).motion
    assert motion.commanded.tolist() == [[True, True, False, True], [True, True, False, True]]
    assert math.isnan(motion.values[0, 0]) and motion.values[0, 1] == math.inf
    assert np.isnan(motion.values[:, 2]).all()
    assert not motion.commanded.flags.writeable


def test_motion_without_mask_derives_it_from_nan() -> None:
    values = np.array([[0.0, np.nan]])
    motion = Motion(("A", "B"), ("P",), np.array([0]), values)
    assert motion.commanded.tolist() == [[True, False]]
    masked = Motion(("A", "B"), ("P",), np.array([0]), values, np.array([[True, True]]))
    assert masked != motion  # same values, but one sends NaN to B
    with pytest.raises(ValueError, match="shape"):
        Motion(("A", "B"), ("P",), np.array([0]), values, np.array([True, True]))


def test_a_nan_cell_is_not_reported_as_star() -> None:
    result = read_bytes(b"#WEBOTS_MOTION,V1.0,A,B\n0,P1,nan,*\n100,P2,nan,*\n")
    codes = [(d.code, d.joint) for d in result.diagnostics]
    assert ("MT211", "B") in codes  # B is '*' in every pose
    assert ("MT211", "A") not in codes and ("MT207", "A") not in codes
    assert [c for c, j in codes if j == "A"] == ["MT113", "MT113"]


def test_player_sends_nan_and_inf_and_inf_minus_inf() -> None:
    stream = sample(read_bytes(NAN_FILE).motion, 50)
    assert stream.elapsed_ms.tolist() == [0, 50, 100]
    assert stream.commanded.tolist() == [[True, True, False, True]] * 3
    t = stream.targets
    assert math.isnan(t[0, 0]) and t[0, 1] == math.inf and t[0, 3] == 1.0
    assert math.isnan(t[1, 0]) and math.isnan(t[1, 1])  # nan + ...; inf + 50 * (inf - inf) / 100
    assert t[2].tolist()[:2] == [1.0, math.inf] and math.isnan(t[2, 2])


def test_a_target_equal_to_the_marker_is_not_sent() -> None:
    # Webots' motion_actuate skips pos == -9999999.9, also when interpolation lands on it.
    data = b"#WEBOTS_MOTION,V1.0,A\n0,P1,-9999999.8\n100,P2,-10000000.0\n"
    motion = read_bytes(data).motion
    targets, sent = commands_at(motion, np.array([25, 50], dtype=np.int64))
    assert sent[:, 0].tolist() == [True, False] and math.isnan(targets[1, 0])
    oracle = webots_load(data)
    rows = webots_play(oracle.times, oracle.values, 50)
    assert [r[1][0] is None for r in rows] == [False, True, False]


def _mask_and_bits(values: list[float | None]) -> list[object]:
    return [None if v is None else ("nan" if math.isnan(v) else v) for v in values]


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(motion_files(non_finite=True))
def test_non_finite_cells_play_like_webots(data: bytes) -> None:
    motion = read_bytes(data).motion
    oracle = webots_load(data)
    assert oracle.ok
    want_cells = [[None if v == UNDEFINED else v for v in row] for row in oracle.values]
    got_cells = [
        [v if c else None for v, c in zip(row, mask, strict=True)]
        for row, mask in zip(motion.values.tolist(), motion.commanded.tolist(), strict=True)
    ]
    assert [_mask_and_bits(r) for r in got_cells] == [_mask_and_bits(r) for r in want_cells]
    for step in (8, 33):
        stream = sample(motion, step)
        want = [_mask_and_bits(row) for _, row in webots_play(oracle.times, oracle.values, step)]
        got = [
            _mask_and_bits([v if c else None for v, c in zip(row, mask, strict=True)])
            for row, mask in zip(stream.targets.tolist(), stream.commanded.tolist(), strict=True)
        ]
        assert got == want


def test_compare_tells_a_nan_command_from_no_command() -> None:
    header = b"#WEBOTS_MOTION,V1.0,A\n"
    nan = read_bytes(header + b"0,P1,0\n100,P2,nan\n").motion
    star = read_bytes(header + b"0,P1,0\n100,P2,*\n").motion
    zero = read_bytes(header + b"0,P1,0\n100,P2,0\n").motion
    assert compare_motions(nan, nan, timestep_ms=10).same
    assert not compare_motions(nan, zero, timestep_ms=10).same
    # With '*' the motor holds 0 until the end; with nan it is sent NaN from 10 ms on.
    assert not compare_motions(nan, star, timestep_ms=10).same
    assert compare_motions(star, zero, timestep_ms=10).same
    _, held = held_targets(star, 50)
    assert held[:, 0].tolist() == [0.0, 0.0, 0.0]


def test_resample_refuses_a_non_finite_cell_with_its_location() -> None:
    doc = loads(b"#WEBOTS_MOTION,V1.0,A\n0,P1,0\n100,P2,inf\n", "f.motion")
    with pytest.raises(MotionSyntaxError, match=r"^f\.motion:3:8: A = inf is not a finite number"):
        resample(doc, step_ms=20)


def test_format_motion_refuses_a_nan_command_and_writes_star_for_none() -> None:
    values = np.array([[np.nan, np.nan]])
    motion = Motion(("A", "B"), ("P",), np.array([0]), values, np.array([[False, True]]))
    with pytest.raises(MotionToolError, match="B = nan"):
        format_motion(motion)
    assert format_motion(Motion(("A",), ("P",), np.array([0]), np.array([[np.nan]]))).endswith(
        "00:00:000,P,*\n"
    )


def test_document_set_value_nan_turns_a_nan_command_into_star() -> None:
    doc = loads(b"#WEBOTS_MOTION,V1.0,A,B\n0,P,nan,*\n")
    assert doc.motion.commanded.tolist() == [[True, False]]
    doc.set_value(0, "B", math.nan)  # already '*': unchanged
    doc.set_value(0, "A", math.nan)  # a NaN command becomes no command
    assert dumps(doc) == b"#WEBOTS_MOTION,V1.0,A,B\n0,P,*,*\n"
    assert doc.motion.commanded.tolist() == [[False, False]]
