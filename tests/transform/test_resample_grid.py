"""``resample --step`` streamed (motionfmt/resample_grid.py): the result written a block at a time
is the one the document edits make, and the comparison made a window at a time is the one made
with the result read back, whatever the block and window sizes."""

from __future__ import annotations

from unittest import mock

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import motion_files

from motiontool.motionfmt import compare, compare_steps, document, loads, resample_grid
from motiontool.motionfmt.compare import compare_motions
from motiontool.motionfmt.player import targets_at
from motiontool.motionfmt.resample import ROUNDING_RAD
from motiontool.motionfmt.resample_grid import Grid, GridResample
from motiontool.motionfmt.writer import pose_name

SETTINGS = settings(max_examples=150, deadline=None)


@SETTINGS
@given(
    st.integers(0, 300), st.integers(0, 300), st.integers(1, 40), st.integers(-5, 320),
    st.integers(-5, 320),
)  # fmt: skip
def test_the_grid_is_the_multiples_and_both_ends(
    first: int, span: int, step: int, lo: int, hi: int
) -> None:
    grid = Grid(first, first + span, step)
    every = sorted({first, first + span, *range(-(-first // step) * step, first + span + 1, step)})
    assert grid.count() == len(every)
    assert grid.between(lo, hi).tolist() == [t for t in every if lo <= t <= hi]
    assert grid.between(first, first + span).tolist() == every
    below = [t for t in every if t < lo]
    above = [t for t in every if t > lo]
    assert grid.before(lo) == (below[-1] if below else first)
    assert grid.after(lo) == (above[0] if above else first + span)
    times = np.arange(first, first + span + 1, dtype=np.int64)
    assert times[grid.holds(times)].tolist() == every


def reference(data: bytes, step: int) -> bytes:
    """The grid as document edits make it: poses off the grid deleted, then the grid times
    without a pose inserted with the targets Webots commands there."""
    doc = loads(data)
    m = doc.motion
    grid = Grid(int(m.times_ms[0]), m.duration_ms, step).between(0, m.duration_ms).tolist()
    times = m.times_ms.tolist()
    for p in range(len(times) - 1, -1, -1):
        if times[p] not in set(grid):
            doc.delete_pose(p)
            del times[p]
    new = [t for t in grid if t not in set(times)]
    at = np.searchsorted(np.asarray(times), new).tolist()
    doc.insert_poses(at, new, [pose_name(t) for t in new], targets_at(m, np.asarray(new)))
    return doc.to_bytes()


@SETTINGS
@given(
    data=motion_files(),
    step=st.integers(1, 60),
    block=st.sampled_from([1, 2, 3, 8192]),
    size=st.sampled_from([1, 40, 1 << 20]),
)
def test_the_streamed_result_is_the_one_the_document_edits_make(
    data: bytes, step: int, block: int, size: int
) -> None:
    doc = loads(data)
    gridded = GridResample(doc, doc.motion, step)
    with (
        mock.patch.object(resample_grid, "_BLOCK", block),
        mock.patch.object(document, "_STREAM_BYTES", size),
    ):
        blocks = list(gridded.blocks())
    assert b"".join(blocks) == reference(data, step)
    assert all(blocks)
    out = loads(b"".join(blocks)).motion
    assert (out.n_poses, out.duration_ms) == (gridded.n_poses, gridded.duration_ms)
    assert gridded.inserted + doc.motion.n_poses - gridded.dropped == gridded.n_poses


@SETTINGS
@given(
    data=motion_files(),
    step=st.integers(1, 60),
    block=st.sampled_from([1, 2, 5, 8192]),
    chunk=st.sampled_from([1, 3, 1 << 14]),
    sparse=st.booleans(),
    timestep=st.sampled_from([1, 7, 20]),
)
def test_a_comparison_a_window_at_a_time_is_the_one_with_the_result_read_back(
    data: bytes, step: int, block: int, chunk: int, sparse: bool, timestep: int
) -> None:
    doc = loads(data)
    original = doc.motion
    gridded = GridResample(doc, original, step)
    if not gridded.marker_free():
        return  # compared whole (resample reads the result back)
    back = loads(b"".join(gridded.blocks())).motion
    limit = 0 if sparse else compare.EVERY_STEP_LIMIT  # the steps next to the pose times
    with (
        mock.patch.object(compare, "EVERY_STEP_LIMIT", limit),
        mock.patch.object(compare_steps, "_CHUNK_STEPS", chunk),
        mock.patch.object(resample_grid, "_BLOCK", block),
    ):
        played = compare_motions(original, gridded, timestep_ms=timestep, tolerance=ROUNDING_RAD)
        whole = compare_motions(original, back, timestep_ms=timestep, tolerance=ROUNDING_RAD)
    assert repr(played) == repr(whole)
