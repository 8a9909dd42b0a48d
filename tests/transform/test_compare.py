"""Semantic diff (motiontool.motionfmt.compare)."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import corpus_params
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from strategies import motion_files

from motiontool.motionfmt import format_motion, loads, read_bytes, read_file
from motiontool.motionfmt.compare import JointDiff, MotionDiff, compare_motions, held_targets
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
