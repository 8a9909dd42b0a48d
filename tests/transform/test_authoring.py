"""Library properties of mirror, concat, trim and scale (motiontool.motionfmt.ops)."""

from __future__ import annotations

import math
from collections import Counter
from unittest.mock import patch

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from strategies import motion_files

from motiontool.errors import MotionToolError
from motiontool.kinematics.checks import Limits, Velocity
from motiontool.kinematics.mirror import mirror_map
from motiontool.kinematics.robots import load_robot
from motiontool.motionfmt import loads
from motiontool.motionfmt.ops import _cells as cells_module
from motiontool.motionfmt.ops.concat import concat
from motiontool.motionfmt.ops.mirror import mirror
from motiontool.motionfmt.ops.scale import _respelt, scale
from motiontool.motionfmt.ops.trim import trim
from motiontool.motionfmt.player import commands_at
from motiontool.motionfmt.reader import read_bytes
from motiontool.motionfmt.resample import ROUNDING_RAD
from motiontool.motionfmt.validate import validate_bytes
from motiontool.motionfmt.writer import format_value, format_values

SETTINGS = settings(max_examples=50, deadline=None, suppress_health_check=[HealthCheck.too_slow])
NAO = load_robot("nao")
NAO_MIRROR = mirror_map(NAO).as_dict()
VMAX = {j.name: j.max_velocity for j in NAO.joints}
LIMITS = {j.name: (j.lower, j.upper, j.unit) for j in NAO.joints}
#: A synthetic map over the J0.. columns of ``motion_files``: a pair, a centre joint that
#: flips, one that keeps its sign, and J4 unknown to the map.
SYNTHETIC = {"J0": ("J1", -1), "J1": ("J0", -1), "J2": ("J2", -1), "J3": ("J3", 1)}
#: Joints of the Nao whose mirror image is within the partner's limits (ranges intersected).
NAO_JOINTS = (
    "HeadYaw",
    "HeadPitch",
    "LShoulderPitch",
    "RShoulderPitch",
    "LShoulderRoll",
    "RShoulderRoll",
    "LElbowRoll",
    "RElbowRoll",
    "LHipRoll",
    "RHipRoll",
    "LKneePitch",
    "RKneePitch",
)


def _safe_range(name: str) -> tuple[float, float]:
    """The values of ``name`` whose mirror image is within the partner's limits too."""
    lo, hi, _ = LIMITS[name]
    partner, sign = NAO_MIRROR[name]
    plo, phi, _ = LIMITS[partner]
    if sign < 0:
        plo, phi = -phi, -plo
    return max(lo, plo), min(hi, phi)


@st.composite
def nao_files(draw: st.DrawFn, *, star: bool = False, joints: list[str] | None = None) -> bytes:
    """A Nao motion that validates clean with limits and velocity: values within the mirror-safe
    ranges, segments slow enough (200-400 ms for at most 0.6 rad at >= 4 rad/s)."""
    if joints is None:
        joints = draw(st.lists(st.sampled_from(NAO_JOINTS), min_size=1, max_size=6, unique=True))
    n_poses = draw(st.integers(2, 6))
    lines = ["#WEBOTS_MOTION,V1.0," + ",".join(joints)]
    t = 0
    prev: list[float] = []
    for p in range(n_poses):
        row = []
        for k, name in enumerate(joints):
            lo, hi = _safe_range(name)
            if prev:
                lo, hi = max(lo, prev[k] - 0.6), min(hi, prev[k] + 0.6)
            row.append(round(draw(st.floats(lo, hi)), 4))
            row[-1] = min(max(row[-1], lo), hi)
        cells = [repr(v) for v in row]
        if star and p not in (0, n_poses - 1):
            cells = [draw(st.sampled_from([c, "*"])) for c in cells]
        lines.append(f"{t},P{p}," + ",".join(cells))
        prev = row
        t += draw(st.integers(200, 400))
    return ("\n".join(lines) + "\n").encode()


