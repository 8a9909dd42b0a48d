"""The lossless document layer, the canonical writer, and robustness on arbitrary bytes."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT, corpus_params, golden
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import motion_files

from motiontool.motionfmt import (
    Motion,
    MotionSyntaxError,
    MotionToolError,
    document,
    dumps,
    format_motion,
    loads,
    read_bytes,
)

ACCEPTED_GOLDEN = [p for p in golden("valid") if p.stem != "line_4095_bytes"]


@pytest.mark.parametrize(
    "path", ACCEPTED_GOLDEN + sorted((ROOT / "motions").rglob("*.motion")), ids=lambda p: p.stem
)
def test_round_trip_golden_and_project_motions(path: Path) -> None:
    data = path.read_bytes()
    assert dumps(loads(data)) == data
    text = data.decode("utf-8", "surrogateescape")
    assert dumps(loads(text)) == text


@pytest.mark.parametrize("path", corpus_params())
def test_round_trip_corpus(path: Path) -> None:
    data = path.read_bytes()
    assert dumps(loads(data)) == data


@settings(max_examples=200, deadline=None)
@given(motion_files())
def test_round_trip_generated(data: bytes) -> None:
    assert dumps(loads(data)) == data


def test_edit_rerenders_only_the_touched_cells() -> None:
    src = b"#WEBOTS_MOTION,V1.0,A,B\r\n00:00:000,P1, +0.10,*\r\n00:00:100,P2,1.000,2e0\r\n"
    doc = loads(src)
    doc.set_value(0, "A", 0.25)
    doc.set_value(1, 1, 2.0)  # equal value: spelling kept
    assert (
        doc.to_bytes()
        == b"#WEBOTS_MOTION,V1.0,A,B\r\n00:00:000,P1, 0.25,*\r\n00:00:100,P2,1.000,2e0\r\n"
    )
    doc.set_time(1, 61040)
    assert doc.to_bytes().splitlines()[2] == b"01:01:040,P2,1.000,2e0"
    assert doc.motion.times_ms.tolist() == [0, 61040]


def test_set_time_keeps_pose_times_increasing_like_set_times() -> None:
    src = b"#WEBOTS_MOTION,V1.0,A\n0,P1,0\n100,P2,1\n200,P3,2\n"
    doc = loads(src)
    for pose, time_ms in [(1, 200), (1, 0), (-1, 100), (0, 100)]:
        with pytest.raises(MotionToolError, match=r"^pose times must strictly increase: pose"):
            doc.set_time(pose, time_ms)
        assert doc.to_bytes() == src  # refused before any change
    with pytest.raises(MotionToolError, match="pose 2 at 100 ms is not after pose 1 at 100 ms"):
        doc.set_time(2, 100)
    doc.set_time(1, 199)
    doc.set_time(-1, 250)
    assert doc.motion.times_ms.tolist() == [0, 199, 250]
    with pytest.raises(MotionToolError, match="pose 2 at 10 ms is not after pose 1 at 199 ms"):
        doc.set_times([0, 199, 10])


def test_insert_and_delete_keep_line_ends() -> None:
    doc = loads(b"#WEBOTS_MOTION,V1.0,A\r\n0,P1,0\r\n100,P2,1")
    doc.insert_pose(2, 250, "P3", [float("nan")])
    assert doc.to_bytes() == b"#WEBOTS_MOTION,V1.0,A\r\n0,P1,0\r\n100,P2,1\r\n250,P3,*"
    doc.delete_pose(0)
    assert doc.to_bytes() == b"#WEBOTS_MOTION,V1.0,A\r\n100,P2,1\r\n250,P3,*"
    assert doc.motion.pose_names == ("P2", "P3")


@settings(max_examples=150, deadline=None)
@given(motion_files(), st.booleans(), st.integers(1, 3), st.data())
def test_inserting_poses_at_once_is_inserting_them_one_by_one(
    data: bytes, suffix: bool, block: int, draw: st.DataObject
) -> None:
    """Also with the new lines spelt a block of 1 to 3 at a time."""
    if suffix:  # lines after a blank line, which Webots ignores
        data = data.rstrip(b"\r\n") + b"\n\n9,ignored,1\n"
    once, each = loads(data), loads(data)
    n, n_joints = once.n_poses, len(once.joints)
    at = sorted(draw.draw(st.lists(st.integers(0, n), min_size=1, max_size=6)))
    values = np.array(
        draw.draw(
            st.lists(
                st.lists(
                    st.floats(-4, 4) | st.just(math.nan), min_size=n_joints, max_size=n_joints
                ),
                min_size=len(at),
                max_size=len(at),
            )
        ),
        dtype=np.float64,
    ).reshape(len(at), n_joints)
    names = [f"N{k}" for k in range(len(at))]
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(document, "_NEW_LINES", block)
        once.insert_poses(at, list(range(len(at))), names, values)
    for k in reversed(range(len(at))):  # the last first: the indices before it stay valid
        each.insert_pose(at[k], k, names[k], values[k].tolist())
    assert once.to_bytes() == each.to_bytes()


def test_inserting_poses_refuses_indices_out_of_order() -> None:
    doc = loads(b"#WEBOTS_MOTION,V1.0,A\n0,P1,0\n100,P2,1\n")
    with pytest.raises(MotionToolError, match="indices that decrease or pass 2"):
        doc.insert_poses([2, 1], [1, 2], ["a", "b"], np.zeros((2, 1)))
    with pytest.raises(MotionToolError, match="indices that decrease or pass 2"):
        doc.insert_poses([3], [1], ["a"], np.zeros((1, 1)))
    assert doc.to_bytes() == b"#WEBOTS_MOTION,V1.0,A\n0,P1,0\n100,P2,1\n"


def test_suffix_after_blank_line_survives_edits() -> None:
    doc = loads(b"#WEBOTS_MOTION,V1.0,A\n0,P1,0\n\n100,ignored,1\n")
    doc.insert_pose(1, 50, "P2", [0.5])
    assert doc.to_bytes() == b"#WEBOTS_MOTION,V1.0,A\n0,P1,0\n50,P2,0.5\n\n100,ignored,1\n"


def test_loads_rejects_what_webots_rejects() -> None:
    with pytest.raises(MotionSyntaxError, match=r"^x.motion:2:17: expected a number"):
        loads(b"#WEBOTS_MOTION,V1.0,A,B\n00:00:000,Pose1,abc,0\n", "x.motion")


def test_canonical_writer_round_trips_values_exactly() -> None:
    rng = np.random.default_rng(1)
    values = rng.uniform(-3, 3, size=(5, 3))
    values[1, 2] = np.nan
    m = Motion(
        ("A", "B", "C"),
        tuple(f"P{i}" for i in range(5)),
        np.array([0, 40, 80, 1000, 61040]),
        values,
    )
    text = format_motion(m)
    assert text.splitlines()[0] == "#WEBOTS_MOTION,V1.0,A,B,C"
    assert text.splitlines()[5].startswith("01:01:040,P4,")
    back = read_bytes(text.encode()).motion
    assert back == m
    assert {d.code for d in read_bytes(text.encode()).diagnostics} == {"MT207"}  # the NaN cell


def test_writer_refuses_names_webots_cannot_read() -> None:
    m = Motion(("A,B",), ("P",), np.array([0]), np.zeros((1, 1)))
    with pytest.raises(MotionToolError, match="joint 'A,B' cannot be written"):
        format_motion(m)


def test_motion_arrays_are_read_only() -> None:
    m = read_bytes(b"#WEBOTS_MOTION,V1.0,A\n0,P,1\n").motion
    with pytest.raises(ValueError):
        m.values[0, 0] = 2.0
    assert m.times_ms.dtype == np.int64 and m.values.dtype == np.float64


def test_a_motion_shares_a_read_only_array_and_copies_any_other() -> None:
    # A read's rows are the motion's values (one copy of a large file's values, not two); an
    # array its caller may still write is copied, and stays writable.
    from motiontool.motionfmt.motion import Motion

    times = ((t // 60000, t // 1000 % 60, t % 1000) for t in range(0, 4 * 10**6, 40))
    big = b"#WEBOTS_MOTION,V1.0,A,B\n" + b"".join(b"%02d:%02d:%03d,P,1,2\n" % t for t in times)
    result = read_bytes(big)
    assert np.shares_memory(result.motion.values, result.cells)  # the bulk path's array
    small = read_bytes(b"#WEBOTS_MOTION,V1.0,A\n0,P,1\n").motion
    assert not small.values.flags.writeable
    mine = np.array([[1.0, 5.0], [2.0, 3.0]])
    m = Motion(("A", "B"), ("P", "Q"), [0, 10], mine, np.array([[True, False], [True, True]]))
    assert not np.shares_memory(m.values, mine) and mine.flags.writeable
    assert np.isnan(m.values[0, 1]) and mine[0, 1] == 5.0
    frozen = mine.copy()
    frozen.flags.writeable = False
    m = Motion(("A", "B"), ("P", "Q"), [0, 10], frozen, np.array([[True, False], [True, True]]))
    assert np.isnan(m.values[0, 1]) and frozen[0, 1] == 5.0  # '*' made NaN in a copy
    m = Motion(("A", "B"), ("P", "Q"), [0, 10], frozen)
    assert np.shares_memory(m.values, frozen)
    times = np.array([0, 10])
    assert not np.shares_memory(Motion(("A", "B"), ("P", "Q"), times, frozen).times_ms, times)
    times.flags.writeable = False
    assert np.shares_memory(Motion(("A", "B"), ("P", "Q"), times, frozen).times_ms, times)


# -- robustness: only diagnostics or MotionToolError, never another exception -----------------


def _never_crashes(data: bytes) -> None:
    result = read_bytes(data, "fuzz.motion", timestep_ms=20)
    for d in result.diagnostics:
        assert d.line >= 1 and d.column >= 1
    try:
        doc = loads(data, "fuzz.motion")
    except MotionToolError:
        assert not result.accepted or any(d.code == "MT111" for d in result.diagnostics)
    else:
        assert dumps(doc) == data
        assert math.isfinite(doc.motion.duration_ms)


@settings(max_examples=500, deadline=None)
@given(st.binary(max_size=300))
def test_random_bytes(data: bytes) -> None:
    _never_crashes(data)


@settings(max_examples=300, deadline=None)
@given(st.binary(max_size=120).map(lambda b: b"#WEBOTS_MOTION,V1.0,A,B\n" + b))
def test_random_bytes_after_a_header(data: bytes) -> None:
    _never_crashes(data)


@pytest.mark.parametrize("path", corpus_params())
def test_mutated_corpus_files(path: Path) -> None:
    data = path.read_bytes()
    rng = np.random.default_rng(len(data))
    for _ in range(40):
        b = bytearray(data)
        for _ in range(int(rng.integers(1, 4))):
            i = int(rng.integers(0, len(b)))
            op = int(rng.integers(0, 3))
            if op == 0:
                b[i] = int(rng.integers(0, 256))
            elif op == 1:
                del b[i]
            else:
                b.insert(i, int(rng.choice(list(b",\n\r *:.-0e"))))
        _never_crashes(bytes(b))


@settings(max_examples=100, deadline=None)
@given(motion_files(), st.lists(st.integers(0, 3), min_size=1, max_size=6), st.data())
def test_bytes_follow_every_edit_after_a_read(
    data: bytes, edits: list[int], draw: st.DataObject
) -> None:
    """A document returns the bytes it last read until an edit: each edit made after reading
    ``result`` shows in ``to_bytes`` as in a document never read."""
    read, fresh = loads(data), loads(data)
    assert read.to_bytes() == data
    for edit in edits:
        read.result  # noqa: B018 - the read that to_bytes reuses until the next edit
        pose = draw.draw(st.integers(0, read.n_poses - 1))
        value = draw.draw(st.floats(-4, 4))
        for doc in (read, fresh):
            if edit == 0:
                doc.set_value(pose, 0, value)
            elif edit == 1 and doc.n_poses > 1:
                doc.delete_pose(pose)
            elif edit == 2:  # a pose after the last
                last = int(doc.motion.times_ms[-1])
                doc.insert_pose(doc.n_poses, last + 40, "New", [0.5] * len(doc.joints))
        assert read.to_bytes() == fresh.to_bytes()
        assert read.result.motion.n_poses == read.n_poses


@pytest.mark.parametrize("block", [1, 8192])
def test_an_insert_that_fails_leaves_the_document_as_it_was(block: int) -> None:
    data = b"#WEBOTS_MOTION,V1.0,A\r\n0,P1,0\r\n100,P2,1"  # CRLF, no end on the last line
    doc = loads(data)
    doc.result  # noqa: B018 - read: to_bytes gives the bytes read until an edit
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(document, "_NEW_LINES", block)
        with pytest.raises(MotionToolError, match="pose name"):
            doc.insert_poses([2, 2], [200, 300], ["P3", "bad,name"], np.zeros((2, 1)))
    assert doc.to_bytes() == data
    doc.insert_poses([2], [200], ["P3"], np.zeros((1, 1)))
    assert doc.to_bytes() == data + b"\r\n200,P3,0"


@settings(max_examples=60, deadline=None)
@given(motion_files())
def test_a_document_splits_its_lines_only_to_edit_them(data: bytes) -> None:
    """Read and written back, a document holds its bytes once (its lines are not split);
    its first edit splits them, with the same pose count and bytes as before."""
    doc = loads(data)
    assert doc.to_bytes() == data and doc.n_poses == len(doc.motion.times_ms)
    assert doc._lines is None
    n = doc.n_poses
    doc.set_value(0, 0, float(doc.motion.values[0, 0]) + 0.5)
    assert doc._lines is not None and doc.n_poses == n
    assert doc.result.motion.n_poses == n


@settings(max_examples=80, deadline=None)
@given(motion_files(), st.sampled_from(["none", "read", "edited"]), st.data())
def test_a_copy_is_edited_on_its_own(data: bytes, state: str, draw: st.DataObject) -> None:
    """A copy and its original share nothing an edit of either changes: each edit shows in
    the one edited only, whatever the original had done before (read, edited, neither)."""
    doc = loads(data)
    if state == "read":
        doc.result  # noqa: B018
    elif state == "edited":
        doc.set_value(0, 0, 0.25)
    before = doc.to_bytes()
    twin = doc.copy()
    assert twin.to_bytes() == before and twin.n_poses == doc.n_poses
    twin.set_value(0, 0, draw.draw(st.floats(-3, 3)))  # in place, first
    last = int(twin.motion.times_ms[-1])
    twin.insert_pose(twin.n_poses, last + 40, "New", [0.5] * len(twin.joints))
    assert doc.to_bytes() == before and doc.n_poses == twin.n_poses - 1
    assert doc.result.motion.n_poses == doc.n_poses
    doc.delete_pose(0) if doc.n_poses > 1 else doc.set_value(0, 0, 1.5)
    assert twin.result.motion.n_poses == twin.n_poses
    assert twin.to_bytes() == loads(twin.to_bytes()).to_bytes()
