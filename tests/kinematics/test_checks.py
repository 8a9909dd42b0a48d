"""The robot checks of ``validate``: exact messages on small motions, plain-loop oracles, the
real NAO's rules, robot selection, and every finding on the Webots corpus, justified."""

from __future__ import annotations

import itertools
import json
import os
import subprocess
import sys
from collections import Counter
from pathlib import Path
from typing import Any

import pytest
from conftest import CORPUS, DATA, ROBOT_FACTS, ROOT, calls_of, require
from hypothesis import given, settings
from hypothesis import strategies as st
from oracle import UNDEFINED, webots_load, webots_play

from motiontool.errors import MotionToolError
from motiontool.kinematics import load_robot
from motiontool.kinematics.checks import (
    CHECKS,
    DEFAULT_CHECKS,
    CheckUnavailableError,
    RobotChecks,
    Velocity,
    Wording,
    parse_checks,
    robot_checks,
)
from motiontool.motionfmt import (
    CODES,
    Diagnostic,
    Severity,
    ValidationReport,
    read_bytes,
    validate_bytes,
    validate_paths,
)

NAO_JSON = ROBOT_FACTS / "nao.json"


def findings(
    data: bytes, robot: str = "nao", checks: tuple[str, ...] = DEFAULT_CHECKS, **kw: object
) -> list[str]:
    """Every diagnostic of ``data`` as ``line:col: severity CODE: message``."""
    report = validate_bytes(data, "t.motion", checks=robot_checks(load_robot(robot), checks, **kw))
    return [d.format().removeprefix("t.motion:") for d in report.diagnostics]


def robot_findings(data: bytes, robot: str = "nao", **kw: object) -> list[str]:
    return [f for f in findings(data, robot, **kw) if " MT3" in f]


# --------------------------------------------------------------------------- codes and options


def test_robot_codes_are_registered_with_titles() -> None:
    for code, severity in [
        ("MT301", Severity.WARNING),
        ("MT302", Severity.ERROR),
        ("MT303", Severity.WARNING),
        ("MT304", Severity.WARNING),
        ("MT305", Severity.ERROR),
        ("MT306", Severity.ERROR),
        ("MT307", Severity.WARNING),
        ("MT308", Severity.WARNING),
        ("MT901", Severity.INFO),
    ]:
        assert CODES[code].severity is severity and CODES[code].title


def test_parse_checks() -> None:
    assert parse_checks("velocity, limits") == ("limits", "velocity")
    assert parse_checks(["all"]) == CHECKS
    assert DEFAULT_CHECKS == ("limits", "velocity", "collision")
    with pytest.raises(
        MotionToolError, match=r"unknown check 'colision'; did you mean 'collision'"
    ):
        parse_checks("limits,colision")
    with pytest.raises(MotionToolError, match="no check named"):
        parse_checks(",")


def test_balance_needs_feet_and_tolerance_is_a_depth() -> None:
    with pytest.raises(CheckUnavailableError, match="robot ur5e has no feet") as no_feet:
        robot_checks(load_robot("ur5e"), ["balance"])
    assert (no_feet.value.check, no_feet.value.robot) == ("balance", "ur5e")
    assert "--" not in str(no_feet.value)  # the CLI names its option (tests/cli)
    with pytest.raises(MotionToolError, match="must be a depth >= 0 mm"):
        robot_checks(load_robot("nao"), ["collision"], penetration_tolerance_mm=-1)


# --------------------------------------------------------------------------- limits


def test_position_limits_name_joint_time_value_bound_and_excess() -> None:
    data = (
        b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n"
        b"00:00:000,P1,0,0.6\n"
        b"00:00:500,P2,*,-0.7\n"
        b"00:01:000,P3,0,0\n"
    )
    assert robot_findings(data, checks=("limits",)) == [
        "2:16: error MT302: HeadPitch = 0.6 rad at 0 ms is above its upper limit 0.514872 rad"
        " by 0.085128 rad",
        "3:16: error MT302: HeadPitch = -0.7 rad at 500 ms is below its lower limit -0.671952 rad"
        " by 0.028048 rad",
    ]
    report = validate_bytes(data, "t.motion", checks=robot_checks(load_robot("nao"), ["limits"]))
    first = report.diagnostics[0]
    assert (first.joint, first.time_ms, first.column, first.end_column) == ("HeadPitch", 0, 16, 19)
    assert first.hint == (
        "Webots clamps the target to the motor's range [-0.671952, 0.514872] rad, and warns"
    )


@pytest.mark.needs("kinematics")
def test_star_cells_are_not_checked_and_the_later_duplicate_column_wins() -> None:
    # Where the later HeadYaw column sends a command it wins (MT205): the earlier one's 5 rad
    # never reaches the motor.
    shadowed = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadYaw\n0,P1,5,0\n1000,P2,*,0.1\n"
    assert robot_findings(shadowed) == []
    winning = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadYaw\n0,P1,0,5\n"
    assert robot_findings(winning, checks=("limits",)) == [
        "2:8: error MT302: HeadYaw = 5 rad at 0 ms is above its upper limit 2.08567 rad"
        " by 2.91433 rad"
    ]


@pytest.mark.needs("kinematics")
def test_the_earlier_duplicate_column_is_checked_where_the_later_sends_nothing() -> None:
    # Webots sends both HeadYaw columns in column order: at 500 ms the later one is '*', so the
    # earlier one's 2.5 rad reaches the motor (clamped, with a warning).
    data = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadYaw\n0,P1,0,0\n500,P2,2.5,*\n1000,P3,0,0\n"
    assert robot_findings(data) == [
        "3:8: error MT302: HeadYaw = 2.5 rad at 500 ms is above its upper limit 2.08567 rad"
        " by 0.41433 rad"
    ]
    report = validate_bytes(data, "t.motion", checks=robot_checks(load_robot("nao"), ["limits"]))
    (limit,) = [d for d in report.diagnostics if d.code == "MT302"]
    assert (limit.joint, limit.column, limit.end_column) == ("HeadYaw", 8, 11)
    # The segment Webots interpolates is the earlier column's too: 1 rad in 100 ms.
    fast = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadYaw\n0,P1,0,0\n100,P2,1,*\n"
    assert robot_findings(fast, checks=("velocity",)) == [
        "3:8: warning MT303: HeadYaw moves 1 rad in 100 ms (0 ms to 100 ms): 10 rad/s, above its"
        " maximum velocity 8.26797 rad/s by 1.73203 rad/s; the motor needs 120.9 ms and falls"
        " 20.9 ms behind"
    ]


@pytest.mark.needs("kinematics")
def test_a_value_exactly_at_a_limit_passes() -> None:
    data = b"#WEBOTS_MOTION,V1.0,HeadPitch,RElbowRoll\n0,P1,0.514872,0\n1000,P2,-0.671952,1.54462\n"
    assert robot_findings(data) == []


# --------------------------------------------------------------------------- velocity


