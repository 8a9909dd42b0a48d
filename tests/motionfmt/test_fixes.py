"""Fixes (motiontool.motionfmt.fixes): safe ones leave Webots' command stream bit-identical,
proved over the vendored Webots corpus and generated files; unsafe ones do what they say."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import corpus_params
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from strategies import motion_files

from motiontool.motionfmt.fixes import fix_bytes, plan_fixes, same_stream
from motiontool.motionfmt.player import hold_targets, sample
from motiontool.motionfmt.reader import read_bytes


def motor_stream(data: bytes, timestep_ms: int) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """What each motor (one per name) holds and whether it is sent something, step by step,
    at ``timestep_ms``: the stream Webots sends, merged by motor as the robot receives it."""
    motion = read_bytes(data, "x").motion
    stream = sample(motion, timestep_ms)
    names = list(dict.fromkeys(motion.joints))
    held = hold_targets(stream.targets, stream.commanded, motion.joints, names)
    return held.targets.view(np.int64), held.sent, names


def assert_same_commands(before: bytes, after: bytes) -> None:
    a, b = read_bytes(before, "x"), read_bytes(after, "x")
    assert a.accepted == b.accepted
    if not a.accepted:
        assert before == after  # a file Webots rejects is never touched
        return
    assert np.array_equal(a.motion.times_ms, b.motion.times_ms)
    for step in (1, 8, 20, 32):
        ta, sa, na = motor_stream(before, step)
        tb, sb, nb = motor_stream(after, step)
        assert na == nb and np.array_equal(sa, sb) and np.array_equal(ta, tb), step


@pytest.mark.parametrize("path", corpus_params())
def test_safe_fixes_keep_the_command_stream_of_every_corpus_file(path: Path) -> None:
    data = path.read_bytes()
    result = fix_bytes(data, path.name)
    assert all(f.safe for f in result.applied)
    assert_same_commands(data, result.data)
    assert same_stream(data, result.data)
    # Nothing safe is left to fix but what the proof refused.
    left = {f.code for f in plan_fixes(result.data, path.name)}
    assert left <= {f.code for f in result.refused}


_cells = st.sampled_from(["0", "1.5", "-0.25", "*", "2rad", "-9999999.9", " 0.5", "1e-1x", "3"])


@st.composite
def fixable_files(draw: st.DrawFn) -> bytes:
    """Files with what the safe fixes cover: units after numbers, the no-value marker, a joint
    named twice; sometimes a blank line or CRLF ends."""
    names = draw(st.lists(st.sampled_from(["A", "B", "C"]), min_size=1, max_size=4))
    n_poses = draw(st.integers(1, 6))
    t = draw(st.integers(0, 100))
    lines = ["#WEBOTS_MOTION,V1.0," + ",".join(names)]
    for p in range(n_poses):
        lines.append(",".join([str(t), f"P{p}", *(draw(_cells) for _ in names)]))
        t += draw(st.integers(1, 200))
    if draw(st.booleans()):
        lines.insert(draw(st.integers(2, len(lines))), "")
    eol = draw(st.sampled_from(["\n", "\r\n"]))
    return (eol.join(lines) + eol).encode()


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.one_of(fixable_files(), motion_files()))
def test_safe_fixes_keep_the_command_stream_of_generated_files(data: bytes) -> None:
    result = fix_bytes(data)
    assert_same_commands(data, result.data)
    again = fix_bytes(result.data)
    assert again.data == result.data  # fixing twice changes nothing more


def test_each_safe_fix() -> None:
    data = b"#WEBOTS_MOTION,V1.0,A,B\r\n00:00:000,P1,1,2rad\r\n00:00:040,P2,-9999999.9,3\r\n"
    result = fix_bytes(data)
    assert result.data == b"#WEBOTS_MOTION,V1.0,A,B\r\n00:00:000,P1,1,2\r\n00:00:040,P2,*,3\r\n"
    assert [f.code for f in result.applied] == ["MT203", "MT204"]


def test_a_joint_named_twice_is_merged_as_webots_merges_it() -> None:
    data = b"#WEBOTS_MOTION,V1.0,A,B,A\n0,P1,1,0,2\n40,P2,3,0,*\n80,P3,5,0,6\n"
    # The later A wins where it sends: P1 and P3; it sends nothing over 0-80 ms (a '*' end),
    # so the earlier A does there.
    merged = fix_bytes(data)
    if merged.refused:  # the merge would change the stream: the file is left as it is
        assert merged.data == data
    else:
        assert merged.data.startswith(b"#WEBOTS_MOTION,V1.0,A,B\n")
        assert_same_commands(data, merged.data)
    simple = b"#WEBOTS_MOTION,V1.0,A,B,A\n0,P1,1,0,2\n40,P2,3,0,4\n"
    result = fix_bytes(simple)
    assert result.data == b"#WEBOTS_MOTION,V1.0,A,B\n0,P1,2,0\n40,P2,4,0\n"
    assert_same_commands(simple, result.data)


def test_a_merge_that_would_change_the_stream_is_refused() -> None:
    # Over 0-40 ms no column sends A (each has a '*' end); one merged column would.
    data = b"#WEBOTS_MOTION,V1.0,A,A\n0,P1,1,*\n40,P2,*,4\n"
    result = fix_bytes(data)
    assert result.data == data and {f.code for f in result.refused} == {"MT205"}


def test_unsafe_fixes_do_what_the_file_evidently_means() -> None:
    # ',,' leaves C without a value (Webots rejects the line); the blank line cuts P2 off.
    data = b"#WEBOTS_MOTION,V1.0,A,B,C\n0,P1,1,,2\n\n40,P2,2,2,2\n"
    assert fix_bytes(data).data == data  # nothing safe to do
    result = fix_bytes(data, unsafe=True)
    assert result.data == b"#WEBOTS_MOTION,V1.0,A,B,C\n0,P1,1,*,2\n40,P2,2,2,2\n"
    assert [f.code for f in result.applied] == ["MT202", "MT201"]
    assert not any(f.safe for f in result.applied)
    # An empty cell whose fix would give too many values is left as it is.
    shifted = b"#WEBOTS_MOTION,V1.0,A,B\n0,P1,1,,2\n"
    assert fix_bytes(shifted, unsafe=True).data == shifted


def test_a_file_webots_rejects_is_never_touched() -> None:
    data = b"#WEBOTS_MOTION,V1.0,A\n0,P1,abc\n40,P2,2rad\n"
    assert fix_bytes(data).data == data
    assert fix_bytes(data, unsafe=True).data == data
    assert plan_fixes(data) == []
