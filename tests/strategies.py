"""Hypothesis strategies shared by the tests."""

from __future__ import annotations

from hypothesis import strategies as st

_cell = st.one_of(
    st.floats(min_value=-4, max_value=4, allow_nan=False).map(repr),
    st.sampled_from(["*", "0", "-0", ".5", "5.", "1e-3", "+1.5", "-9999999.9", " 2", "2rad"]),
)
NON_FINITE = ("nan", "inf", "-inf", "-nan", "Infinity", "NAN", "1e309", "-1e999")
"""Cells Webots reads as NaN or an infinity: commands it sends to the motor."""

# Times whose C int arithmetic wraps (m * 60000 + s * 1000 + ms), around 2**31 and 2**32.
WRAPPING_TIMES = (
    "35791:23:647",  # 2**31 - 1, the largest time that does not wrap
    "35791:23:648",  # 2**31: wraps to -2**31
    "35792:00:000",  # wraps negative
    "71582:47:295",  # 2**32 - 1: wraps to -1, Webots' 'undefined time'
    "71582:47:296",  # 2**32: wraps to 0
    "71582:47:396",  # wraps to 100
    "99999:99999:99999",
    "2147483647",
    "2147483648",
    "4294967296",
    "4294967396",
    "0:2147483",
    "0:2147484",
)


@st.composite
def motion_files(draw: st.DrawFn, *, non_finite: bool = False) -> bytes:
    """A small file Webots accepts, in varied spelling; ``non_finite`` adds nan/inf cells."""
    n_joints = draw(st.integers(1, 5))
    n_poses = draw(st.integers(1, 8))
    gaps = draw(st.lists(st.integers(1, 300), min_size=n_poses, max_size=n_poses))
    start = draw(st.integers(0, 200))
    times = [start + sum(gaps[:i]) for i in range(n_poses)]
    cell = st.one_of(_cell, st.sampled_from(NON_FINITE)) if non_finite else _cell
    lines = ["#WEBOTS_MOTION,V1.0," + ",".join(f"J{j}" for j in range(n_joints))]
    for p, t in enumerate(times):
        style = draw(st.sampled_from(["ms", "s:ms", "m:s:ms"]))
        tt = {
            "ms": str(t),
            "s:ms": f"{t // 1000}:{t % 1000:03d}",
            "m:s:ms": f"{t // 60000:02d}:{t // 1000 % 60:02d}:{t % 1000:03d}",
        }[style]
        cells = [draw(cell) for _ in range(n_joints)]
        lines.append(",".join([tt, f"P{p}", *cells]))
    eol = draw(st.sampled_from(["\n", "\r\n"]))
    return (eol.join(lines) + draw(st.sampled_from(["", eol]))).encode()


@st.composite
def time_tokens(draw: st.DrawFn, n_fields: int) -> tuple[int, str]:
    """(exact ms, token) of a time with ``n_fields`` fields of 1-5 digits (zero-padded to a
    random width), sometimes one that wraps a C int."""
    if n_fields == 3 and draw(st.integers(0, 5)) == 0:
        token = draw(st.sampled_from([t for t in WRAPPING_TIMES if t.count(":") == 2]))
        m, s, ms = (int(f) for f in token.split(":"))
        return m * 60000 + s * 1000 + ms, token
    fields = [draw(st.integers(0, 99999)) for _ in range(n_fields)]
    if n_fields == 3 and draw(st.booleans()):  # mostly realistic minutes, sometimes huge
        fields[0] = draw(st.integers(0, 99))
    widths = [draw(st.integers(len(str(f)), 5)) for f in fields]
    token = ":".join(f"{f:0{w}d}" for f, w in zip(fields, widths, strict=True))
    exact = sum(f * u for f, u in zip(fields, (60000, 1000, 1)[-n_fields:], strict=True))
    return exact, token


@st.composite
def timed_files(draw: st.DrawFn) -> bytes:
    """A clean file whose times have 1-5 digit fields, some wrapping a C int; mostly in
    increasing order (so that the fast paths are taken), sometimes not."""
    n_joints = draw(st.integers(1, 3))
    n_poses = draw(st.integers(1, 6))
    n_fields = draw(st.integers(1, 3))
    times = [draw(time_tokens(n_fields)) for _ in range(n_poses)]
    if draw(st.integers(0, 3)):
        times.sort()
    if draw(st.integers(0, 3)) == 0:  # one plain-ms time of up to 10 digits
        p = draw(st.integers(0, n_poses - 1))
        token = draw(st.sampled_from([t for t in WRAPPING_TIMES if ":" not in t]))
        times[p] = (int(token), token)
    lines = ["#WEBOTS_MOTION,V1.0," + ",".join(f"J{j}" for j in range(n_joints))]
    for p, (_, token) in enumerate(times):
        cells = [repr(draw(st.floats(-4, 4, allow_nan=False))) for _ in range(n_joints)]
        lines.append(",".join([token, f"P{p}", *cells]))
    return ("\n".join(lines) + "\n").encode()
