"""plot draws a dense line from the points that draw it at the panel's resolution
(cli/_plotting.py ``_kept``): in each span of time its first and last point, its lowest and
highest, its first break; every point where a span has at most four."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from motiontool.cli._plotting import _SPANS, _first_lowest, _kept

SPANS = 5


@settings(max_examples=300, deadline=None)
@given(
    st.lists(st.integers(0, 3), min_size=2, max_size=120),
    st.lists(st.one_of(st.floats(-5, 5), st.just(float("nan"))), min_size=120, max_size=120),
    st.sets(st.integers(0, 119), max_size=12),
)
def test_each_span_keeps_its_ends_extremes_and_a_break(
    steps: list[int], ys: list[float], gaps: set[int]
) -> None:
    n = len(steps)
    x = np.cumsum(steps).astype(np.float64)
    y = np.array(ys[:n])
    x[[g for g in gaps if g < n]] = np.nan  # breaks in time, as the fast segments' line has
    kept = _kept(x, (y,), SPANS)
    timed = ~np.isnan(x)
    if n <= 4 * SPANS or not timed.any() or x[timed].max() <= x[timed].min():
        assert kept is None
        return
    assert kept is not None
    # The span of each point, a break the span of the time before it (the first, before any).
    lo, hi = x[timed].min(), x[timed].max()
    span = np.zeros(n, dtype=np.int64)
    last = None
    for i in range(n):
        last = x[i] if timed[i] else last
        if last is not None:
            span[i] = min(int((last - lo) * SPANS / (hi - lo)), SPANS - 1)
    finite = timed & ~np.isnan(y)
    for s in np.unique(span):
        inside = span == s
        idx = np.flatnonzero(inside)
        assert kept[idx[0]] and kept[idx[-1]]
        if (finite & inside).any():
            assert y[finite & inside & kept].min() == y[finite & inside].min()
            assert y[finite & inside & kept].max() == y[finite & inside].max()
        if (~finite & inside).any():
            assert (~finite & inside & kept).any()
    assert kept.sum() <= 5 * len(np.unique(span))


@pytest.mark.needs("plot")
def test_a_dense_line_is_drawn_without_markers_and_a_sparse_one_with_them() -> None:
    from matplotlib.figure import Figure

    from motiontool.cli._plotting import Panel, _draw_panel
    from motiontool.motionfmt import loads

    for poses, dense in ((50, False), (20 * _SPANS, True)):
        lines = "".join(f"{40 * p},P{p},{np.sin(p / 7):.4f}\n" for p in range(poses))
        motion = loads(f"#WEBOTS_MOTION,V1.0,HeadYaw\n{lines}".encode()).motion
        ax = Figure().subplots()
        t_s = motion.times_ms.astype(np.float64) / 1000
        _draw_panel(ax, motion, Panel("HeadYaw", ["HeadYaw"]), t_s, {}, None, None)
        (line,) = ax.lines
        x, _y = line.get_data()
        assert (line.get_marker() in (None, "None", "")) is dense
        assert x.shape[0] <= 5 * _SPANS if dense else x.shape[0] == poses


def test_diff_plots_old_and_new_from_the_points_either_keeps() -> None:
    from motiontool.cli._plotting import _decimated_pair

    t = np.arange(20 * _SPANS, dtype=np.float64)
    old, new = np.sin(t / 3), np.cos(t / 5)
    x, a, b = _decimated_pair(t, old, new)
    keep_old, keep_new = _kept(t, (old,), _SPANS), _kept(t, (new,), _SPANS)
    assert keep_old is not None and keep_new is not None
    keep = keep_old | keep_new
    assert x.tolist() == t[keep].tolist() and a.tolist() == old[keep].tolist()
    assert b.tolist() == new[keep].tolist() and x.shape[0] <= 10 * _SPANS
    short = t[:100]
    assert _decimated_pair(short, old[:100], new[:100])[0] is short


@settings(max_examples=300, deadline=None)
@given(
    st.lists(st.sampled_from([-1.0, 0.0, 2.5, float("inf")]), min_size=1, max_size=40),
    st.sets(st.integers(1, 39), max_size=10),
)
def test_the_lowest_point_of_a_span_is_its_first_lowest(
    values: list[float], cuts: set[int]
) -> None:
    """``_first_lowest``: per run, the first index of its lowest value (as a stable sort by
    run and value finds it; ties are frequent here, and the drawn point must not move)."""
    v = np.array(values)
    starts = np.array([0, *sorted(c for c in cuts if c < v.shape[0])])
    ends = [*starts[1:].tolist(), v.shape[0]]
    want = [a + int(np.argmin(v[a:b])) for a, b in zip(starts.tolist(), ends, strict=True)]
    assert _first_lowest(v, starts).tolist() == want