def clean(data: bytes, path: str = "m.motion") -> list[str]:
    """Every finding of validate's syntax level plus limits and velocity on the Nao."""
    report = validate_bytes(data, path, checks=[Limits(NAO), Velocity(NAO)])
    return [d.format() for d in report.diagnostics]


# --------------------------------------------------------------------------- mirror


@SETTINGS
@given(motion_files())
def test_mirror_twice_is_the_identity_in_command_stream(data: bytes) -> None:
    doc = loads(data, "m.motion")
    once = mirror(doc, SYNTHETIC).document
    twice = mirror(once, SYNTHETIC).document
    assert twice.motion == doc.motion  # names, times, every value and '*' bit for bit


@SETTINGS
@given(motion_files())
def test_mirror_swaps_and_negates_exactly_and_keeps_other_lines(data: bytes) -> None:
    doc = loads(data, "m.motion")
    m = doc.motion
    out = mirror(doc, SYNTHETIC).document.motion
    for j, name in enumerate(m.joints):
        if name not in SYNTHETIC:
            assert np.array_equal(out.values[:, j], m.values[:, j], equal_nan=True)
            continue
        partner, sign = SYNTHETIC[name]
        k = out.column(partner)
        assert np.array_equal(out.commanded[:, k], m.commanded[:, j])
        assert np.array_equal(out.values[:, k], sign * m.values[:, j], equal_nan=True)
    assert np.array_equal(out.times_ms, m.times_ms)
    assert out.pose_names == m.pose_names


def test_mirror_keeps_digits_and_spelling() -> None:
    data = b"#WEBOTS_MOTION,V1.0,J0,J1,J2,J3\r\n0,A,0.10,+2.50, 1e-3,7\r\n40,B,*,-0,-0.5,7.0\r\n"
    out = mirror(loads(data, "m.motion"), SYNTHETIC).document.to_bytes()
    assert (
        out
        == b"#WEBOTS_MOTION,V1.0,J0,J1,J2,J3\r\n0,A,-2.50,-0.10, -1e-3,7\r\n40,B,-0,*,0.5,7.0\r\n"
    )


@SETTINGS
@given(nao_files())
def test_a_clean_nao_motion_mirrors_clean(data: bytes) -> None:
    assert clean(data) == []
    out = mirror(loads(data, "m.motion"), NAO_MIRROR).document
    assert clean(out.to_bytes()) == []
    assert mirror(out, NAO_MIRROR).document.motion == loads(data, "m.motion").motion


def test_mirror_refuses_a_joint_named_twice() -> None:
    data = b"#WEBOTS_MOTION,V1.0,J0,J0\n0,A,1,2\n"
    with pytest.raises(MotionToolError, match=r"joint 'J0' is named twice \(MT205\)"):
        mirror(loads(data, "m.motion"), SYNTHETIC)


# --------------------------------------------------------------------------- trim


@SETTINGS
@given(motion_files(), st.data())
def test_trim_keeps_the_command_stream_of_the_window(data: bytes, draw: st.DataObject) -> None:
    doc = loads(data, "m.motion")
    m = doc.motion
    if m.duration_ms < 2:
        return
    lo = draw.draw(st.integers(0, m.duration_ms - 1))
    hi = draw.draw(st.integers(lo + 1, m.duration_ms + 50))
    r = trim(doc, lo, hi)
    out = r.document.motion
    assert int(out.times_ms[0]) == 0
    assert out.duration_ms == min(hi, m.duration_ms) - lo
    # The boundary poses are exactly what Webots commands there.
    edges = np.array([lo, min(hi, m.duration_ms)], dtype=np.int64)
    want, sent = commands_at(m, edges)
    at = int(m.times_ms.searchsorted(lo))
    if at >= m.n_poses or int(m.times_ms[at]) != lo:
        assert np.array_equal(out.commanded[0], sent[0])
        assert np.array_equal(out.values[0], want[0], equal_nan=True)
    # Every millisecond strictly inside the window commands the same. (At a boundary that is
    # a kept pose, a joint whose segment into it touches '*' gets no command at that one
    # instant in the original: the kept line commands it, as written.)
    e = np.arange(1, out.duration_ms, dtype=np.int64)
    a, a_sent = commands_at(m, e + lo)
    b, b_sent = commands_at(out, e)
    assert np.array_equal(a_sent, b_sent)
    assert np.all(np.abs(a[a_sent] - b[b_sent]) <= ROUNDING_RAD * (1 + np.abs(a[a_sent])))
    a, a_sent = commands_at(m, np.array([lo + out.duration_ms]))
    b, b_sent = commands_at(out, np.array([out.duration_ms]))
    both = a_sent & b_sent
    assert np.all(np.abs(a[both] - b[both]) <= ROUNDING_RAD * (1 + np.abs(a[both])))


