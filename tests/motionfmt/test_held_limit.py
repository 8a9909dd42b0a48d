"""A stream held whole in memory is refused past MAX_HELD_STEPS, before it is built, where a
motion plays for days; what reads it a chunk at a time takes any duration."""

from __future__ import annotations

import itertools

import pytest

from motiontool.motionfmt import read_bytes
from motiontool.motionfmt.compare import held_targets
from motiontool.motionfmt.document import loads
from motiontool.motionfmt.player import (
    MAX_HELD_STEPS,
    StreamTooLongError,
    iter_commands,
    require_held,
    sample,
)
from motiontool.motionfmt.resample import resample
from motiontool.motionfmt.resample_grid import GridResample

DAYS = b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,P1,0\n40,P2,1.5\n2000000000,P3,0\n"


def test_a_whole_stream_of_a_motion_that_plays_for_days_is_refused_before_it_is_built() -> None:
    motion = read_bytes(DAYS, "days.motion").motion
    with pytest.raises(StreamTooLongError, match=r"100,000,001 steps of 20 ms \(555.6 h\)"):
        sample(motion, 20)
    with pytest.raises(StreamTooLongError):
        held_targets(motion, 20)
    with pytest.raises(StreamTooLongError, match="the resampling grid"):  # it would take hours
        resample(loads(DAYS, "days.motion"), step_ms=20)
    chunks = iter_commands(motion, 20, chunk_steps=1000)  # streamed: any duration
    assert sum(c.elapsed_ms.shape[0] for c in itertools.islice(chunks, 3)) == 3000
    gridded = GridResample(loads(DAYS, "days.motion"), motion, 20)  # written a block at a time
    assert gridded.n_poses == 100_000_001
    head = next(gridded.blocks())
    assert head.startswith(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,P1,0\n20,Pose20ms,0.75\n40,P2,1.5\n")


def test_the_limit_is_inclusive() -> None:
    require_held(MAX_HELD_STEPS, 20)
    with pytest.raises(StreamTooLongError):
        require_held(MAX_HELD_STEPS + 1, 20)
