"""Semantic diff (motiontool.motionfmt.compare)."""

from __future__ import annotations

from unittest import mock

import numpy as np
import pytest
from conftest import corpus_params
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from strategies import motion_files

from motiontool.motionfmt import compare_steps, format_motion, loads, read_bytes, read_file
from motiontool.motionfmt.compare import (
    JointDiff,
    MotionDiff,
    compare_motions,
    held_pair,
    held_targets,
    joint_names,
)
from motiontool.motionfmt.motion import Motion

SETTINGS = settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def motion(text: str) -> Motion:
    return read_bytes(text.encode()).motion


def swapped(j: JointDiff) -> JointDiff:
    return JointDiff(
        j.joint,
        j.max_delta,
        j.at_ms,
        j.new_value,
        j.old_value,
        old_only_steps=j.new_only_steps,
        new_only_steps=j.old_only_steps,
        presence_at_ms=j.presence_at_ms,
    )


@SETTINGS
@given(data=motion_files(), timestep=st.sampled_from([1, 8, 20]))
def test_diff_of_a_motion_with_itself_is_empty(data: bytes, timestep: int) -> None:
    m = read_bytes(data).motion
    d = compare_motions(m, m, timestep_ms=timestep, tolerance=0.0)
    assert d.same and d.changed == () and not d.added and not d.removed and not d.reordered
    assert all(
        j.max_delta == 0.0 and not j.old_only_steps and not j.new_only_steps for j in d.joints
    )


@SETTINGS
@given(a=motion_files(), b=motion_files(), timestep=st.sampled_from([1, 20]))
def test_diff_is_symmetric_in_what_it_reports(a: bytes, b: bytes, timestep: int) -> None:
    ma, mb = read_bytes(a).motion, read_bytes(b).motion
    ab = compare_motions(ma, mb, timestep_ms=timestep)
    ba = compare_motions(mb, ma, timestep_ms=timestep)
    assert ab.same == ba.same
    assert (ab.added, ab.removed) == (ba.removed, ba.added)
    assert ab.reordered == ba.reordered
    assert (ab.old_duration_ms, ab.new_duration_ms) == (ba.new_duration_ms, ba.old_duration_ms)
    assert (ab.old_poses, ab.new_poses) == (ba.new_poses, ba.old_poses)
    assert {j.joint: j for j in ab.joints} == {j.joint: swapped(j) for j in ba.joints}
    assert {j.joint for j in ab.changed} == {j.joint for j in ba.changed}


@SETTINGS
@given(data=motion_files())
def test_respelled_file_is_the_same_motion(data: bytes) -> None:
    m = read_bytes(data).motion
    canonical = read_bytes(format_motion(m, newline="\r\n").encode()).motion
    assert compare_motions(m, canonical, tolerance=0.0).same


def _at_pose_times(old: Motion, new: Motion, timestep: int) -> MotionDiff:
    """The comparison of a grid too long to compare at every step: the steps next to each
    pose time only."""
    with mock.patch("motiontool.motionfmt.compare.EVERY_STEP_LIMIT", 0):
        return compare_motions(old, new, timestep_ms=timestep)


def _agrees_with_every_step(old: Motion, new: Motion, timestep: int) -> None:
    every = compare_motions(old, new, timestep_ms=timestep)
    fast = _at_pose_times(old, new, timestep)
    assert every.every_step and fast.grid_steps == every.grid_steps >= fast.compared_steps
    end = max(old.duration_ms, new.duration_ms)
    for e, f in zip(every.joints, fast.joints, strict=True):
        # Which side holds a target is the same along a run of steps: counted exactly.
        assert (f.old_only_steps, f.new_only_steps, f.presence_at_ms) == (
            e.old_only_steps,
            e.new_only_steps,
            e.presence_at_ms,
        )
        # The largest |Δq| is at a step next to a pose time, but for rounding.
        assert f.max_delta == pytest.approx(e.max_delta, rel=1e-12, abs=1e-12) or (
            f.max_delta == e.max_delta == np.inf
        )
        if f.at_ms is not None:  # the step it names has that |Δq| on every step's grid too
            _, a = held_targets(old, timestep, until_ms=end, names=[f.joint])
            _, b = held_targets(new, timestep, until_ms=end, names=[f.joint])
            k = f.at_ms // timestep
            assert (a[k, 0], b[k, 0]) == pytest.approx((f.old_value, f.new_value), nan_ok=True)


