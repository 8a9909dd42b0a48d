"""``resample --max-error``'s greedy with the slope cone (``_Cone``) takes the same steps as
asking :func:`_window_ok` at every step (the quadratic reference), and the collinear count in
one pass is the count pose by pose."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import motion_files

from motiontool.motionfmt import read_bytes
from motiontool.motionfmt.document import loads
from motiontool.motionfmt.resample import _collinear, _simplify, _window_ok, resample

BOUNDS = st.sampled_from([0.0, 1e-12, 1e-6, 0.01, 0.1, 0.5, 3.0])


@st.composite
def dense(draw: st.DrawFn) -> bytes:
    """A motion of many poses near lines (exactly on them, a rounding off, or a bound off),
    with '*' runs: where the greedy reaches far and the cone answers most steps."""
    n_joints = draw(st.integers(1, 3))
    n = draw(st.integers(3, 60))
    times = np.cumsum(draw(st.lists(st.integers(1, 50), min_size=n, max_size=n)))
    rows = []
    for j in range(n_joints):
        slope, start = draw(st.floats(-0.01, 0.01)), draw(st.floats(-2, 2))
        noise = draw(st.sampled_from([0.0, 1e-16, 1e-12, 1e-6, 0.01]))
        col = start + slope * times + noise * np.sin(times * (j + 1.0))
        stars = draw(st.lists(st.integers(0, n - 1), max_size=3))
        rows.append([("*" if p in stars else repr(float(x))) for p, x in enumerate(col)])
    lines = ["#WEBOTS_MOTION,V1.0," + ",".join(f"J{j}" for j in range(n_joints))]
    lines += [
        ",".join([str(int(t)), f"P{p}", *(rows[j][p] for j in range(n_joints))])
        for p, t in enumerate(times)
    ]
    return ("\n".join(lines) + "\n").encode()


@settings(max_examples=300, deadline=None)
@given(st.one_of(motion_files(), dense()), BOUNDS)
def test_the_cone_takes_the_steps_of_the_window_check(data: bytes, bound: float) -> None:
    motion = read_bytes(data, "m.motion").motion
    fast = _simplify(motion, motion, bound)
    slow = _simplify(motion, motion, bound, cone=False)
    assert fast == slow


@settings(max_examples=100, deadline=None)
@given(dense(), st.integers(5, 40), BOUNDS)
def test_the_cone_on_a_grid_takes_the_steps_of_the_window_check(
    data: bytes, step: int, bound: float
) -> None:
    """Against the original while the poses are the grid's (resample --step --max-error)."""
    doc = loads(data)
    grid = resample(doc, step_ms=step).document.motion
    assert _simplify(grid, doc.motion, bound) == _simplify(grid, doc.motion, bound, cone=False)


@settings(max_examples=200, deadline=None)
@given(st.one_of(motion_files(), dense()))
def test_collinear_in_one_pass_is_the_count_pose_by_pose(data: bytes) -> None:
    m = read_bytes(data, "m.motion").motion
    t, v = m.times_ms, m.values
    inner = np.arange(1, m.n_poses - 1, dtype=np.intp)
    each = sum(_window_ok(t, v, i - 1, i + 1, t, v, 0.0) for i in inner.tolist())
    assert _collinear(t, v, inner) == each


def test_a_long_line_is_one_segment_in_linear_time() -> None:
    """40,001 poses on a line: two kept, and the cone answers (the reference would ask the
    window check 40,000 times over up to 40,000 poses each)."""
    t = np.arange(0, 800_001, 20)
    body = "".join(f"{x},P{k},{x * 1e-6!r}\n" for k, x in enumerate(t.tolist()))
    doc = loads(("#WEBOTS_MOTION,V1.0,HeadYaw\n" + body).encode())
    out = resample(doc, max_error=0.001)
    assert out.document.n_poses == 2 and out.removed == out.collinear == 40_000 - 1