@pytest.mark.needs("kinematics")
def test_segment_faster_than_max_velocity_says_how_late_the_motor_is() -> None:
    data = b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,P1,0\n100,P2,1\n200,P3,1\n"
    # 1 rad in 100 ms = 10 rad/s > 8.26797 rad/s: 1 / 8.26797 s = 120.9 ms, 20.9 ms late.
    assert robot_findings(data) == [
        "3:8: warning MT303: HeadYaw moves 1 rad in 100 ms (0 ms to 100 ms): 10 rad/s, above its"
        " maximum velocity 8.26797 rad/s by 1.73203 rad/s; the motor needs 120.9 ms and falls"
        " 20.9 ms behind"
    ]


@pytest.mark.needs("kinematics")
def test_command_stream_jump_after_a_star_stretch_is_one_warning() -> None:
    # '*' at 500 ms: no command from 20 ms until 1000 ms (both segments touch the '*'), then
    # at 1020 ms the target jumps from the held 0 to 1 + 20 * 0.4 / 1000 = 1.008 rad within
    # one 20 ms step: 50.4 rad/s; the motor needs 1.008 / 8.26797 s = 121.9 ms, 101.9 ms more.
    data = b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n500,B,*\n1000,C,1\n2000,D,1.4\n"
    assert robot_findings(data) == [
        "4:8: warning MT304: HeadYaw gets no command from 20 ms to 1000 ms ('*'), then its target"
        " jumps by 1.008 rad at 1020 ms, within one 20 ms controller step: 50.4 rad/s, above its"
        " maximum velocity 8.26797 rad/s by 42.132 rad/s; the motor falls 101.9 ms behind"
    ]
    # At a 5 ms step the jump is 4x faster but still one diagnostic, with that step.
    (only,) = robot_findings(data, timestep_ms=5)
    assert "at 1005 ms, within one 5 ms controller step: 200.4 rad/s" in only


@pytest.mark.needs("kinematics")
def test_infinite_targets_are_limit_errors_not_velocity_findings() -> None:
    # An 'inf' cell is sent and clamped: MT302 says so; its infinite speed is no MT303/MT304
    # (this used to crash the velocity check with an OverflowError).
    data = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n0,A,0,0\n500,B,nan,-inf\n1000,C,inf,0\n"
    assert [f.split(":")[2].strip() for f in robot_findings(data)] == [
        "error MT302",
        "error MT302",
    ]


@pytest.mark.needs("kinematics")
def test_uncommanded_joint_is_not_checked_where_it_is_not_commanded() -> None:
    # HeadYaw holds 0 while '*'; the file never asks it to move fast, and it stays put.
    data = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n0,A,0,0\n40,B,*,0.2\n80,C,*,0.1\n"
    assert robot_findings(data) == []


_NAO = load_robot("nao")
_VMAX = {j.name: j.max_velocity for j in _NAO.joints}
_LIMITS = {j.name: (j.lower, j.upper) for j in _NAO.joints}


@st.composite
def nao_motions(draw: st.DrawFn) -> bytes:
    names = draw(
        st.lists(st.sampled_from(["HeadYaw", "HeadPitch", "RElbowRoll"]), min_size=1, max_size=4)
    )
    n_poses = draw(st.integers(1, 7))
    gaps = draw(st.lists(st.integers(1, 120), min_size=n_poses, max_size=n_poses))
    times = [sum(gaps[:i]) for i in range(n_poses)]
    cell = st.one_of(
        st.just("*"), st.floats(-2.5, 2.5, allow_nan=False).map(lambda x: repr(round(x, 3)))
    )
    lines = ["#WEBOTS_MOTION,V1.0," + ",".join(names)]
    lines += [
        ",".join([str(t), f"P{p}", *(draw(cell) for _ in names)]) for p, t in enumerate(times)
    ]
    return ("\n".join(lines) + "\n").encode()


def _oracle(data: bytes, step: int) -> set[tuple[str, int, str, int | None]]:
    """(code, line, joint, time) of the limit and velocity findings, from plain loops over the
    oracle loader and player (no motiontool code). Of the columns that name one motor, Webots
    sends each in column order: the later column's command wins where it sends one."""
    loaded = webots_load(data)
    joints = [j.decode() for j in loaded.joints]
    out: set[tuple[str, int, str, int | None]] = set()
    times, values = loaded.times, loaded.values
    last = len(times) - 1
    stream = webots_play(times, values, step)

    def number(p: int, j: int) -> bool:
        return 0 <= p <= last and values[p][j] != UNDEFINED

    for name in set(joints):
        group = [j for j, n in enumerate(joints) if n == name]
        lo, hi = _LIMITS[name]
        for p in range(len(times)):
            sent = [
                j
                for j in group
                if number(p, j) and (p in (0, last) or number(p - 1, j) or number(p + 1, j))
            ]
            numbers = [j for j in group if number(p, j)]
            cell = (sent or numbers or [None])[-1]
            if cell is not None and not lo <= values[p][cell] <= hi:
                out.add(("MT302", p + 2, name, times[p]))
        fast_segments = set()
        for p in range(len(times) - 1):
            drivers = [j for j in group if number(p, j) and number(p + 1, j)]
            if not drivers:
                continue
            a, b = values[p][drivers[-1]], values[p + 1][drivers[-1]]
            if abs(b - a) / ((times[p + 1] - times[p]) / 1000) > _VMAX[name] * (1 + 1e-9):
                out.add(("MT303", p + 3, name, times[p + 1]))
                fast_segments.add(p)
        commanded = []
        for e, row in stream:
            targets = [row[j] for j in group if row[j] is not None]
            if targets:
                commanded.append((e, targets[-1]))
        worst: dict[int, tuple[float, int]] = {}
        for (e0, q0), (e1, q1) in itertools.pairwise(commanded):
            speed = abs(q1 - q0) / (step / 1000)
            if speed <= _VMAX[name] * (1 + 1e-9):
                continue
            if e1 - e0 > step:  # a jump after a '*' stretch
                pose = next(
                    p
                    for p in range(len(times))
                    if any(number(p, j) for j in group) and times[p] > e0
                )
            else:
                segs = [
                    p
                    for p in range(len(times) - 1)
                    if (times[p] < e1 and times[p + 1] > e0) or times[p] <= e0 < times[p + 1]
                ]
                if any(p in fast_segments for p in segs):
                    continue
                pose = max(segs) + 1
            if pose not in worst or speed > worst[pose][0]:
                worst[pose] = (speed, e1)
        out.update(("MT304", pose + 2, name, e1) for pose, (_s, e1) in worst.items())
    return out


@settings(max_examples=60, deadline=None)
@given(nao_motions(), st.sampled_from([5, 20]), st.integers(1, 7))
def test_the_command_stream_read_in_chunks_finds_what_the_whole_stream_finds(
    data: bytes, step: int, chunk: int
) -> None:
    """The velocity check reads the stream a chunk of steps at a time (flat memory whatever the
    duration): chunks of 1 to 7 steps give the findings of one chunk for it all."""
    from motiontool.kinematics.checks import velocity

    def found() -> list[Diagnostic]:
        checks = robot_checks(_NAO, ["velocity"], timestep_ms=step)
        return list(validate_bytes(data, "t.motion", checks=checks).diagnostics)

    whole = found()
    saved = velocity._STREAM_CHUNK
    velocity._STREAM_CHUNK = chunk
    try:
        assert found() == whole
    finally:
        velocity._STREAM_CHUNK = saved