@SETTINGS
@given(a=motion_files(non_finite=True), b=motion_files(), timestep=st.sampled_from([1, 8, 20]))
def test_the_steps_next_to_pose_times_find_what_every_step_finds(
    a: bytes, b: bytes, timestep: int
) -> None:
    _agrees_with_every_step(read_bytes(a).motion, read_bytes(b).motion, timestep)


def test_a_segment_through_the_no_value_marker_is_compared_at_every_step() -> None:
    # Halfway from -19999999.8 to 0 the interpolated target is Webots' no-value marker,
    # -9999999.9, at one step (500 ms): nothing is sent there, the motor holds its last target.
    old = motion("#WEBOTS_MOTION,V1.0,A\n0,p,-19999999.8\n1000,q,0\n")
    new = motion("#WEBOTS_MOTION,V1.0,A\n0,p,-19999999.8\n1000,q,0.0000001\n")
    d = _at_pose_times(old, new, 1)
    (a,) = d.joints
    assert a.at_ms == 500 and a.max_delta == pytest.approx(20_000, rel=1e-6)  # 499 ms held
    _agrees_with_every_step(old, new, 1)


def test_a_run_of_steps_that_starts_holding_is_counted_from_its_first_step() -> None:
    # A's first command is sent at 201 ms (the segments before touch '*'): the new motion,
    # which commands it from 0 ms, holds a target alone for 201 steps, the first one at 0 ms.
    old = motion("#WEBOTS_MOTION,V1.0,A\n0,p,*\n100,q,*\n200,r,1\n300,s,1\n")
    new = motion("#WEBOTS_MOTION,V1.0,A\n0,p,1\n300,s,1\n")
    (a,) = _at_pose_times(old, new, 1).joints
    assert (a.new_only_steps, a.presence_at_ms) == (201, 0)
    _agrees_with_every_step(old, new, 1)
    _agrees_with_every_step(new, old, 20)


def test_a_motion_lasting_days_is_compared_in_a_moment() -> None:
    days = "#WEBOTS_MOTION,V1.0,A,B\n0,p,0,0\n40,q,1.5,*\n2000000000,r,0,{}\n"
    d = compare_motions(motion(days.format(0)), motion(days.format(0.1)))
    assert d.grid_steps == 2_000_000_001 and d.compared_steps < 20
    a, b = d.joints
    assert (a.max_delta, b.max_delta, b.at_ms) == (0.0, pytest.approx(0.1), 2_000_000_000)


def test_reports_the_largest_delta_per_joint_with_its_time() -> None:
    old = motion("#WEBOTS_MOTION,V1.0,A,B\n0,p,0,0\n100,q,1,0\n200,r,0,0\n")
    new = motion("#WEBOTS_MOTION,V1.0,B,A\n0,p,0,0\n100,q,0,0.8\n200,r,0,0\n")
    d = compare_motions(old, new)
    assert not d.same and d.reordered and not d.added and not d.removed
    a, b = d.joints
    assert (a.joint, a.at_ms, a.old_value, a.new_value) == ("A", 100, 1.0, 0.8)
    assert a.max_delta == pytest.approx(0.2, abs=1e-15)
    assert (b.joint, b.max_delta, b.at_ms) == ("B", 0.0, 0)
    assert [j.joint for j in d.changed] == ["A"]
    assert compare_motions(old, new, tolerance=0.2 + 1e-12).same


def test_held_targets_are_compared_where_one_side_sends_no_command() -> None:
    # Old: B holds 0 through the '*' segment; new writes the same hold explicitly: same.
    old = motion("#WEBOTS_MOTION,V1.0,A,B\n0,p,0,0\n100,q,1,*\n200,r,0,*\n")
    new = motion("#WEBOTS_MOTION,V1.0,A,B\n0,p,0,0\n100,q,1,0\n200,r,0,0\n")
    assert compare_motions(old, new).same
    # A joint never commanded by one side: a presence difference, not a number.
    never = motion("#WEBOTS_MOTION,V1.0,A,B\n0,p,0,*\n100,q,1,*\n200,r,0,*\n")
    d = compare_motions(never, new)
    (b,) = d.changed
    assert (b.joint, b.old_only_steps, b.new_only_steps, b.presence_at_ms) == ("B", 0, 201, 0)