@SETTINGS
@given(nao_files(), st.data())
def test_a_clean_motion_trims_clean(data: bytes, draw: st.DataObject) -> None:
    doc = loads(data, "m.motion")
    end = doc.motion.duration_ms
    lo = draw.draw(st.integers(0, end - 1))
    hi = draw.draw(st.integers(lo + 1, end))
    assert clean(trim(doc, lo, hi).document.to_bytes()) == []


def test_trim_keeps_kept_lines_and_boundary_poses_are_exact() -> None:
    data = b"#WEBOTS_MOTION,V1.0,A,B\n0,P0,0,1\n100,P1,+0.30,*\n200,P2,0.6,2\n"
    r = trim(loads(data, "m.motion"), 25, 150)
    assert r.document.to_bytes() == (
        b"#WEBOTS_MOTION,V1.0,A,B\n0,Pose0ms,0.075,*\n75,P1,+0.30,*\n"
        # 0.3 + (150 - 100) * (0.6 - 0.3) / (200 - 100), as Webots computes it:
        b"125,Pose125ms,0.44999999999999996,*\n"
    )
    kept = trim(loads(data, "m.motion"), 25, 150, keep_times=True).document.motion
    assert kept.times_ms.tolist() == [25, 100, 150]


@SETTINGS
@given(motion_files(), st.data())
def test_trim_blocks_join_to_the_result_whatever_their_size(
    data: bytes, draw: st.DataObject
) -> None:
    doc = loads(data, "m.motion")
    end = doc.motion.duration_ms
    if end < 2:
        return
    lo = draw.draw(st.integers(0, end - 1))
    r = trim(doc, lo, draw.draw(st.integers(lo + 1, end + 50)), keep_times=draw.draw(st.booleans()))
    whole = b"".join(r.blocks())  # one block of lines (a generated file has few)
    with patch.object(cells_module, "BLOCK_LINES", draw.draw(st.integers(1, 3))):
        assert b"".join(r.blocks()) == whole
    assert r.document.to_bytes() == whole
    assert (r.document.n_poses, r.document.motion.duration_ms) == (r.n_poses, r.duration_ms)


@pytest.mark.parametrize(
    ("data", "lo", "hi", "want"),
    [
        # Every kept line ends as the header does; no final newline: none after the last line.
        (
            b"#WEBOTS_MOTION,V1.0,A\r\n0,P0,0\r\n100,P1,1\n200,P2,2",
            50,
            200,
            b"#WEBOTS_MOTION,V1.0,A\r\n0,Pose0ms,0.5\r\n50,P1,1\r\n150,P2,2",
        ),
        (
            b"#WEBOTS_MOTION,V1.0,A\r\n0,P0,0\r\n100,P1,1\n200,P2,2",
            0,
            200,
            b"#WEBOTS_MOTION,V1.0,A\r\n0,P0,0\r\n100,P1,1\r\n200,P2,2",
        ),
        # The lines after the terminating blank line stay, after the boundary pose.
        (
            b"#WEBOTS_MOTION,V1.0,A\r\n0,P0,0\r\n100,P1,1\n200,P2,2\r\n\r\nnot read\r\n",
            0,
            150,
            b"#WEBOTS_MOTION,V1.0,A\r\n0,P0,0\r\n100,P1,1\r\n150,Pose150ms,1.5\r\n\r\nnot read\r\n",
        ),
    ],
)
@pytest.mark.parametrize("lines", [1, 8192])
def test_trim_keeps_the_line_ends_and_what_follows_the_poses(
    data: bytes, lo: int, hi: int, want: bytes, lines: int
) -> None:
    r = trim(loads(data, "m.motion"), lo, hi)
    with patch.object(cells_module, "BLOCK_LINES", lines):
        assert b"".join(r.blocks()) == want


