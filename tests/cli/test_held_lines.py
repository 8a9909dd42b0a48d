"""``plot``'s dotted lines (held targets over ``*``), made a chunk of steps at a time with only
the points that shape them, are the lines through every step that the plot drew before."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import motion_files

from motiontool.cli import _held_lines
from motiontool.motionfmt import read_bytes
from motiontool.motionfmt.compare import held_targets
from motiontool.motionfmt.player import commands_at
from motiontool.motionfmt.units import MS_PER_S


def _every_step(motion: object, step: int, column: int) -> np.ndarray:
    """The line through every step: the held target where the column sends no command, or
    sends none at the next step; NaN elsewhere."""
    names = tuple(dict.fromkeys(motion.joints))  # type: ignore[attr-defined]
    elapsed, held = held_targets(motion, step, names=names)  # type: ignore[arg-type]
    sent = commands_at(motion, elapsed)[1][:, column]  # type: ignore[arg-type]
    drawn = ~sent
    drawn[:-1] |= ~sent[1:]
    k = names.index(motion.joints[column])  # type: ignore[attr-defined]
    return np.where(drawn, held[:, k], np.nan)


@settings(max_examples=200, deadline=None)
@given(motion_files(non_finite=True), st.integers(1, 6), st.sampled_from([1, 7, 20, 50]))
def test_the_lines_are_those_through_every_step(data: bytes, chunk: int, step: int) -> None:
    motion = read_bytes(data, "m.motion").motion
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_held_lines, "_CHUNK_STEPS", chunk)
        lines = _held_lines.held_lines(motion, step)
    assert len(lines) == motion.n_joints
    for column, (x, y) in enumerate(lines):
        full = _every_step(motion, step, column)
        at = np.rint(x * MS_PER_S / step).astype(np.int64)
        assert at[0] == 0 and at[-1] == full.shape[0] - 1 and (np.diff(at) > 0).all()
        assert np.array_equal(y, full[at], equal_nan=True)  # kept points are the stream's
        for a, b in zip(at[:-1].tolist(), at[1:].tolist(), strict=True):
            left_out = full[a + 1 : b]  # what a line from a to b passes over
            if np.isnan(full[a]):
                assert np.isnan(left_out).all()  # a break stays a break
            else:
                assert (left_out == full[a]).all() and (left_out.size == 0 or full[b] == full[a])


def test_a_long_flat_hold_is_two_points() -> None:
    motion = read_bytes(b"#WEBOTS_MOTION,V1.0,A\n0,P1,0.5\n100,P2,*\n3600000,P3,1\n").motion
    x, y = _held_lines.held_lines(motion, 20)[0]
    assert x.shape[0] < 200  # 180,001 steps, a chunk's two ends at most each
    assert np.nanmax(y) == np.nanmin(y) == 0.5 and x[-1] == pytest.approx(3600.0)