def test_later_duplicate_column_wins_unless_it_sends_nothing() -> None:
    dup = motion("#WEBOTS_MOTION,V1.0,A,A\n0,p,5,1\n100,q,5,*\n")
    # t = 0: the later column sends 1; after it, its segment touches "*": the earlier one wins
    one = motion("#WEBOTS_MOTION,V1.0,A\n0,p,1\n1,m,5\n100,q,5\n")
    d = compare_motions(dup, one)
    assert d.same, d


def test_duration_and_joint_set_changes_are_differences() -> None:
    a = motion("#WEBOTS_MOTION,V1.0,A\n0,p,0\n100,q,0\n")
    longer = motion("#WEBOTS_MOTION,V1.0,A\n0,p,0\n300,q,0\n")
    wider = motion("#WEBOTS_MOTION,V1.0,A,C\n0,p,0,*\n100,q,0,*\n")
    d = compare_motions(a, longer)
    assert not d.same and d.changed == () and d.new_duration_ms == 300
    d = compare_motions(a, wider)
    assert not d.same and d.added == ("C",) and d.changed == ()


def test_held_targets_forward_fill() -> None:
    m = motion("#WEBOTS_MOTION,V1.0,A\n0,p,1\n40,q,*\n80,r,2\n")
    elapsed, held = held_targets(m, 20)
    assert elapsed.tolist() == [0, 20, 40, 60, 80]
    # (0, 80): segments touch '*', the motor holds 1; at 80 ms (the end) the last pose is sent
    assert held[:, 0].tolist() == [1.0, 1.0, 1.0, 1.0, 2.0]
    elapsed, held = held_targets(m, 20, until_ms=120)
    assert held[-1, 0] == 2.0 and elapsed[-1] == 120


@pytest.mark.parametrize("path", corpus_params())
def test_corpus_file_against_its_canonical_spelling(path: object) -> None:
    m = read_bytes(read_file(str(path))).motion
    canonical = read_bytes(format_motion(m).encode()).motion
    d: MotionDiff = compare_motions(m, canonical, timestep_ms=1, tolerance=0.0)
    assert d.same
    shifted = loads(read_file(str(path)))
    last = shifted.n_poses - 1
    if last > 0:
        shifted.set_time(last, int(m.times_ms[-1]) + 40)
        d = compare_motions(m, shifted.motion)
        assert not d.same and d.new_duration_ms - d.old_duration_ms == 40
    assert np.isfinite([j.max_delta for j in d.joints]).all()


@settings(max_examples=150, deadline=None)
@given(motion_files(), motion_files(), st.sampled_from([1, 7, 20]), st.integers(1, 5))
def test_held_pair_shapes_the_lines_through_every_step(
    old: bytes, new: bytes, step: int, chunk: int
) -> None:
    """``diff --plot`` draws the held targets at the steps ``held_pair`` picks (in chunks of a
    few steps here): they are those of every step there, and every step between two of them
    lies on the line between them."""
    a, b = read_bytes(old, "a.motion").motion, read_bytes(new, "b.motion").motion
    names = [n for n in joint_names(a) if n in set(joint_names(b))]
    with mock.patch.object(compare_steps, "_CHUNK_STEPS", chunk):
        elapsed, held_a, held_b = held_pair(a, b, step, names)
    end = max(a.duration_ms, b.duration_ms)
    assert elapsed[0] == 0 and elapsed[-1] == -(-end // step) * step
    assert (np.diff(elapsed) > 0).all()  # each step once, in order
    at = elapsed // step
    for motion, picked in ((a, held_a), (b, held_b)):
        _, full = held_targets(motion, step, until_ms=end, names=names)
        assert np.array_equal(picked, full[at], equal_nan=True)
        for i, j in zip(at[:-1].tolist(), at[1:].tolist(), strict=True):
            if j - i < 2:
                continue
            share = (np.arange(i + 1, j) - i)[:, None] / (j - i)
            line = full[i] + share * (full[j] - full[i])
            between = full[i + 1 : j]
            assert np.array_equal(np.isnan(between), np.isnan(line))  # breaks stay breaks
            assert np.allclose(between, line, rtol=1e-9, atol=1e-9, equal_nan=True)
