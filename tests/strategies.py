"""Hypothesis strategies shared by the tests."""

from __future__ import annotations

from hypothesis import strategies as st

_cell = st.one_of(
    st.floats(min_value=-4, max_value=4, allow_nan=False).map(repr),
    st.sampled_from(["*", "0", "-0", ".5", "5.", "1e-3", "+1.5", "-9999999.9", " 2", "2rad"]),
)


@st.composite
def motion_files(draw: st.DrawFn) -> bytes:
    n_joints = draw(st.integers(1, 5))
    n_poses = draw(st.integers(1, 8))
    gaps = draw(st.lists(st.integers(1, 300), min_size=n_poses, max_size=n_poses))
    start = draw(st.integers(0, 200))
    times = [start + sum(gaps[:i]) for i in range(n_poses)]
    lines = ["#WEBOTS_MOTION,V1.0," + ",".join(f"J{j}" for j in range(n_joints))]
    for p, t in enumerate(times):
        style = draw(st.sampled_from(["ms", "s:ms", "m:s:ms"]))
        tt = {
            "ms": str(t),
            "s:ms": f"{t // 1000}:{t % 1000:03d}",
            "m:s:ms": f"{t // 60000:02d}:{t // 1000 % 60:02d}:{t % 1000:03d}",
        }[style]
        cells = [draw(_cell) for _ in range(n_joints)]
        lines.append(",".join([tt, f"P{p}", *cells]))
    eol = draw(st.sampled_from(["\n", "\r\n"]))
    return (eol.join(lines) + draw(st.sampled_from(["", eol]))).encode()
