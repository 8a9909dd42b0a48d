"""The one forward-fill (:func:`motiontool.motionfmt.player.hold_targets`) against a plain loop of
Webots' player: per step, ``wb_motor_set_position`` once per column that sends a target, in
column order; a motor keeps its last target."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from motiontool.motionfmt import Held, hold_targets

_VALUES = st.one_of(
    st.floats(-3.0, 3.0, allow_nan=False), st.just(math.nan), st.just(math.inf)
)  # a sent target may be NaN or infinite: Webots sends a 'nan' / 'inf' cell


def _plain_loop(
    targets: list[list[float]],
    commanded: list[list[bool]],
    joints: list[str],
    names: list[str],
    initial: list[float],
    holding: list[bool],
) -> tuple[list[list[float]], list[list[bool]], list[list[bool]]]:
    motor = dict(zip(names, range(len(names)), strict=True))
    now, has = list(initial), list(holding)
    held, sent, holds = [], [], []
    for row, mask in zip(targets, commanded, strict=True):
        step = [False] * len(names)
        for j, name in enumerate(joints):
            if mask[j] and name in motor:
                now[motor[name]] = row[j]  # a later column overwrites an earlier one
                has[motor[name]] = step[motor[name]] = True
        held.append(list(now))
        sent.append(step)
        holds.append(list(has))
    return held, sent, holds


def _bits(rows: list[list[float]]) -> list[list[object]]:
    return [["nan" if math.isnan(v) else v for v in row] for row in rows]


@st.composite
def _streams(draw: st.DrawFn) -> tuple[list[list[float]], list[list[bool]], list[str]]:
    n_steps = draw(st.integers(0, 6))
    joints = draw(st.lists(st.sampled_from("ABCD"), min_size=1, max_size=5))
    targets = [[draw(_VALUES) for _ in joints] for _ in range(n_steps)]
    commanded = [[draw(st.booleans()) for _ in joints] for _ in range(n_steps)]
    return targets, commanded, joints


@settings(max_examples=300, deadline=None)
@given(
    _streams(),
    st.lists(st.sampled_from("ABCDE"), unique=True, max_size=5),
    st.data(),
)
def test_hold_targets_is_webots_player_plain_loop(
    stream: tuple[list[list[float]], list[list[bool]], list[str]],
    names: list[str],
    data: st.DataObject,
) -> None:
    targets, commanded, joints = stream
    if len(set(joints)) == len(joints) and data.draw(st.booleans()):
        names = data.draw(st.permutations(joints))  # every column a motor: in order, or not
    start = data.draw(st.none() | st.lists(_VALUES, min_size=len(names), max_size=len(names)))
    holding = data.draw(
        st.none() | st.lists(st.booleans(), min_size=len(names), max_size=len(names))
    )
    t = np.array(targets, dtype=np.float64).reshape(len(targets), len(joints))
    c = np.array(commanded, dtype=np.bool_).reshape(t.shape)
    got = hold_targets(
        t,
        c,
        joints,
        names,
        initial=None if start is None else np.array(start, dtype=np.float64),
        holding=None if holding is None else np.array(holding, dtype=np.bool_),
    )
    want = _plain_loop(
        targets,
        commanded,
        joints,
        names,
        [math.nan] * len(names) if start is None else start,
        [False] * len(names) if holding is None else holding,
    )
    assert got.targets.dtype == np.float64 and got.targets.shape == (len(targets), len(names))
    assert _bits(got.targets.tolist()) == _bits(want[0])
    assert got.sent.tolist() == want[1]
    assert got.holding.tolist() == want[2]


def test_columns_kept_as_they_are_without_names() -> None:
    t = np.array([[1.0, np.nan], [np.nan, 2.0], [3.0, np.nan]])
    c = np.array([[True, False], [False, True], [True, False]])
    got = hold_targets(t, c, initial=np.array([9.0, 8.0]))
    assert got.targets.tolist() == [[1.0, 8.0], [1.0, 2.0], [3.0, 2.0]]
    assert got.holding.tolist() == [[True, False], [True, True], [True, True]]
    with pytest.raises(ValueError, match="names needs joints"):
        hold_targets(t, c, None, ["A"])


@settings(max_examples=60, deadline=None)
@given(cuts=st.lists(st.integers(0, 40), max_size=5), start=st.booleans())
def test_a_stream_cut_in_chunks_holds_what_it_holds_whole(cuts: list[int], start: bool) -> None:
    """``Holder`` carries what each chunk leaves held into the next (an empty chunk
    included): the chunks join into the stream held whole."""
    from motiontool.motionfmt.player import Holder

    rng = np.random.default_rng(3)
    t = rng.uniform(-1, 1, size=(40, 4))
    c = rng.random((40, 4)) < 0.2
    joints, names = ["A", "B", "A", "C"], ["C", "A", "B", "D"]
    initial = np.array([0.5, np.nan, -0.5, 0.25]) if start else None
    holding = np.array([True, False, True, False]) if start else None
    whole = hold_targets(t, c, joints, names, initial=initial, holding=holding)
    holder = Holder(names, initial=initial, holding=holding)
    bounds = [0, *sorted(cuts), 40]
    parts = [holder.hold(t[a:b], c[a:b], joints) for a, b in itertools.pairwise(bounds)]
    for field in Held._fields:
        joined = np.concatenate([getattr(part, field) for part in parts])
        assert np.array_equal(joined, getattr(whole, field), equal_nan=True), field
