"""PoseNames holds pose names as text and reads like the list of them, whatever way it was
filled; a read keeps its poses in compact arrays, shared with its motion."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from motiontool.motionfmt.pose_names import CHUNK, PoseNames
from motiontool.motionfmt.reader import read_bytes

NAMES = st.text(st.characters(blacklist_characters="\n"), max_size=4)
SIZES = st.sampled_from([0, 1, CHUNK - 1, CHUNK, CHUNK + 1, 2 * CHUNK + 3])


def _names(n: int, tag: str = "P") -> list[str]:
    return [f"{tag}{i}" for i in range(n)]


@settings(max_examples=40, deadline=None)
@given(SIZES, st.lists(st.integers(0, 3 * CHUNK), max_size=4), NAMES)
def test_filled_any_way_it_reads_as_the_list(size: int, cuts: list[int], odd: str) -> None:
    want = _names(size)
    if want:
        want[size // 2] = odd  # any character but a newline, the empty name included
    appended, extended, joined = PoseNames(), PoseNames(), PoseNames()
    for name in want:
        appended.append(name)
    bounds = sorted({0, size, *(c % (size + 1) for c in cuts)})
    for a, b in itertools.pairwise(bounds):
        extended.extend(want[a:b])  # chunks filled across their boundaries
        joined.extend(PoseNames(want[a:b]))
    for names in (appended, extended, joined, PoseNames(want), PoseNames(iter(want))):
        assert len(names) == size
        assert list(names) == want
        assert names == want and want == names and names == tuple(want)
        assert names == appended
        assert [names[i] for i in range(size)] == want
        assert [names[-i] for i in range(1, size + 1)] == [want[-i] for i in range(1, size + 1)]
        assert names[1 : size - 1 : 3] == want[1 : size - 1 : 3]
        with pytest.raises(IndexError):
            names[size]
        with pytest.raises(IndexError):
            names[-size - 1]


def test_read_far_apart_and_back() -> None:
    want = _names(3 * CHUNK + 5)
    names = PoseNames(want)
    for i in [3 * CHUNK + 4, 0, CHUNK, 2 * CHUNK - 1, 5, 3 * CHUNK, CHUNK + 7]:
        assert names[i] == want[i]
    assert names.index("P4100") == 4100 and "P12000" in names and "Q" not in names
    twice = PoseNames([*want, *want])
    n = len(want)
    for name, start, stop in [
        ("P0", 0, None),
        ("P0", 1, None),
        ("P3", -(n - 2), None),
        ("P7", 2, 9),
    ]:
        assert twice.index(name, start, stop) == [*want, *want].index(name, start, stop or 2 * n)
    assert twice.index("P4100", 4101, n + 4101) == n + 4100
    for name, start, stop in [("P4100", 4101, n + 4100), ("P1", 2, 3 * CHUNK), ("Q", 0, None)]:
        with pytest.raises(ValueError, match="not a pose name"):
            twice.index(name, start, stop)


def test_unequal_and_unhashable() -> None:
    names = PoseNames(_names(CHUNK + 2))
    assert names != _names(CHUNK + 1)
    assert names != [*_names(CHUNK + 1), "other"]
    assert names != PoseNames(_names(CHUNK + 2, "Q"))
    assert names != PoseNames([*_names(CHUNK + 1), "other"])  # the same full chunks
    assert names != "P0" and names != 3
    with pytest.raises(TypeError):
        hash(names)
    assert repr(PoseNames(["A", "B", "C", "D"])) == "PoseNames(['A', 'B', 'C', ...], 4 names)"


def test_a_newline_in_a_name_is_refused_and_adds_nothing() -> None:
    names = PoseNames(["A"])
    with pytest.raises(ValueError, match="newline"):
        names.append("B\nC")
    with pytest.raises(ValueError, match="newline"):
        names.extend([*_names(CHUNK + 1), "B\nC"])
    assert names == ["A"]
    names.extend(names)
    assert names == ["A", "A"]
    many = PoseNames(_names(CHUNK + 1))
    many.extend(many)
    assert many == _names(CHUNK + 1) * 2


@pytest.mark.parametrize("size", [1, 2 * CHUNK + 1])
@pytest.mark.parametrize("star", [False, True], ids=["clean", "star"])
def test_a_read_keeps_compact_arrays_its_motion_shares(size: int, star: bool) -> None:
    # Line by line (a '*' anywhere, or a small file) and in bulk alike: times as a C int
    # array, names as text, values as one float64 array the motion shares.
    lines = [f"{40 * p},Pose{p},{p / 8},{'*' if star and p == 1 else -p / 4}" for p in range(size)]
    read = read_bytes(("#WEBOTS_MOTION,V1.0,A,B\n" + "\n".join(lines) + "\n").encode())
    assert read.accepted
    assert read.times_ms.typecode == "q" and list(read.times_ms) == [40 * p for p in range(size)]
    assert isinstance(read.pose_names, PoseNames)
    assert read.pose_names == [f"Pose{p}" for p in range(size)]
    assert len(read.cells) == 2 * size and read.row(size - 1) == [(size - 1) / 8, -(size - 1) / 4]
    with pytest.raises(IndexError):
        read.row(size)
    motion = read.motion
    assert motion.pose_names is read.pose_names
    assert np.shares_memory(motion.values, np.asarray(read.cells))
    assert np.shares_memory(motion.times_ms, np.asarray(read.times_ms))
    assert not motion.values.flags.writeable and not motion.times_ms.flags.writeable
    assert motion.values.shape == (size, 2)
    assert motion.values[size - 1].tolist() == read.row(size - 1)
