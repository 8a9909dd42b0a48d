"""Library properties of resample and retime (motiontool.motionfmt.resample, motiontool.motionfmt.retime)."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from conftest import corpus_params
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from strategies import motion_files

from motiontool.errors import MotionToolError
from motiontool.motionfmt import loads, read_file, sample
from motiontool.motionfmt.compare import compare_motions
from motiontool.motionfmt.motion import Motion
from motiontool.motionfmt.resample import ROUNDING_RAD, grid_times, resample
from motiontool.motionfmt.retime import (
    MAX_TIME_MS,
    TimeOverflowError,
    fit_duration,
    fit_limits,
    scale_times,
)

TIMESTEPS = (1, 7, 8, 16, 20, 32, 40)
SETTINGS = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@st.composite
def motions(draw: st.DrawFn, *, min_gap: int = 1, star: bool = True, base: int = 1) -> bytes:
    """Motion files whose times are multiples of ``base`` ms, gaps >= ``min_gap`` bases."""
    n_joints = draw(st.integers(1, 4))
    n_poses = draw(st.integers(1, 9))
    gaps = draw(st.lists(st.integers(min_gap, 40), min_size=n_poses, max_size=n_poses))
    start = draw(st.integers(0, 10))
    times = [base * (start + sum(gaps[:i])) for i in range(n_poses)]
    value = st.floats(-2.5, 2.5, allow_nan=False).map(lambda x: repr(round(x, 4)))
    cell = st.one_of(value, st.just("*")) if star else value
    lines = ["#WEBOTS_MOTION,V1.0," + ",".join(f"J{j}" for j in range(n_joints))]
    for p, t in enumerate(times):
        cells = [draw(cell) for _ in range(n_joints)]
        lines.append(
            ",".join([f"{t // 60000:02d}:{t // 1000 % 60:02d}:{t % 1000:03d}", f"P{p}", *cells])
        )
    return ("\n".join(lines) + "\n").encode()


def assert_same_stream(a: Motion, b: Motion, timestep: int, *, reverse: bool = False) -> None:
    """Webots' command streams equal at ``timestep``: same steps commanded, same targets to
    within floating-point rounding of the interpolation."""
    sa, sb = sample(a, timestep, reverse=reverse), sample(b, timestep, reverse=reverse)
    assert np.array_equal(sa.elapsed_ms, sb.elapsed_ms)
    assert np.array_equal(np.isnan(sa.targets), np.isnan(sb.targets))
    both = ~np.isnan(sa.targets)
    assert np.all(np.abs(sa.targets[both] - sb.targets[both]) <= ROUNDING_RAD)


# --------------------------------------------------------------------------- resample


@SETTINGS
@given(data=motion_files(), divisor=st.sampled_from([1, 2, 4]))
def test_resample_onto_a_grid_holding_every_keyframe_is_lossless(data: bytes, divisor: int) -> None:
    doc = loads(data)
    m = doc.motion
    gcd = int(np.gcd.reduce(m.times_ms)) or m.duration_ms or 1
    step = max(gcd // divisor, 1) if gcd % divisor == 0 else gcd
    r = resample(doc, step_ms=step)
    out = r.document.motion
    assert r.grid_has_keyframes and r.dropped_off_grid == 0
    assert out.times_ms.tolist() == grid_times(int(m.times_ms[0]), m.duration_ms, step)
    for timestep in TIMESTEPS:
        assert_same_stream(m, out, timestep)
    assert_same_stream(m, out, 20, reverse=True)
    assert r.deviation.same
    # kept lines keep their spelling, byte for byte
    kept = set(data.split(b"\n")[1:]) - {b""}
    out_lines = set(r.document.to_bytes().split(b"\n"))
    assert {line.rstrip(b"\r") for line in kept} <= {line.rstrip(b"\r") for line in out_lines}
    assert doc.to_bytes() == data  # the input document is not modified


@SETTINGS
@given(data=motions(), step=st.integers(1, 50))
def test_resample_off_grid_reports_the_deviation_it_introduces(data: bytes, step: int) -> None:
    doc = loads(data)
    r = resample(doc, step_ms=step)
    out = r.document.motion
    assert out.times_ms[0] == doc.motion.times_ms[0] and out.duration_ms == doc.motion.duration_ms
    # The report's number is the true largest held-target deviation at 1 ms.
    again = compare_motions(doc.motion, out, timestep_ms=1)
    assert r.deviation.joints == again.joints


def test_new_keyframe_inside_a_star_segment_gets_a_star() -> None:
    doc = loads(b"#WEBOTS_MOTION,V1.0,A,B\n0,P1,0,*\n100,P2,1,2\n150,P3,0.5,1\n")
    r = resample(doc, step_ms=50)
    assert r.document.to_bytes() == (
        b"#WEBOTS_MOTION,V1.0,A,B\n0,P1,0,*\n50,Pose50ms,0.5,*\n100,P2,1,2\n150,P3,0.5,1\n"
    )


@SETTINGS
@given(data=motions(), bound=st.sampled_from([0.0, 1e-3, 0.05, 0.5]))
def test_max_error_keeps_every_joint_within_the_bound(data: bytes, bound: float) -> None:
    doc = loads(data)
    r = resample(doc, max_error=bound)
    out = r.document.motion
    assert out.n_poses == doc.motion.n_poses - r.removed
    assert r.collinear <= r.removed
    for timestep in (1, 20):
        sa, sb = sample(doc.motion, timestep), sample(out, timestep)
        assert np.array_equal(np.isnan(sa.targets), np.isnan(sb.targets))
        both = ~np.isnan(sa.targets)
        assert np.all(np.abs(sa.targets[both] - sb.targets[both]) <= bound + ROUNDING_RAD)
    assert r.deviation.same


@SETTINGS
@given(data=motions(), step=st.integers(1, 60), bound=st.sampled_from([0.0, 0.01]))
def test_grid_then_max_error_is_measured_against_the_original(
    data: bytes, step: int, bound: float
) -> None:
    doc = loads(data)
    grid = resample(doc, step_ms=step)
    both = resample(doc, step_ms=step, max_error=bound)
    worst_grid = grid.deviation.largest
    worst = both.deviation.largest
    assert (
        worst is None
        or worst_grid is None
        or (worst.max_delta <= max(bound, worst_grid.max_delta) + ROUNDING_RAD)
    )


def test_collinear_keyframes_go_for_free() -> None:
    doc = loads(b"#WEBOTS_MOTION,V1.0,A\n0,a,0\n10,b,0.1\n20,c,0.2\n30,d,0.30000001\n40,e,0\n")
    r = resample(doc, max_error=0.0)
    assert (r.removed, r.collinear) == (1, 1)
    assert (
        r.document.to_bytes()
        == b"#WEBOTS_MOTION,V1.0,A\n0,a,0\n20,c,0.2\n30,d,0.30000001\n40,e,0\n"
    )
    r = resample(doc, max_error=1e-6)
    assert (r.removed, r.collinear) == (2, 1)


def test_resample_needs_something_to_do() -> None:
    with pytest.raises(MotionToolError, match="nothing to do"):
        resample(loads(b"#WEBOTS_MOTION,V1.0,A\n0,a,0\n"))


@pytest.mark.parametrize("path", corpus_params())
def test_corpus_resample_lossless_and_simplified(path: object) -> None:
    doc = loads(read_file(str(path)), str(path))
    m = doc.motion
    step = int(np.gcd.reduce(m.times_ms)) or 1
    r = resample(doc, step_ms=step)
    for timestep in (8, 20, 32):
        assert_same_stream(m, r.document.motion, timestep)
    small = resample(doc, max_error=0.01)
    assert small.deviation.same and small.document.motion.n_poses <= m.n_poses


# --------------------------------------------------------------------------- retime

increasing_times = st.lists(st.integers(2, 400), min_size=1, max_size=12).flatmap(
    lambda gaps: st.integers(0, 300).map(
        lambda start: [start + sum(gaps[:i]) for i in range(len(gaps))]
    )
)


@settings(max_examples=300, deadline=None)
@given(times=increasing_times, k=st.floats(0.125, 2.0))
def test_retime_by_k_then_one_over_k_returns_within_1_ms(times: list[int], k: float) -> None:
    there = scale_times(times, k)
    assert all(b > a for a, b in zip(there.times_ms, there.times_ms[1:], strict=False))
    back = scale_times(there.times_ms, 1.0 / k)
    assert max(abs(a - b) for a, b in zip(back.times_ms, times, strict=True)) <= 1


@settings(max_examples=200, deadline=None)
@given(
    times=st.lists(st.integers(0, 10_000), min_size=2, max_size=12, unique=True),
    d=st.integers(0, 20_000),
)
def test_fit_duration_lands_exactly(times: list[int], d: int) -> None:
    times = sorted(times)
    if times[-1] == 0:
        return
    if d < len(times) - 1:
        with pytest.raises(MotionToolError, match="cannot hold"):
            fit_duration(times, d)
        return
    r = fit_duration(times, d)
    assert r.duration_ms == d
    assert all(b > a for a, b in zip(r.times_ms, r.times_ms[1:], strict=False))
    assert r.times_ms[0] >= 0


def _exact_retime(times: list[int], factor: Fraction, last: int | None) -> tuple[list[int], float]:
    """The definition: each t x factor as a Fraction, rounded half up, pushed to increase
    (pulled back below ``last`` where it is fixed); the largest rounding, ms."""
    exact = [t * factor for t in times]
    new = [math.floor(x + Fraction(1, 2)) for x in exact]
    for i in range(1, len(new)):
        new[i] = max(new[i], new[i - 1] + 1)
    if last is not None:
        new[-1] = last
        for i in range(len(new) - 2, -1, -1):
            new[i] = min(new[i], new[i + 1] - 1)
    return new, float(max(abs(n - x) for n, x in zip(new, exact, strict=True)))


@settings(max_examples=300, deadline=None)
@given(
    times=increasing_times,
    speed=st.floats(1e-3, 1e3) | st.sampled_from([0.1, 0.3, 1 / 3, 2.0, 7.0]),
    d=st.integers(1, MAX_TIME_MS),
)
def test_retiming_is_the_exact_rational_rounded_half_up(
    times: list[int], speed: float, d: int
) -> None:
    # Integer arithmetic gives what Fractions give, times and rounding alike.
    try:
        r = scale_times(times, speed)
    except TimeOverflowError:
        assert _exact_retime(times, 1 / Fraction(speed), None)[0][-1] > MAX_TIME_MS
    else:
        assert (list(r.times_ms), r.rounding_ms) == _exact_retime(times, 1 / Fraction(speed), None)
    if times[-1] > 0 and d >= len(times) - 1:
        r = fit_duration(times, d)
        want = _exact_retime(times, Fraction(d, times[-1]), d)
        assert (list(r.times_ms), r.rounding_ms) == want


def test_speed_rounds_half_up_and_keeps_times_increasing() -> None:
    assert scale_times([0, 1, 2, 3, 4], 2.0).times_ms == (0, 1, 2, 3, 4)
    assert scale_times([0, 10, 25], 2.0).times_ms == (0, 5, 13)
    assert scale_times([100, 200], 0.5).times_ms == (200, 400)
    with pytest.raises(MotionToolError, match="positive"):
        scale_times([0, 10], 0.0)


@st.composite
def limited_motions(draw: st.DrawFn) -> tuple[list[int], list[str], np.ndarray, dict[str, float]]:
    n_joints = draw(st.integers(1, 4))
    n_poses = draw(st.integers(1, 10))
    gaps = draw(st.lists(st.integers(1, 200), min_size=n_poses, max_size=n_poses))
    start = draw(st.integers(0, 100))
    times = [start + sum(gaps[:i]) for i in range(n_poses)]
    values = np.array(
        draw(
            st.lists(
                st.lists(
                    st.one_of(st.floats(-3, 3, allow_nan=False), st.just(math.nan)),
                    min_size=n_joints,
                    max_size=n_joints,
                ),
                min_size=n_poses,
                max_size=n_poses,
            )
        )
    )
    joints = [f"J{j}" for j in range(n_joints)]
    if n_joints > 1 and draw(st.booleans()):
        joints[-1] = joints[0]  # a duplicate column: held to the limit as well
    limits = {
        name: draw(st.floats(0.5, 30.0))
        for name in set(joints)
        if draw(st.integers(0, 4))  # some joints unconstrained
    }
    return times, joints, values, limits


def _velocity_ok(
    times: tuple[int, ...],
    joints: list[str],
    values: np.ndarray,
    limits: dict[str, float],
    margin: float,
) -> bool:
    d = np.diff(np.asarray(times)) / 1000.0
    for j, name in enumerate(joints):
        if name not in limits:
            continue
        with np.errstate(invalid="ignore"):
            speed = np.abs(np.diff(values[:, j])) / d
        if np.any(speed > limits[name] * margin):  # NaN compares False
            return False
    return True


@settings(max_examples=200, deadline=None)
@given(
    m=limited_motions(),
    margin=st.sampled_from([1.0, 0.9, 0.5]),
    accel=st.sampled_from([None, 5.0, 200.0]),
)
def test_fit_limits_never_violates_and_is_idempotent(
    m: tuple, margin: float, accel: float | None
) -> None:
    times, joints, values, limits = m
    r = fit_limits(times, joints, values, limits, margin=margin, max_acceleration=accel)
    assert r.times_ms[0] == times[0]
    assert all(b > a for a, b in zip(r.times_ms, r.times_ms[1:], strict=False))
    old_d, new_d = np.diff(times), np.diff(r.times_ms)
    assert np.all(new_d >= old_d)  # only ever longer
    assert _velocity_ok(r.times_ms, joints, values, limits, margin)
    # shortest: one ms less on a stretched velocity segment would break a limit
    for s in r.stretches:
        if s.reason == "velocity":
            shorter = list(r.times_ms)
            for i in range(s.segment + 1, len(shorter)):
                shorter[i] -= 1
            assert not _velocity_ok(tuple(shorter), joints, values, limits, margin)
    again = fit_limits(r.times_ms, joints, values, limits, margin=margin, max_acceleration=accel)
    assert again.times_ms == r.times_ms and again.stretches == ()
    if accel is not None:
        from motiontool.motionfmt.retime import _accel_ratio

        cols = [j for j, name in enumerate(joints) if name in limits]
        if len(times) > 1 and cols:
            with np.errstate(invalid="ignore"):
                dq = np.diff(values[:, cols], axis=0)
            ratio = _accel_ratio(np.diff(r.times_ms).astype(float), dq, accel)
            assert np.all(ratio <= 1.0)


@settings(max_examples=200, deadline=None)
@given(
    m=limited_motions(),
    step=st.sampled_from([1, 8, 10, 20, 32]),
    accel=st.sampled_from([None, 5.0, 200.0]),
)
def test_fit_limits_keeps_pose_times_on_the_step(m: tuple, step: int, accel: float | None) -> None:
    """A segment that was a whole number of controller steps is stretched to the fewest whole
    steps within the limits (so its pose times stay on the step: no MT209), and the result is
    still within them and a fixed point."""
    times, joints, values, limits = m
    r = fit_limits(times, joints, values, limits, max_acceleration=accel, step_ms=step)
    assert _velocity_ok(r.times_ms, joints, values, limits, 0.9)
    old_d, new_d = np.diff(times), np.diff(r.times_ms)
    assert np.all(new_d >= old_d)
    for s in r.stretches:
        if old_d[s.segment] % step == 0:
            assert new_d[s.segment] % step == 0
            if s.reason == "velocity":  # the fewest steps: one less breaks a limit
                shorter = list(r.times_ms)
                for i in range(s.segment + 1, len(shorter)):
                    shorter[i] -= step
                assert not _velocity_ok(tuple(shorter), joints, values, limits, 0.9)
    if accel is None:  # a segment off the step is stretched as without one: whole ms
        plain = np.diff(fit_limits(times, joints, values, limits).times_ms)
        off = old_d % step != 0
        assert np.array_equal(new_d[off], plain[off])
    again = fit_limits(r.times_ms, joints, values, limits, max_acceleration=accel, step_ms=step)
    assert again.times_ms == r.times_ms and again.stretches == ()


def test_fit_limits_stretches_to_the_shortest_whole_ms() -> None:
    # 0.262 rad in 40 ms at 6.40239 rad/s x 0.9: needs 45.47 ms -> 46 ms
    r = fit_limits([0, 40, 80], ["K"], np.array([[0.0], [0.262], [0.262]]), {"K": 6.40239})
    assert r.times_ms == (0, 46, 86)
    assert [(s.segment, s.old_ms, s.new_ms, s.joint, s.reason) for s in r.stretches] == [
        (0, 40, 46, "K", "velocity")
    ]
    assert (r.added_ms, round(r.added_percent or 0, 2)) == (6, 7.5)
    unlimited = fit_limits([0, 1], ["X"], np.array([[0.0], [9.0]]), {})
    assert unlimited.times_ms == (0, 1) and unlimited.unconstrained == ("X",)


def test_fit_limits_rejects_a_bad_margin() -> None:
    with pytest.raises(MotionToolError, match="margin"):
        fit_limits([0, 10], ["A"], np.zeros((2, 1)), {"A": 1.0}, margin=1.5)


@settings(max_examples=200, deadline=None)
@given(
    st.integers(2, 9),
    st.integers(1, 4),
    st.data(),
)
def test_fitting_velocities_in_numpy_is_fitting_them_segment_by_segment(
    n_poses: int, n_cols: int, draw: st.DataObject
) -> None:
    """fit_limits' numpy path (blocks of segments) stretches every segment to the duration, and
    names the joint, that its segment-by-segment loop does."""
    from unittest.mock import patch

    from motiontool.motionfmt import retime as fl

    gaps = draw.draw(st.lists(st.integers(1, 300), min_size=n_poses - 1, max_size=n_poses - 1))
    old = [int(t) for t in np.cumsum([0, *gaps])]
    value = st.floats(-4, 4) | st.sampled_from([0.0, math.nan, math.inf, 1e-9, 2.0, 1e306])
    rows = [[draw.draw(value) for _ in range(n_cols)] for _ in range(n_poses)]
    vlim = np.array([draw.draw(st.floats(0.01, 20) | st.just(math.inf)) for _ in range(n_cols)])
    names = [f"J{c % 2}" for c in range(n_cols)]  # two columns may share a joint name
    v = np.array(rows, dtype=np.float64)
    want_reason: dict[int, tuple[str, str]] = {}
    want = fl._fit_velocity(old, v, vlim, names, want_reason, vectorised=False)
    with patch.object(fl, "_SEGMENTS", draw.draw(st.integers(1, 4))):
        reason: dict[int, tuple[str, str]] = {}
        assert fl._fit_velocity(old, v, vlim, names, reason) == want
        assert reason == want_reason


def test_fitting_velocities_mends_the_rounding_of_its_first_guess_and_names_the_first_joint() -> (
    None
):
    """ceil(delta / vmax) in ms can be one too many (0.0003 rad at 0.1 rad/s: 4 ms, where
    3 ms keep within it, as the division decides); of two joints that need as long, the first
    is named. Both paths agree on it."""
    from motiontool.motionfmt import retime as fl

    v = np.array([[0.0, 0.0, 0.0], [0.00030000000000000003, 0.00030000000000000003, 0.0]])
    vlim = np.array([0.1, 0.1, 1.0])
    for vectorised in (True, False):
        reason: dict[int, tuple[str, str]] = {}
        assert fl._fit_velocity([0, 1], v, vlim, ["A", "B", "C"], reason, vectorised=vectorised)
        assert reason == {0: ("A", "velocity")}
        assert fl._fit_velocity([0, 1], v, vlim, ["A", "B", "C"], {}, vectorised=vectorised) == [3]


@SETTINGS
@given(data=motion_files(), speed=st.sampled_from([0.3, 0.7, 1.0, 2.5]), lines=st.integers(1, 3))
def test_retimed_blocks_write_what_set_times_makes(data: bytes, speed: float, lines: int) -> None:
    """``retime --speed`` streams its result (``retimed_blocks``): the bytes of the document whose
    times ``set_times`` set, in blocks of any size; every line keeps its own end."""
    from unittest.mock import patch

    from motiontool.motionfmt import retime
    from motiontool.motionfmt.ops import _cells

    doc = loads(data, "m.motion")
    times = list(scale_times([int(t) for t in doc.motion.times_ms], speed).times_ms)
    edited = doc.copy()
    edited.set_times(times)
    with patch.object(_cells, "BLOCK_LINES", lines):
        blocks = retime.retimed_blocks(doc, range(doc.n_poses), times, ends_as_header=False)
        assert b"".join(blocks) == edited.to_bytes()