@pytest.mark.parametrize(("lo", "hi"), [(50, 50), (300, 400), (60, 20)])
def test_trim_refuses_an_empty_window(lo: int, hi: int) -> None:
    doc = loads(b"#WEBOTS_MOTION,V1.0,A\n0,P0,0\n200,P1,1\n", "m.motion")
    with pytest.raises(MotionToolError, match="nothing to keep"):
        trim(doc, lo, hi)


# --------------------------------------------------------------------------- concat


@SETTINGS
@given(st.lists(st.sampled_from(NAO_JOINTS), min_size=1, max_size=6, unique=True), st.data())
def test_concat_of_clean_motions_is_clean_and_keeps_both(
    names: list[str], draw: st.DataObject
) -> None:
    a = draw.draw(nao_files(joints=names))
    b = draw.draw(nao_files(joints=names[::-1]))  # the same joints in another order
    assert clean(a, "a.motion") == [] and clean(b, "b.motion") == []
    da, db = loads(a, "a.motion"), loads(b, "b.motion")
    mb = db.motion
    r = concat([da, db], max_velocity=VMAX)
    assert clean(r.document.to_bytes()) == []
    out = r.document.motion
    ma = da.motion
    n = ma.n_poses
    assert out.n_poses == n + mb.n_poses
    assert np.array_equal(out.values[:n], ma.values, equal_nan=True)
    order = [db.joints.index(j) for j in names]
    assert np.array_equal(out.values[n:], db.motion.values[:, order], equal_nan=True)
    (t,) = r.transitions
    assert int(out.times_ms[n]) - int(out.times_ms[n - 1]) == t.duration_ms
    # Shortest: one ms less would be too fast for some joint (or it is 1 ms already).
    delta = np.abs(out.values[n] - out.values[n - 1])
    vlim = np.array([VMAX[j] * 0.9 for j in names])
    assert np.all(delta / (t.duration_ms / 1000.0) <= vlim * (1 + 1e-12))
    if t.duration_ms > 1:
        assert np.any(delta / ((t.duration_ms - 1) / 1000.0) > vlim)


def test_concat_keeps_the_first_file_and_respells_only_the_next_times() -> None:
    a = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\r\n00:00:000,A,0,+0.10\r\n00:00:040,B,0.5,0.1\r\n"
    b = b"#WEBOTS_MOTION,V1.0,HeadPitch,HeadYaw\n00:00:100,C,0.2 ,1.0\n00:00:300,D,*,1.5\n"
    r = concat([loads(a, "a.motion"), loads(b, "b.motion")], max_velocity=VMAX)
    (t,) = r.transitions
    # HeadYaw 0.5 -> 1.0 rad at 0.9 x 8.26797 rad/s: 67.2 ms, so 68 ms.
    assert (t.duration_ms, t.joint, t.start_ms) == (68, "HeadYaw", 40)
    assert r.reordered == ("b.motion",)
    assert r.document.to_bytes() == (
        b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\r\n00:00:000,A,0,+0.10\r\n00:00:040,B,0.5,0.1\r\n"
        b"00:00:108,C,1.0,0.2 \r\n00:00:308,D,1.5,*\r\n"
    )