@st.composite
def long_nao_motions(draw: st.DrawFn) -> bytes:
    """Motions of few poses over many controller steps: gaps up to 5 s (up to 5 000 steps),
    '*', 'nan' and 'inf' cells, Webots' no-value marker -9999999.9 (a target equal to it is not
    sent) and values whose segments pass through it."""
    names = draw(
        st.lists(st.sampled_from(["HeadYaw", "HeadPitch", "RElbowRoll"]), min_size=1, max_size=4)
    )
    n_poses = draw(st.integers(1, 6))
    gaps = draw(st.lists(st.integers(0, 5000), min_size=n_poses, max_size=n_poses))
    times = [sum(gaps[1 : i + 1]) for i in range(n_poses)]
    cell = st.one_of(
        st.just("*"),
        st.sampled_from(["nan", "inf", "-9999999.9", "-19999999.8", "1e7", "-9999999.8"]),
        st.floats(-2.5, 2.5, allow_nan=False).map(lambda x: repr(round(x, 3))),
    )
    lines = ["#WEBOTS_MOTION,V1.0," + ",".join(names)]
    lines += [
        ",".join([str(t), f"P{p}", *(draw(cell) for _ in names)]) for p, t in enumerate(times)
    ]
    return ("\n".join(lines) + "\n").encode()


@settings(max_examples=150, deadline=None)
@given(long_nao_motions(), st.sampled_from([1, 3, 8, 20, 40]), st.integers(1, 9))
def test_the_velocity_check_reads_the_steps_around_each_pose_and_finds_what_every_step_finds(
    data: bytes, step: int, chunk: int
) -> None:
    """Between two poses each target moves at its segment's speed, step after step (MT303's to
    judge): the check reads the steps around each pose time (and around a target equal to
    Webots' no-value marker), not every step, and finds what reading every step finds, in
    chunks of any size."""
    import numpy as np

    from motiontool.kinematics.checks import velocity

    def found() -> list[str]:
        checks = robot_checks(_NAO, ["velocity"], timestep_ms=step)
        return [str(d) for d in validate_bytes(data, "t.motion", checks=checks).diagnostics]

    read = found()
    saved = velocity.steps_read, velocity._STREAM_CHUNK
    velocity.steps_read = lambda motion, step, n: (np.array([0]), np.array([n]))
    try:
        every = found()
        velocity._STREAM_CHUNK = chunk
        assert found() == every
    finally:
        velocity.steps_read, velocity._STREAM_CHUNK = saved
    assert read == every


