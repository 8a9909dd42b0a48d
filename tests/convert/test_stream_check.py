"""The robot check of what an export sends reads its stream a chunk at a time and says what
it says of the whole stream: the first target out of a joint's limits, its fastest move."""

from __future__ import annotations

import itertools

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from motiontool.cli.convert_checks import stream_findings
from motiontool.kinematics.robots import load_robot
from motiontool.motionfmt.convert.base import RobotStream

UR = load_robot("ur5e")
JOINTS = (*UR.joint_names[:3], "not_a_joint")


@settings(max_examples=60, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    rows=st.integers(0, 40),
    cuts=st.lists(st.integers(0, 40), max_size=5),
)
def test_chunks_say_what_the_whole_stream_says(seed: int, rows: int, cuts: list[int]) -> None:
    rng = np.random.default_rng(seed)
    times = np.cumsum(rng.integers(1, 9, rows)).astype(np.int64)
    # Values near the limits and steps near maxVelocity; equal speeds in places (the first
    # of the fastest is named); NaN: nothing sent.
    targets = rng.choice([-3.2, -0.01, 0.0, 0.02, 3.0, 3.3, np.nan], size=(rows, len(JOINTS)))
    whole = stream_findings(RobotStream(JOINTS, times, targets), UR, "x")
    bounds = sorted({0, rows, *(c % (rows + 1) for c in cuts)})

    def made():  # type: ignore[no-untyped-def]
        for a, b in itertools.pairwise(bounds):
            yield times[a:b], targets[a:b]

    empty = np.zeros(0, dtype=np.int64)
    chunked = RobotStream(JOINTS, empty, np.zeros((0, len(JOINTS))), made=made)
    assert stream_findings(chunked, UR, "x") == whole
    assert whole[-1] == "x: not_a_joint is not a motor of robot ur5e"


def _two_chunks(times: np.ndarray, targets: np.ndarray) -> RobotStream:
    """The UR5e's shoulder_pan_joint stream ``(times, targets)`` made in two chunks, split
    after its second step."""

    def made():  # type: ignore[no-untyped-def]
        yield times[:2], targets[:2]
        yield times[2:], targets[2:]

    return RobotStream(("shoulder_pan_joint",), times[:0], targets[:0], made=made)


def test_a_move_across_two_chunks_is_checked() -> None:
    times = np.array([0, 8, 16], dtype=np.int64)
    targets = np.array([[0.0], [0.0], [0.1]])  # 0.1 rad in 8 ms, between the chunks
    (line,) = stream_findings(_two_chunks(times, targets), UR, "x")
    assert "shoulder_pan_joint moves at 12.5 rad/s from 8 ms to 16 ms" in line


def test_the_first_of_two_equally_fast_moves_is_named_across_chunks() -> None:
    times = np.array([0, 8, 16, 24], dtype=np.int64)
    targets = np.array([[0.0], [0.1], [0.1], [0.2]])  # 12.5 rad/s twice
    (line,) = stream_findings(_two_chunks(times, targets), UR, "x")
    assert "from 0 ms to 8 ms" in line