@pytest.mark.parametrize("lines", [1, 8192])
@pytest.mark.parametrize(
    ("inputs", "want"),
    [
        # The first input's line ends throughout; the last one's lack of a final newline.
        (
            [b"#WEBOTS_MOTION,V1.0,J\r\n0,A,0\r\n40,B,0.5\r\n", b"#WEBOTS_MOTION,V1.0,J\n0,C,1"],
            b"#WEBOTS_MOTION,V1.0,J\r\n0,A,0\r\n40,B,0.5\r\n41,C,1",
        ),
        (
            [b"#WEBOTS_MOTION,V1.0,J\n0,C,1\n9,D,2", b"#WEBOTS_MOTION,V1.0,J\r\n0,A,0\r\n"] * 2,
            b"#WEBOTS_MOTION,V1.0,J\n0,C,1\n9,D,2\n10,A,0\n11,C,1\n20,D,2\n21,A,0\n",
        ),
    ],
)
def test_concat_ends_its_lines_as_the_inputs_say(
    inputs: list[bytes], want: bytes, lines: int
) -> None:
    docs = [loads(data, f"{k}.motion") for k, data in enumerate(inputs)]
    with patch.object(cells_module, "BLOCK_LINES", lines):
        assert concat(docs, transition_ms=1).data == want