def test_the_velocity_check_of_a_motion_ending_at_2_31_ms_reads_a_few_steps(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A 3-line file whose last pose is past 2^31 ms took 10 s to validate: the check read
    all 107 million 20 ms steps. It reads the steps around each pose: a few dozen."""
    from motiontool.kinematics.checks import velocity

    read = calls_of(monkeypatch, velocity, "commands_at")  # (motion, elapsed)
    rows = b"0,P1,0,0\n40,P2,1.5,*\n2147483000,P3,0,1\n2147483640,P4,0,1\n"
    data = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n" + rows
    found = findings(data, checks=("velocity",), timestep_ms=20)
    assert [f.split(": ")[1] for f in found] == ["warning MT303", "warning MT207", "warning MT304"]
    assert "target jumps by 1 rad at 2147483020 ms" in found[2]
    assert 0 < sum(len(args[1]) for args, _ in read) <= 32  # of 107 374 183 steps


EXTREME = ["0", "0.5", "-2", "3.14", "1e30", "-1e200", "1e308", "-1e308", "5e-324", "*"]
EXTREME_TIMES = [0, 1, 8, 20, 40, 1000, 65536000, 2147483000, 2147483647]


@settings(max_examples=60, deadline=None)
@given(
    st.sampled_from(["nao", "ur5e"]),
    st.integers(1, 4),
    st.lists(st.sampled_from(EXTREME_TIMES), min_size=1, max_size=5, unique=True),
    st.data(),
    st.sampled_from([None, 8, 20]),
    st.booleans(),
)
def test_extreme_values_and_times_neither_raise_nor_warn(
    robot: str, n_joints: int, times: list[int], data: Any, step: int | None, group: bool
) -> None:
    """Values from 5e-324 to 1e308, '*' and times up to 2^31-1 ms through the default checks:
    findings, never an exception or a numpy warning (pytest makes a warning an error)."""
    spec = load_robot(robot)
    joints = spec.joint_names[:n_joints]
    lines = ["#WEBOTS_MOTION,V1.0," + ",".join(joints)]
    for k, t in enumerate(sorted(times)):
        minutes, rest = divmod(t, 60000)
        cells = data.draw(st.lists(st.sampled_from(EXTREME), min_size=n_joints, max_size=n_joints))
        lines.append(f"{minutes:02d}:{rest // 1000:02d}:{rest % 1000:03d},P{k}," + ",".join(cells))
    text = ("\n".join(lines) + "\n").encode()
    report = validate_bytes(
        text, "t.motion", timestep_ms=step, checks=robot_checks(spec), group=group
    )
    for d in report.diagnostics:
        d.format()
        report.fix_summary(d)


def test_values_too_far_apart_for_a_double_are_left_to_the_limits() -> None:
    """1e308 to -1e308 in 40 ms: the move overflows a double; the velocity check leaves it to
    MT302 without numpy's overflow warning (pytest turns a warning into an error here)."""
    data = b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,P1,1e308\n00:00:040,P2,-1e308\n"
    for step in (20, 8):
        found = findings(data, timestep_ms=step)
        assert [f.split(": ")[1] for f in found] == ["error MT302", "error MT302"], found
    # 0 to 1e308 in a second: a finite speed whose time needed overflows (a traceback once).
    data = b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,P1,0\n00:01:000,P2,1e308\n"
    report = validate_bytes(data, "t.motion", checks=robot_checks(load_robot("nao")))
    codes = [(d.code, d.hint) for d in report.diagnostics]
    assert [code for code, _hint in codes] == ["MT302", "MT303"], codes
    assert "give this move at least more time than a motion has" in str(codes[1][1])


@settings(max_examples=80, deadline=None)
@given(
    nao_motions(),
    st.sampled_from([5, 20]),
    st.lists(st.tuples(st.integers(-10, 700), st.integers(0, 300)), max_size=3),
)
def test_velocity_findings_at_chosen_times_are_those_of_the_whole_check(
    data: bytes, step: int, windows: list[tuple[int, int]]
) -> None:
    """``Velocity.at_times`` (concat's transitions) makes only the findings whose time it
    keeps: the same as every finding of the check, filtered by time."""
    import numpy as np

    check = Velocity(_NAO, step)
    result = read_bytes(data, "t.motion")

    def keep(times: np.ndarray) -> np.ndarray:
        inside = np.zeros(times.shape, dtype=bool)
        for lo, width in windows:
            inside |= (lo < times) & (times <= lo + width)
        return inside

    every = list(check(result))
    want = [d for d in every if keep(np.array([d.time_ms]))[0]]
    assert list(check.at_times(result, keep)) == want


@st.composite
def arm_motions(draw: st.DrawFn) -> bytes:
    """Nao motions whose right hand may go into the hip (a self-collision), their poses drawn
    from a small pool so that configurations repeat, with '*' cells."""
    names = ["RShoulderPitch", "RShoulderRoll", "RElbowYaw", "RElbowRoll", "LShoulderRoll"]
    cell = st.one_of(
        st.just("*"), st.floats(-2.0, 2.0, allow_nan=False).map(lambda x: repr(round(x, 2)))
    )
    hand_in_hip = ["1.7", "0.3", "-1.8", "0.3", "0"]
    pose = st.one_of(st.just(hand_in_hip), st.lists(cell, min_size=5, max_size=5))
    pool = draw(st.lists(pose, min_size=1, max_size=4))
    gaps = draw(st.lists(st.integers(1, 200), min_size=1, max_size=12))
    lines = ["#WEBOTS_MOTION,V1.0," + ",".join(names)]
    for p in range(len(gaps)):
        time_ms = sum(gaps[:p])
        lines.append(",".join([str(time_ms), f"P{p}", *draw(st.sampled_from(pool))]))
    return ("\n".join(lines) + "\n").encode()


@pytest.mark.needs("kinematics")
@settings(max_examples=40, deadline=None)
@given(arm_motions(), st.integers(1, 5), st.integers(0, 3), st.booleans())
def test_the_checks_read_in_blocks_find_what_one_block_finds(
    data: bytes, block: int, memo: int, group: bool
) -> None:
    """The velocity check compares keyframe segments, the collision check scans configurations
    a block of poses at a time and remembers so many configurations it met, the held targets
    are worked out a block at a time (flat memory whatever the motion's length): blocks of 1
    to 5 and memos of 0 to 3 give the findings of one block for it all, grouped or not."""
    from unittest import mock

    from motiontool.kinematics import collision
    from motiontool.kinematics.checks import _table, self_collision, velocity

    def found() -> list[Diagnostic]:
        checks = robot_checks(_NAO, ["limits", "velocity", "collision"])
        return list(validate_bytes(data, "t.motion", checks=checks, group=group).diagnostics)

    whole = found()
    with (
        mock.patch.object(velocity, "_SEGMENTS", block),
        mock.patch.object(self_collision, "_POSES", block),
        mock.patch.object(collision, "KNOWN_CONFIGURATIONS", memo),
        mock.patch.object(_table, "_HOLD_POSES", block),
    ):
        assert found() == whole


@pytest.mark.needs("kinematics")
def test_a_cycle_met_again_is_not_scanned_again(monkeypatch: pytest.MonkeyPatch) -> None:
    # A motion repeating one cycle over 6 blocks of poses, the right hand into the hip at its
    # first two poses: its configurations are scanned in the first block only, and the
    # contacts found in every block.
    from motiontool.kinematics import collision
    from motiontool.kinematics.checks import self_collision

    monkeypatch.setattr(self_collision, "_POSES", 4)
    cycle = ["1.7,0.3,-1.8,0.3", "1.7,0.3,-1.8,0.3", "-1.0,-0.3,1.5,1.5", "0,0,0,0"]
    lines = ["#WEBOTS_MOTION,V1.0,RShoulderPitch,RShoulderRoll,RElbowYaw,RElbowRoll"]
    lines += [f"{400 * p},P{p},{cycle[p % 4]}" for p in range(24)]
    scans = calls_of(monkeypatch, collision, "_scan_unique")  # (spec, unique, ...)
    checks = robot_checks(_NAO, ["collision"])
    report = validate_bytes(("\n".join(lines) + "\n").encode(), "t.motion", checks=checks)
    scanned = [args[1].shape[0] for args, _ in scans]
    assert scanned[0] > 0 and scanned[1:] == [0] * 5
    hits = [d for d in report.diagnostics if d.code == "MT307"]
    assert [d.line for d in hits] == [2 + 4 * k for k in range(6)]  # a run of 2 poses each
    assert all(
        "RWristYaw body 'r_hand' and RHipRoll body 'r_hip' overlap by 28.7 mm" in d.message
        for d in hits
    )


@settings(max_examples=150, deadline=None)
@given(nao_motions(), st.sampled_from([5, 20, 32]))
def test_limits_and_velocity_match_a_plain_loop_oracle(data: bytes, step: int) -> None:
    report = validate_bytes(
        data,
        "t.motion",
        checks=robot_checks(_NAO, ["limits", "velocity"], timestep_ms=step),
    )
    got = {
        (d.code, d.line, d.joint, d.time_ms) for d in report.diagnostics if d.code.startswith("MT3")
    }
    assert got == _oracle(data, step)


# --------------------------------------------------------------------------- unknown joints


@pytest.mark.needs("kinematics")
def test_unknown_joint_points_at_the_header_token_with_did_you_mean() -> None:
    data = b"#WEBOTS_MOTION,V1.0,HeadYw,HeadPitch\n0,P1,0,0\n"
    report = validate_bytes(data, "t.motion", checks=robot_checks(_NAO))
    (d,) = report.diagnostics
    assert d.format() == (
        "t.motion:1:21: warning MT301: unknown joint 'HeadYw' for robot nao; did you mean 'HeadYaw'?"
    )
    assert (d.end_column, d.joint) == (27, "HeadYw")
    assert d.hint == "Webots ignores this column (with a warning); rename it 'HeadYaw'"


@pytest.mark.needs("kinematics")
def test_unknown_joint_without_a_close_name_lists_the_motors() -> None:
    (d,) = validate_bytes(
        b"#WEBOTS_MOTION,V1.0,wheel_left\n0,P,0\n", "t", checks=robot_checks(load_robot("ur5e"))
    ).diagnostics
    assert d.message == "unknown joint 'wheel_left' for robot ur5e"
    assert "shoulder_pan_joint, shoulder_lift_joint" in (d.hint or "")
    assert (d.hint or "").endswith("; or name another robot explicitly")  # no CLI flag


@pytest.mark.needs("kinematics")
def test_hints_name_the_callers_robot_option() -> None:
    # The CLI says how its user names a robot; the library only passes it on.
    data = b"#WEBOTS_MOTION,V1.0,wheel_left\n0,P,0\n"
    wording = Wording(robot_option="--robot")
    checks = robot_checks(load_robot("ur5e"), wording=wording)
    (d,) = validate_bytes(data, "t", checks=checks).diagnostics
    assert (d.hint or "").endswith("; or name another robot with --robot")
    (note,) = RobotChecks("auto", wording=wording)(read_bytes(data, "t"))
    assert note.code == "MT901"
    assert note.hint == (
        "name the robot with --robot (nao, nao-v5, ur5e, a .urdf/.xml path, or erd:<name>)"
    )


# --------------------------------------------------------------------------- real NAO rules


def test_nao_v5_head_envelope_and_hip_yaw_pitch_coupling_are_errors() -> None:
    data = (
        b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch,LHipYawPitch,RHipYawPitch\n"
        b"0,P1,1.5,0.4,-0.5,-0.5\n"
        b"1000,P2,0,0.3,-0.4,*\n"
    )
    # At HeadYaw 1.5 rad the envelope (nao-v5.json) allows HeadPitch up to
    # 0.200015 + (1.5 - 1.526988) / (1.089958 - 1.526988) * (0.300022 - 0.200015) = 0.206191.
    assert robot_findings(data, "nao-v5", checks=("limits",)) == [
        "2:10: error MT305: HeadPitch = 0.4 rad at HeadYaw = 1.5 rad (0 ms) is above 0.206191 rad,"
        " the real robot's limit at that yaw, by 0.193809 rad",
        "3:15: error MT306: RHipYawPitch = -0.5 rad at 1000 ms differs from LHipYawPitch = -0.4"
        " rad by up to 0.1 rad: one motor drives LHipYawPitch and RHipYawPitch on the real robot",
    ]
    assert robot_findings(data, "nao", checks=("limits",)) == []


def test_nao_v5_fingers_are_one_hand_a_warning() -> None:
    data = b"#WEBOTS_MOTION,V1.0," + b",".join(b"RPhalanx%d" % i for i in range(1, 9))
    data += b"\n0,P1,1,1,1,1,1,1,1,0\n1000,P2,0.5,0.5,0.5,0.5,0.5,0.5,0.5,0.5\n"
    assert robot_findings(data, "nao-v5", checks=("limits",)) == [
        "2:20: warning MT306: RPhalanx8 = 0 rad at 0 ms differs from RPhalanx1 = 1 rad by up to"
        " 1 rad: the real robot's hand has one motor for RPhalanx1..8: it opens and closes all"
        " the fingers together"
    ]


def test_values_differing_by_less_than_the_coupling_tolerance_pass() -> None:
    data = b"#WEBOTS_MOTION,V1.0,LHipYawPitch,RHipYawPitch\n0,P,-0.3,-0.3009\n"
    assert robot_findings(data, "nao-v5", checks=("limits",)) == []


# --------------------------------------------------------------------------- collision, balance

ARM_IN_TORSO = (
    b"#WEBOTS_MOTION,V1.0,RShoulderPitch,RShoulderRoll,RElbowRoll\n"
    b"0,P1,0,0,0\n1000,P2,1.4,0.3,1.5\n2000,P3,1.4,0.3,1.5\n3000,P4,0,0,0\n"
)


@pytest.mark.needs("kinematics")
def test_self_collision_names_bodies_time_and_depth_once_per_run() -> None:
    # The right forearm and hand folded across the belly sink into the torso's capsule.
    assert robot_findings(ARM_IN_TORSO) == [
        "3:1: warning MT307: RElbowRoll body 'r_forearm' and root body 'torso' overlap by 32.7 mm at 1000 ms (pose 'P2'); they"
        " overlap from 1000 ms to 2000 ms",
        "3:1: warning MT307: RWristYaw body 'r_hand' and root body 'torso' overlap by 49.0 mm at 1000 ms (pose 'P2'); they"
        " overlap from 1000 ms to 2000 ms",
    ]
    assert robot_findings(ARM_IN_TORSO, penetration_tolerance_mm=40) == [
        "3:1: warning MT307: RWristYaw body 'r_hand' and root body 'torso' overlap by 49.0 mm at 1000 ms (pose 'P2'); they"
        " overlap from 1000 ms to 2000 ms",
    ]


@pytest.mark.needs("kinematics")
def test_a_pair_that_collides_in_many_runs_is_one_finding_when_grouped() -> None:
    """The arm folded into the belly 12 times, unfolded between: 12 runs of r_hand in the
    torso. Grouped (more than MAX_RUNS runs) one finding for the pair at its deepest; not
    grouped, a finding per run."""
    from motiontool.motionfmt.grouping import MAX_RUNS

    lines = [f"{k * 1000},P{k},{'1.4,0.3,1.5' if k % 2 else '0,0,0'}".encode() for k in range(25)]
    data = b"#WEBOTS_MOTION,V1.0,RShoulderPitch,RShoulderRoll,RElbowRoll\n" + b"\n".join(lines)
    checks = robot_checks(load_robot("nao"), ("collision",), penetration_tolerance_mm=40)
    grouped = validate_bytes(data + b"\n", "t.motion", checks=checks, group=True)
    assert [d.format().removeprefix("t.motion:") for d in grouped.diagnostics] == [
        "3:1: warning MT307: RWristYaw body 'r_hand' and root body 'torso' overlap by 49.0 mm at 1000 ms (pose 'P1'); they"
        " overlap at 12 instants in 12 runs, from 1000 ms to 23000 ms"
    ]
    assert MAX_RUNS < 12
    each = validate_bytes(data + b"\n", "t.motion", checks=checks, group=False)
    assert len(each.diagnostics) == 12


@pytest.mark.needs("kinematics")
def test_collision_at_a_segment_midpoint_only() -> None:
    # Both poses are clear; halfway, the elbow turning over brings the hand into the belly.
    data = (
        b"#WEBOTS_MOTION,V1.0,RShoulderPitch,RShoulderRoll,RElbowYaw,RElbowRoll\n"
        b"0,P1,2,0.3,-1,1.1\n1000,P2,1.3,0.1,1.7,1.2\n"
    )
    assert robot_findings(data) == [
        "3:1: warning MT307: RElbowRoll body 'r_forearm' and root body 'torso' overlap by 17.1 mm at 500 ms, halfway from 0 ms"
        " to 1000 ms",
        "3:1: warning MT307: RWristYaw body 'r_hand' and root body 'torso' overlap by 37.0 mm at 500 ms, halfway from 0 ms to"
        " 1000 ms",
    ]


@pytest.mark.needs("kinematics")
def test_out_of_range_values_are_clamped_before_the_collision_check() -> None:
    # LShoulderRoll -0.5 is past its -0.314159 limit (MT302); Webots stops the arm at the
    # limit, where the raised arm clears the head by more than the tolerance.
    data = b"#WEBOTS_MOTION,V1.0,LShoulderPitch,LShoulderRoll\n0,P1,-1.5,-0.5\n"
    assert robot_findings(data) == [
        "2:11: error MT302: LShoulderRoll = -0.5 rad at 0 ms is below its lower limit -0.314159"
        " rad by 0.185841 rad"
    ]
    # Every overlap, as deep as with the arm at its limit (unclamped, l_elbow would be 25 mm
    # into the head).
    assert robot_findings(data, penetration_tolerance_mm=0)[:2] == [
        "2:1: warning MT307: HeadPitch body 'head' and LElbowYaw body 'l_elbow' overlap by 5.6 mm at 0 ms (pose 'P1')",
        "2:1: warning MT307: HeadPitch body 'head' and LShoulderRoll body 'l_upper_arm' overlap by 7.2 mm at 0 ms (pose 'P1')",
    ]
    at_limit = b"#WEBOTS_MOTION,V1.0,LShoulderPitch,LShoulderRoll\n0,P1,-1.5,-0.314159\n"
    assert robot_findings(at_limit, penetration_tolerance_mm=0) == [
        "2:1: warning MT307: HeadPitch body 'head' and LElbowYaw body 'l_elbow' overlap by 5.6 mm at 0 ms (pose 'P1')",
        "2:1: warning MT307: HeadPitch body 'head' and LShoulderRoll body 'l_upper_arm' overlap by 7.2 mm at 0 ms (pose 'P1')",
    ]


@pytest.mark.needs("kinematics")
def test_balance_is_opt_in_and_reports_the_margin_in_mm() -> None:
    data = (
        b"#WEBOTS_MOTION,V1.0,LHipPitch,RHipPitch\n0,P1,0,0\n1000,P2,-1.5,-1.5\n2000,P3,-1.5,-1.5\n"
    )
    assert robot_findings(data) == []
    (line,) = robot_findings(data, checks=("balance",))
    assert line.startswith(
        "3:1: warning MT308: centre of mass 165.3 mm outside the support polygon of the feet at"
        " 1000 ms (pose 'P2'); outside from 1000 ms to 2000 ms"
    )


# --------------------------------------------------------------------------- the salute


def test_salute_of_the_lesson_is_rejected_for_its_twelve_values() -> None:
    report = validate_paths([DATA / "robots" / "salute.motion"], checks=[RobotChecks("nao")])
    (d,) = report.diagnostics
    assert (d.code, d.line, d.column) == ("MT110", 2, 47)
    assert "expected 11 values (one per joint), found 12" in d.message


@pytest.mark.needs("kinematics")
def test_fixed_salute_passes_nao_and_breaks_the_real_robots_elbow_limit() -> None:
    path = DATA / "robots" / "salute_fixed.motion"
    nao = validate_paths([path], checks=[RobotChecks("nao")])
    assert not nao.failed()
    assert [(d.code, d.line) for d in nao.diagnostics] == [("MT206", 2), ("MT307", 2)]
    v5 = validate_paths([path], checks=[RobotChecks("nao-v5")])
    assert v5.failed()
    assert [(d.code, d.line, d.column) for d in v5.diagnostics] == [
        ("MT206", 2, 1),
        ("MT307", 2, 1),
        ("MT302", 3, 23),
    ]
    assert v5.diagnostics[0].message.startswith("first pose is at 1000 ms")
    assert v5.diagnostics[2].message == (
        "RElbowRoll = 0 rad at 2000 ms is below its lower limit 0.0349066 rad by 0.0349066 rad"
    )
    # The salute itself: with the elbow bent to 1.5 rad the hand sits 25 mm inside the head's
    # capsule, deeper than the shapes' coarseness explains; 1.2 rad clears it.
    assert v5.diagnostics[1].message == (
        "HeadPitch body 'head' and RWristYaw body 'r_hand' overlap by 25.0 mm at 1000 ms (pose 'Pose1')"
    )


# --------------------------------------------------------------------------- robot selection


def test_auto_picks_the_robot_per_file_and_notes_when_none_fits(tmp_path: Path) -> None:
    (tmp_path / "nao.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,P,3\n")
    (tmp_path / "arm.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,shoulder_pan_joint\n0,P,7\n")
    (tmp_path / "typo.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadPitch,HeadYw\n0,P,3,0\n")
    (tmp_path / "stray.motion").write_bytes(
        b"#WEBOTS_MOTION,V1.0,HeadPitch,HeadYw,Tail\n0,P,0,0,0\n"
    )
    (tmp_path / "mixed.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw,elbow_joint\n0,P,0,0\n")
    (tmp_path / "hexapod.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,hip_l0,knee_l0\n0,P,0,0\n")
    checker = RobotChecks("auto")
    report = validate_paths([tmp_path], checks=[checker])
    by_file = {Path(f.path).name: f.diagnostics for f in report.files}  # each file validated
    robots = {Path(p).name: (s.name if s else None) for p, s in checker.used.items()}
    assert robots == {"nao.motion": "nao", "arm.motion": "ur5e", "typo.motion": "nao",
                      "stray.motion": None, "mixed.motion": None,
                      "hexapod.motion": None}  # fmt: skip
    assert [d.code for d in by_file["nao.motion"]] == ["MT302"]
    assert [d.code for d in by_file["arm.motion"]] == ["MT302"]
    # Half of the joints are the Nao's: checked on the Nao, the typo named (MT301), the joint
    # it has checked (HeadPitch 3 rad is past its limit: MT302).
    assert [d.code for d in by_file["typo.motion"]] == ["MT301", "MT302"]
    assert "did you mean 'HeadYaw'?" in by_file["typo.motion"][0].message
    (stray,) = by_file["stray.motion"]
    assert stray.format().endswith(
        "1:31: info MT901: robot checks skipped: no built-in robot has half of its joints or"
        " more: nao has 1 of 3, not 'HeadYw', 'Tail' (did you mean 'HeadYaw'?); checked at"
        " syntax level only"
    )
    # The library names no CLI flag; the CLI passes its own (tests/cli: "with --robot").
    assert stray.hint == (
        "name the robot explicitly (nao, nao-v5, ur5e, a .urdf/.xml path, or erd:<name>)"
    )
    (mixed,) = by_file["mixed.motion"]
    assert mixed.message == (
        "robot checks skipped: nao and ur5e have 1 of its 2 joints each, so the joints do not"
        " say which robot it is for; checked at syntax level only"
    )
    (hexapod,) = by_file["hexapod.motion"]
    assert hexapod.message == (
        "robot checks skipped: no built-in robot (nao, nao-v5, ur5e) has any of its joints;"
        " checked at syntax level only"
    )


def test_unknown_robot_names_the_choices() -> None:
    with pytest.raises(MotionToolError, match=r"unknown robot 'nao5'; did you mean 'nao'\? choose"):
        RobotChecks("nao5")


@pytest.mark.needs("kinematics")
def test_limits_and_velocity_do_not_load_pinocchio_but_collision_does(tmp_path: Path) -> None:
    motion = tmp_path / "m.motion"
    motion.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,P,0\n100,Q,3\n")

    def run(checks: list[str]) -> str:
        code = (
            "import sys\nfrom motiontool.motionfmt import validate_paths\n"
            "from motiontool.kinematics.checks import RobotChecks\n"
            f"r = validate_paths([{str(motion)!r}], checks=[RobotChecks('nao', {checks!r})])\n"
            "print(sorted({d.code for d in r.diagnostics}), 'pinocchio' in sys.modules)"
        )
        env = {**os.environ, "XDG_CACHE_HOME": str(tmp_path / "cache")}
        proc = subprocess.run(
            [sys.executable, "-c", code],
            capture_output=True,
            text=True,
            check=True,
            cwd=ROOT,
            env=env,
        )
        return proc.stdout.strip()

    assert run(["limits", "velocity"]) == "['MT302', 'MT303'] False"
    assert run(["collision"]) == "[] True"  # builds the robot's tables, and stores them
    # From then on, Pinocchio only for the pairs numpy cannot clear: none here.
    assert run(["collision"]) == "[] False"


# --------------------------------------------------------------------------- the Webots corpus

#: Everything ``validate --robot nao`` finds in the motions that ship with Webots, per file:
#: (code, severity) -> count, and why. Errors are proven below against the PROTO's numbers.
CORPUS_FINDINGS: dict[str, tuple[dict[tuple[str, str], int], str]] = {
    "projects/robots/robotis/darwin-op/controllers/motion_player/hand_high.motion": (
        {("MT207", "warning"): 4, ("MT301", "warning"): 3},
        "a Darwin-OP motion, not a Nao one: none of its 3 joints is a Nao motor (MT301); its '*'"
        " cells leave joints uncommanded over whole segments (MT207, syntax level)",
    ),
    "projects/robots/softbank/dancing_nao/motions/Backwards.motion": ({}, "clean"),
    "projects/robots/softbank/dancing_nao/motions/Fall.motion": (
        {("MT303", "warning"): 2},
        "both ShoulderPitch move 1.3 and 1.5 rad in 100 ms (13 and 15 rad/s > 8.26797): the arms"
        " are thrown forward faster than the motors turn",
    ),
    "projects/robots/softbank/dancing_nao/motions/Forwards.motion": ({}, "clean"),
    "projects/robots/softbank/dancing_nao/motions/Forwards50.motion": (
        {("MT303", "warning"): 5},
        "KneePitch 0.257-0.262 rad in 40 ms (6.425-6.55 rad/s > 6.40239): 0.1-0.9 ms late, real"
        " but harmless",
    ),
    "projects/robots/softbank/dancing_nao/motions/HandDown.motion": (
        {("MT205", "warning"): 1, ("MT302", "error"): 2},
        "the header names LShoulderRoll twice, the 6th column is meant as RShoulderRoll: its"
        " -0.349 (fine for the right arm) drives LShoulderRoll below -0.314159",
    ),
    "projects/robots/softbank/dancing_nao/motions/HandHighLeft.motion": (
        {("MT207", "info"): 1, ("MT309", "info"): 1},
        "RShoulderPitch '*' after the first pose: it holds its target (note); its LShoulderRoll"
        " is HandHighRight's RShoulderRoll unnegated, an unmirrored copy (note, within limits)",
    ),
    "projects/robots/softbank/dancing_nao/motions/HandHighRight.motion": (
        {("MT207", "info"): 1, ("MT309", "info"): 1},
        "LShoulderPitch '*' after the first pose: it holds its target (note); the sibling of"
        " HandHighLeft: the two are unmirrored copies of each other (note)",
    ),
    "projects/robots/softbank/dancing_nao/motions/HandWaveLeft.motion": (
        {("MT207", "info"): 1, ("MT302", "error"): 7},
        "the left-arm copy of HandWave.motion keeps the right arm's ShoulderRoll values instead"
        " of mirroring them: -0.4 and -0.5 rad are below LShoulderRoll's -0.314159",
    ),
    "projects/robots/softbank/dancing_nao/motions/HandsUp.motion": (
        {("MT302", "error"): 4, ("MT303", "warning"): 1},
        "LShoulderRoll copies RShoulderRoll unmirrored (below -0.314159), and LShoulderPitch"
        " flips from 1.5 to -1.5 rad in 40 ms (75 rad/s)",
    ),
    "projects/robots/softbank/dancing_nao/motions/HandsUpNoWiggle.motion": ({}, "clean"),
    "projects/robots/softbank/dancing_nao/motions/Shoot.motion": (
        {("MT303", "warning"): 3},
        "the kick: LKneePitch up to 8.15 rad/s and LElbowRoll 7.3 rad/s, above 6.40239 and"
        " 7.19407 rad/s (up to 10.9 ms late)",
    ),
    "projects/robots/softbank/dancing_nao/motions/SideStepLeft.motion": ({}, "clean"),
    "projects/robots/softbank/dancing_nao/motions/SideStepRight.motion": ({}, "clean"),
    "projects/robots/softbank/dancing_nao/motions/TurnLeft10.motion": ({}, "clean"),
    "projects/robots/softbank/dancing_nao/motions/TurnLeft180.motion": (
        {},
        "clean: its feet boxes overlap by 10.0 mm, under the 15 mm tolerance",
    ),
    "projects/robots/softbank/dancing_nao/motions/TurnLeft40.motion": ({}, "clean"),
    "projects/robots/softbank/dancing_nao/motions/TurnRight40.motion": ({}, "clean"),
    "projects/robots/softbank/nao/controllers/nao_wave_hand/HandWave.motion": (
        {("MT207", "info"): 1},
        "LShoulderPitch '*' after the first pose (note)",
    ),
    "projects/robots/softbank/nao/motions/StandUpFromFront.motion": (
        {("MT303", "warning"): 4},
        "pushing up from the floor, both ShoulderPitch move 1.3-1.8 rad in 100 ms (up to"
        " 17.9 rad/s > 8.26797): 57-117 ms late",
    ),
    "projects/robots/softbank/nao/motions/TaiChi.motion": (
        {("MT206", "warning"): 1},
        "first pose at 3000 ms: the robot jumps to it (syntax level)",
    ),
    "projects/robots/softbank/nao/motions/Taichi.motion": (
        {("MT206", "warning"): 1, ("MT302", "error"): 14},
        "the older TaiChi: 14 values beyond the PROTO limits, every one of them brought back"
        " within range in the newer TaiChi.motion (proven below)",
    ),
    "projects/robots/softbank/nao/motions/TurnLeft60.motion": ({}, "clean"),
    "projects/robots/softbank/nao/motions/TurnRight60.motion": ({}, "clean"),
    "projects/robots/softbank/nao/motions/WipeForehead.motion": (
        {("MT206", "warning"): 1, ("MT209", "warning"): 12},
        "first pose at 213 ms (syntax level); 12 pose times (266, 453, 506 ms, ...) off the "
        "Nao's 20 ms step, checked without -t",
    ),
    "projects/samples/robotbenchmark/humanoid_sprint/controllers/sprinter/forward.motion": (
        {("MT303", "warning"): 1},
        "a Nao walk: LKneePitch 6.55 rad/s > 6.40239 rad/s, 0.9 ms late",
    ),
    "tests/api/motions/HexapodForwards.motion": (
        {("MT301", "warning"): 12, ("MT209", "warning"): 4},
        "a hexapod motion, not a Nao one: all 12 joints unknown to the Nao; 250, 750, 1250 and "
        "1750 ms are off the Nao's 20 ms step",
    ),
}


@pytest.fixture(scope="module")
def corpus_report(corpus: Path) -> ValidationReport:
    return validate_paths([corpus], checks=[RobotChecks("nao")])


def _proto_joints() -> dict[str, dict[str, float]]:
    doc = json.loads(require(NAO_JSON, "robot facts JSON").read_text(encoding="utf-8"))
    return {j["name"]: j for j in doc["joints"]}


def test_corpus_findings_per_file_are_all_justified(corpus_report: ValidationReport) -> None:
    found = {
        str(Path(f.path).relative_to(CORPUS)): dict(
            Counter((d.code, str(d.severity)) for d in f.diagnostics)
        )
        for f in corpus_report.files
    }
    assert found == {path: counts for path, (counts, _why) in CORPUS_FINDINGS.items()}


def test_corpus_limit_errors_are_real_against_the_proto(corpus_report: ValidationReport) -> None:
    """Every MT302 cell, read by the oracle loader, lies outside the PROTO's range."""
    proto = _proto_joints()
    errors = [d for d in corpus_report.diagnostics if d.code == "MT302"]
    assert len(errors) == 27
    for d in errors:
        loaded = webots_load(Path(d.path).read_bytes())
        names = [j.decode() for j in loaded.joints]
        column = max(i for i, n in enumerate(names) if n == d.joint)
        value = loaded.values[d.line - 2][column]
        joint = proto[d.joint]
        assert not joint["minPosition"] <= value <= joint["maxPosition"], d.format()
        bound = joint["minPosition"] if value < joint["minPosition"] else joint["maxPosition"]
        assert f"limit {bound:.6g} rad" in d.message


def test_corpus_velocity_warnings_are_real_against_the_proto(
    corpus_report: ValidationReport,
) -> None:
    proto = _proto_joints()
    warnings = [d for d in corpus_report.diagnostics if d.code == "MT303"]
    assert len(warnings) == 16
    for d in warnings:
        loaded = webots_load(Path(d.path).read_bytes())
        names = [j.decode() for j in loaded.joints]
        column = max(i for i, n in enumerate(names) if n == d.joint)
        p = d.line - 2
        speed = abs(loaded.values[p][column] - loaded.values[p - 1][column]) / (
            (loaded.times[p] - loaded.times[p - 1]) / 1000
        )
        assert speed > proto[d.joint]["maxVelocity"], d.format()


def test_corpus_taichi_limit_errors_were_fixed_upstream(corpus_report: ValidationReport) -> None:
    old = CORPUS / "projects/robots/softbank/nao/motions/Taichi.motion"
    new = webots_load((old.parent / "TaiChi.motion").read_bytes())
    proto = _proto_joints()
    names = [j.decode() for j in new.joints]
    cells = [d for d in corpus_report.diagnostics if d.path == str(old) and d.code == "MT302"]
    assert cells
    for d in cells:
        value = new.values[d.line - 2][names.index(d.joint)]
        assert proto[d.joint]["minPosition"] <= value <= proto[d.joint]["maxPosition"]


def test_corpus_hand_wave_left_is_the_right_arm_unmirrored(corpus: Path) -> None:
    nao = corpus / "projects/robots/softbank"
    right = webots_load((nao / "nao/controllers/nao_wave_hand/HandWave.motion").read_bytes())
    left = webots_load((nao / "dancing_nao/motions/HandWaveLeft.motion").read_bytes())
    assert [r[1] for r in right.values] == [r[1] for r in left.values]  # ShoulderRoll column
    lo, hi = _LIMITS["RShoulderRoll"]
    assert all(lo <= r[1] <= hi for r in right.values)


def test_auto_detection_on_the_corpus_follows_the_manifest(corpus: Path) -> None:
    manifest = [line.split("\t") for line in (corpus / "MANIFEST.tsv").read_text().splitlines()[1:]]
    checker = RobotChecks("auto")
    for _file in validate_paths([corpus], checks=[checker]).files:  # validated as read
        pass
    for path, *_rest, robot, _verdict in manifest:
        spec = checker.used[str(corpus / path)]
        # robotbenchmark's humanoid sprint is a Nao ("other" in the manifest)
        expected = "nao" if robot == "nao" or "humanoid_sprint" in path else None
        assert (spec.name if spec else None) == expected, path


def test_limit_findings_do_not_rebuild_the_table(monkeypatch: pytest.MonkeyPatch) -> None:
    # 63 000 MT302 on a 20 000-pose file took 35 s when every finding rebuilt the (P, K) view
    # of the table; the views are built once per check, whatever the number of findings.
    from motiontool.kinematics.checks import _table

    calls = []
    original = _table.Table._at_source
    monkeypatch.setattr(
        _table.Table, "_at_source", lambda self, cells: calls.append(1) or original(self, cells)
    )
    for poses in (10, 400):
        calls.clear()
        rows = "".join(f"{40 * p},P,{3 if p % 2 else -3},0\n" for p in range(poses))
        data = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n" + rows.encode()
        found = findings(data, checks=("limits",))
        assert sum(" MT302: " in f for f in found) == poses
        assert len(calls) <= 3


def test_the_velocity_check_of_a_long_motion_holds_a_chunk_of_its_stream_only() -> None:
    """Three poses over 5.5 hours: 1 000 000 controller steps. The whole stream would be tens
    of MB of arrays; read a chunk at a time, the check's memory does not grow with duration."""
    import tracemalloc

    data = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n0,P1,0,0\n40,P2,1.5,0\n20000000,P3,0,0.1\n"
    checks = robot_checks(_NAO, ["velocity"], timestep_ms=20)
    tracemalloc.start()
    try:
        found = list(validate_bytes(data, "long.motion", checks=checks).diagnostics)
        _current, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert [d.code for d in found] == ["MT303"]
    assert peak < 24 * 2**20  # a chunk: 65 536 steps; the whole stream: 1 000 000


def test_the_checks_of_one_file_share_one_table(monkeypatch: pytest.MonkeyPatch) -> None:
    """Limits, velocity and collision read the file's poses against the robot once; the
    arrays only the checks use are dropped once they are done (the findings made later keep
    the values, times and columns)."""
    from motiontool.kinematics.checks import _table

    built: list[_table.Table] = []
    original = _table.read_table

    def counting(*args: object) -> _table.Table:
        built.append(original(*args))  # type: ignore[arg-type]
        return built[-1]

    monkeypatch.setattr(_table, "read_table", counting)
    checks = RobotChecks("nao", ("limits", "velocity", "collision"))
    data = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n0,P1,0,0\n40,P2,2.5,0\n80,P3,0,0.1\n"
    found = validate_bytes(data, "t.motion", checks=[checks], group=True).diagnostics
    assert len(built) == 1 and "held" not in built[0].__dict__
    assert {d.code for d in found} == {"MT302", "MT303"}
    again = validate_bytes(data, "u.motion", checks=[checks], group=True)  # another file
    assert len(built) == 2 and len(again.diagnostics) == len(found)