def test_concat_refuses_different_joints() -> None:
    a = loads(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n", "a.motion")
    b = loads(b"#WEBOTS_MOTION,V1.0,HeadPitch\n0,A,0\n", "b.motion")
    with pytest.raises(MotionToolError, match=r"b\.motion does not have the joints of a\.motion"):
        concat([a, b], transition_ms=10)


# --------------------------------------------------------------------------- scale


@SETTINGS
@given(nao_files(star=True), st.floats(0.0, 1.0), st.sampled_from(["first", "zero", "P1"]))
def test_scaling_down_a_clean_motion_stays_clean(data: bytes, k: float, about: str) -> None:
    doc = loads(data, "m.motion")
    r = scale(doc, k, about=about, limits=LIMITS)
    before = validate_bytes(data, "m.motion", checks=[Limits(NAO), Velocity(NAO)]).diagnostics
    after = validate_bytes(
        r.document.to_bytes(), "m.motion", checks=[Limits(NAO), Velocity(NAO)]
    ).diagnostics
    # No new finding: '*' notes and jumps after a '*' (MT207, MT304) at most, never more.
    assert Counter(d.code for d in after) <= Counter(d.code for d in before)
    assert r.clips == ()


@SETTINGS
@given(motion_files(), st.floats(0.0, 4.0), st.sampled_from(["first", "zero"]))
def test_scale_formula_and_clipping(data: bytes, k: float, about: str) -> None:
    doc = loads(data, "m.motion")
    m = doc.motion
    if not np.all(np.isfinite(m.values[m.commanded])):
        return
    limits = {name: (-1.0, 1.0, "rad") for name in m.joints[:2]}
    r = scale(doc, k, about=about, limits=limits)
    out = r.document.motion
    assert np.array_equal(out.commanded, m.commanded)
    for j, name in enumerate(m.joints):
        c = m.commanded[:, j]
        if not c.any():
            continue
        ref = 0.0 if about == "zero" else float(m.values[c, j][0])
        want = ref + k * (m.values[c, j] - ref)
        if name in limits:
            assert np.all(np.abs(out.values[c, j]) <= 1.0)
            want = np.clip(want, -1.0, 1.0)
        assert np.allclose(out.values[c, j], want, rtol=0, atol=1e-12)


@SETTINGS
@given(
    motion_files() | nao_files(star=True),
    st.floats(0.0, 4.0),
    st.sampled_from(["", " ", "\t", "+"]),
    st.data(),
)
def test_scale_respells_column_by_column_as_line_by_line(
    data: bytes, k: float, lead: str, draw: st.DataObject
) -> None:
    if lead:  # a cell with white space (kept) or '+' in front: the line-by-line path
        lines = data.split(b"\n")
        p = draw.draw(st.integers(1, len([x for x in lines if x.strip()]) - 1))
        cells = lines[p].split(b",")
        j = draw.draw(st.integers(2, len(cells) - 1))
        if lead == "+" and not cells[j][:1].isdigit():  # '+' only before a digit: '+1.5'
            lead = " "
        if cells[j].rstrip(b"\r") != b"*":  # white space before a '*' is a syntax error
            cells[j] = lead.encode() + cells[j]
        lines[p] = b",".join(cells)
        data = b"\n".join(lines)
    doc = loads(data, "m.motion")
    m = doc.motion
    with np.errstate(invalid="ignore"):
        new = np.where(m.commanded, k * m.values + 0.0, np.nan)
    changed = m.commanded & (new != m.values)
    if not np.isfinite(new[changed]).all():
        return
    want = _respelt(doc, new, changed, columns=False)
    assert _respelt(doc, new, changed) == want
    with patch.object(cells_module, "BLOCK_LINES", draw.draw(st.integers(1, 3))):  # in blocks
        assert _respelt(doc, new, changed) == want


@settings(max_examples=300, deadline=None)
@given(st.lists(st.floats(allow_infinity=False) | st.sampled_from([0.0, -0.0, 1e16, 1e-5])))
@example([math.nan, 2.0, -0.0, 0.5, 1e16, 1e-5, -1e300])
def test_format_values_spells_each_value_as_format_value(values: list[float]) -> None:
    def spelt(v: float) -> str:  # the canonical spelling, written out here as an oracle
        if math.isnan(v):
            return "*"
        text = repr(v)
        return text[:-2] if text.endswith(".0") else text

    got = format_values(np.array(values, dtype=np.float64))
    assert got == [spelt(v).encode() for v in values]
    assert [format_value(v) for v in values] == [spelt(v) for v in values]


def test_format_values_refuses_an_infinite_value_as_format_value() -> None:
    with pytest.raises(MotionToolError, match="cannot write an infinite joint value"):
        format_values(np.array([1.0, -math.inf]))


def test_scale_reports_clipping_with_its_unit_and_keeps_unchanged_cells() -> None:
    data = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n0,A,0.0,0.00\n100,B,1.5,0.00\n200,C,0.0,0.4\n"
    r = scale(loads(data, "m.motion"), 2.0, about="A", limits=LIMITS)
    (yaw, pitch) = r.clips
    assert (yaw.joint, yaw.count, yaw.side, yaw.at_ms, yaw.unit) == (
        "HeadYaw",
        1,
        "upper",
        100,
        "rad",
    )
    assert math.isclose(yaw.worst_excess, 3.0 - 2.08567)
    assert (pitch.joint, pitch.side) == ("HeadPitch", "upper")
    assert r.document.to_bytes() == (
        b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n0,A,0.0,0.00\n100,B,2.08567,0.00\n"
        b"200,C,0.0,0.514872\n"
    )


def test_scale_names_the_poses_when_the_reference_is_unknown() -> None:
    doc = loads(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,Start,0\n", "m.motion")
    with pytest.raises(
        MotionToolError, match=r"no pose named 'Stat' in m\.motion; give first, zero"
    ):
        scale(doc, 2.0, about="Stat")


def test_read_bytes_of_a_mirrored_corpus_like_file_matches_the_model_table() -> None:
    # The derived Nao table against a hand-checked expectation lives in
    # tests/kinematics/test_mirror.py; here: one row mirrored through the document layer.
    data = (
        b"#WEBOTS_MOTION,V1.0,HeadYaw,LHipYawPitch,RHipYawPitch,LAnkleRoll\n0,A,0.2,-0.3,-0.3,0.1\n"
    )
    out = read_bytes(mirror(loads(data, "m.motion"), NAO_MIRROR).document.to_bytes(), "m")
    assert out.joints == ["HeadYaw", "LHipYawPitch", "RHipYawPitch", "RAnkleRoll"]
    assert out.row(0) == [-0.2, -0.3, -0.3, -0.1] and len(out.times_ms) == 1
