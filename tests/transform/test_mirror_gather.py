"""mirror's numpy gather path (``_mirror_gather``) against its per-cell path, byte for byte.

``mirror`` rearranges plain pose lines with one numpy gather of the file's bytes and every
other file cell by cell; the per-cell path (``_mirror_bytes(..., gather=False)``) is the
reference. On every generated file the bytes ``mirror`` writes are the reference's, and where
the gather applies its bytes are too.
"""

from __future__ import annotations

from unittest.mock import patch

import pytest
from hypothesis import HealthCheck, event, example, given, settings
from hypothesis import strategies as st

from motiontool.errors import MotionToolError
from motiontool.motionfmt import loads
from motiontool.motionfmt.ops import mirror as mirror_ops
from motiontool.motionfmt.ops.mirror import (
    _mirror_bytes,
    _mirror_gather,
    _mirror_plan,
    mirror,
    permute_cells,
)

Mapping = dict[str, tuple[str, int]]

#: Cells the gather takes: numbers as people and tools spell them, '*', the 'no value' marker.
PLAIN_CELLS = (
    "0",
    "0.0",
    "-0",
    "-0.0",
    "*",
    ".5",
    "-.5",
    "5.",
    "-5.",
    "7",
    "1e-300",
    "-1e-300",
    "-5E+10",
    "5E+10",
    "1e-3",
    "0x1p-3",
    "-0x1.8p1",
    "0X1P+2",
    "2rad",
    "-9999999.9",
    "3.14159265358979323846264338327950288419716939937510582097494459230781640628",
    "-0.000000000000000000000000000000000000000000000000000000000000000000000000001",
    "123456789012345678901234567890123456789012345678901234567890",
)
#: Cells that send a file down the per-cell path: white space or '+' in front.
ODD_CELLS = ("+1.5", " 2", "\t-3", "\x0b1", "+0", "\x0c.5")
#: Pose names: not UTF-8, UTF-8, with '-', '*', spaces; ' lead' and '+x' are odd starts.
NAMES = (b"P", b"Pose-1", b"P\xff\xfe", "名前".encode(), b"a b", b"*", b"-n", b" lead", b"+x")


@st.composite
def mirror_cases(draw: st.DrawFn) -> tuple[bytes, Mapping]:
    """A file Webots accepts (LF or CRLF, with or without a final newline, sometimes lines after
    a blank line) and a mirror map over its columns: pairs, centre joints, columns renamed to
    a missing partner (names of another length), columns the map does not know."""
    n_joints = draw(st.integers(1, 40))
    n_poses = draw(st.integers(1, 6))
    joints = [
        draw(st.sampled_from(["J", "Joint", "LeftShoulderPitch"])) + str(j) for j in range(n_joints)
    ]
    odd = draw(st.integers(0, 4)) == 0  # mostly files the gather takes
    cell = st.one_of(
        st.floats(-4, 4, allow_nan=False).map(repr),
        st.sampled_from(PLAIN_CELLS),
        st.sampled_from(ODD_CELLS if odd else PLAIN_CELLS),
    )
    lines = [b"#WEBOTS_MOTION,V1.0," + ",".join(joints).encode()]
    t = draw(st.integers(0, 100))
    for _ in range(n_poses):
        t += draw(st.integers(1, 100_000))
        style = draw(st.sampled_from(["ms", "s:ms", "m:s:ms"]))
        time = {
            "ms": str(t),
            "s:ms": f"{t // 1000}:{t % 1000:03d}",
            "m:s:ms": f"{t // 60000:02d}:{t // 1000 % 60:02d}:{t % 1000:03d}",
        }[style]
        name = draw(st.sampled_from(NAMES if odd else NAMES[:-2]))
        cells = [draw(cell) for _ in range(n_joints)]
        lines.append(b",".join([time.encode(), name, *(c.encode() for c in cells)]))
    if draw(st.integers(0, 9)) == 0:  # a number whose negation is the 'no value' marker
        p, j = draw(st.integers(1, n_poses)), draw(st.integers(0, n_joints - 1))
        cells = lines[p].split(b",")
        cells[2 + j] = b"9999999.9"
        lines[p] = b",".join(cells)
    eol = draw(st.sampled_from([b"\n", b"\r\n"]))
    if draw(st.booleans()):
        lines += [b"", b"after a blank line, ignored"]
    data = eol.join(lines) + draw(st.sampled_from([b"", eol]))

    mapping: Mapping = {}
    free = list(range(n_joints))
    while free:
        j = free.pop(0)
        kind = draw(st.sampled_from(["pair", "centre", "rename", "unmapped"]))
        sign = draw(st.sampled_from([1, -1]))
        if kind == "pair" and free:
            k = free.pop(draw(st.integers(0, len(free) - 1)))
            mapping[joints[j]] = (joints[k], sign)
            mapping[joints[k]] = (joints[j], sign)
        elif kind == "centre":
            mapping[joints[j]] = (joints[j], sign)
        elif kind == "rename":
            partner = draw(st.sampled_from(["K", "RightShoulderPitch"])) + str(j)
            mapping[joints[j]] = (partner, sign)
    return data, mapping


def _nao_like(n_poses: int, n_joints: int, cells: list[str], eol: bytes = b"\n") -> bytes:
    """A file whose cells repeat ``cells``, with swapped-pair columns L0, R0, L1, R1, ..."""
    joints = [f"{side}{j // 2}" for j in range(n_joints) for side in "LR"[j % 2]]
    lines = [b"#WEBOTS_MOTION,V1.0," + ",".join(joints).encode()]
    for p in range(n_poses):
        row = [cells[(p * n_joints + j) % len(cells)] for j in range(n_joints)]
        lines.append(f"{40 * p},Pose{p + 1},{','.join(row)}".encode())
    return eol.join(lines) + eol


def _lr_map(n_joints: int, sign: int = -1) -> Mapping:
    mapping: Mapping = {}
    for j in range(0, n_joints - 1, 2):
        mapping[f"L{j // 2}"] = (f"R{j // 2}", sign)
        mapping[f"R{j // 2}"] = (f"L{j // 2}", sign)
    return mapping


def _long_line() -> bytes:
    """A single pose whose line is 4094 bytes (with its newline, the longest Webots reads in
    one piece): 300 joints, the last number with 1087 digits."""
    data = _nao_like(1, 300, ["-1.234567", "9.8765432"])
    line = data.split(b"\n")[1]
    return data[:-1] + b"1" * (4094 - len(line)) + b"\n"


LONG_LINE = _long_line()
#: (label, file, map, whether the gather takes it)
EXTREMES: list[tuple[str, bytes, Mapping, bool]] = [
    ("long line", LONG_LINE, _lr_map(300), True),
    ("many joints", _nao_like(3, 600, ["0.1", "-0.2", "*"]), _lr_map(600), True),
    ("single pose", _nao_like(1, 2, ["0.5", "-0.5"]), _lr_map(2), True),
    ("zeros", _nao_like(2, 4, ["0", "-0", "0.0", "-0.000"]), _lr_map(4), True),
    ("stars and markers", _nao_like(2, 4, ["*", "-9999999.9", "1"]), _lr_map(4), True),
    ("digits", _nao_like(2, 2, [PLAIN_CELLS[20], PLAIN_CELLS[21]]), _lr_map(2), True),
    ("exponents", _nao_like(2, 4, ["1e-300", "-5E+10", "1E5", "-2e+0"]), _lr_map(4), True),
    ("hex floats", _nao_like(2, 4, ["0x1p-3", "-0x1.8p1", "0X1P+2", "0x.8"]), _lr_map(4), True),
    ("leading dots", _nao_like(2, 2, [".5", "-.5"]), _lr_map(2), True),
    ("2rad", _nao_like(2, 2, ["2rad", "-1rad"]), _lr_map(2), True),
    (
        "non-UTF-8 names",
        b"#WEBOTS_MOTION,V1.0,L0,R0\n0,P\xff\xfe,1,2\n40,\xe5\x90\x8d,3,-4\n",
        _lr_map(2),
        True,
    ),
    ("no final newline", _nao_like(2, 2, ["1", "-2"])[:-1], _lr_map(2), True),
    (
        "lines after a blank line",
        _nao_like(2, 2, ["1", "-2"]) + b"\nignored,after,the,blank,line\n",
        _lr_map(2),
        True,
    ),
    ("CRLF", _nao_like(3, 4, ["1", "-2", "*"], b"\r\n"), _lr_map(4), True),
    (
        "CRLF, lines after a blank line",
        _nao_like(2, 2, ["1", "-2"], b"\r\n") + b"\r\nignored\r\n",
        _lr_map(2),
        True,
    ),
    ("CRLF, no final newline", _nao_like(2, 2, ["1", "-2"], b"\r\n")[:-2], _lr_map(2), False),
    ("a '+' cell", _nao_like(2, 2, ["+1", "-2"]), _lr_map(2), False),
    ("white space", _nao_like(2, 2, [" 1", "-2 "]), _lr_map(2), False),
    ("a tab", _nao_like(2, 2, ["\t1", "-2"]), _lr_map(2), False),
    ("a name with a space in front", b"#WEBOTS_MOTION,V1.0,L0,R0\n0, P,1,2\n", _lr_map(2), False),
    (
        "renamed to a shorter name",
        b"#WEBOTS_MOTION,V1.0,Jabc\n0,P0,12\n100,P1,12\n",
        {"Jabc": ("J", -1)},
        True,
    ),
    (
        "renamed to a longer name",
        b"#WEBOTS_MOTION,V1.0,J,Q\n0,P0,1,22\n100,P1,-1,22\n",
        {"J": ("Jabcdef", -1), "Q": ("Q", 1)},
        True,
    ),
    ("nothing moves", _nao_like(2, 2, ["1", "-2"]), {"L0": ("L0", 1)}, False),
]


def _check(data: bytes, mapping: Mapping) -> tuple[str, bytes | None]:
    """Assert that ``mirror`` writes the per-cell path's bytes (or both refuse); which path
    wrote them, and the gather's bytes (None where it does not apply)."""
    doc = loads(data, "m.motion")
    try:
        plan = _mirror_plan(doc, mapping)
    except MotionToolError as e:
        assert "'no value' marker" in str(e)
        with pytest.raises(MotionToolError, match="'no value' marker"):
            mirror(doc, mapping)
        return "refused: the 'no value' marker", None
    reference = _mirror_bytes(doc, plan, gather=False)
    gathered = _mirror_gather(doc, plan)
    if gathered is not None:
        assert gathered == reference
    assert mirror(doc, mapping).data == reference
    assert doc.to_bytes() == data  # the input is not modified
    return ("per cell" if gathered is None else "gathered"), gathered


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mirror_cases())
@example((EXTREMES[0][1], EXTREMES[0][2]))
@example((_nao_like(2, 2, ["9999999.9", "1"]), _lr_map(2)))  # the marker refusal
def test_the_gather_writes_the_bytes_of_the_per_cell_path(case: tuple[bytes, Mapping]) -> None:
    event(_check(*case)[0])


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mirror_cases(), st.integers(1, 120))
@example((EXTREMES[0][1], EXTREMES[0][2]), 1)  # lines longer than a block
def test_the_gather_in_blocks_of_a_few_bytes_writes_the_same_bytes(
    case: tuple[bytes, Mapping], block: int
) -> None:
    """The lines are gathered about ``_GATHER_BYTES`` at a time (a line longer than that in a
    block of its own): a generated file in one block against the same in many."""
    data, mapping = case
    doc = loads(data, "m.motion")
    try:
        plan = _mirror_plan(doc, mapping)
    except MotionToolError:
        return
    whole = _mirror_gather(doc, plan)
    with patch.object(mirror_ops, "_GATHER_BYTES", block):
        assert _mirror_gather(doc, plan) == whole


@pytest.mark.parametrize(
    ("data", "mapping", "gathers"),
    [pytest.param(d, m, g, id=label) for label, d, m, g in EXTREMES],
)
def test_extremes_take_the_expected_path_with_the_same_bytes(
    data: bytes, mapping: Mapping, gathers: bool
) -> None:
    assert _check(data, mapping)[0] == ("gathered" if gathers else "per cell")


def test_the_long_line_is_the_longest_webots_reads_in_one_piece() -> None:
    assert max(len(line) for line in LONG_LINE.split(b"\n")) == 4094


def test_negation_keeps_the_digits_on_the_gather_path() -> None:
    data = b"#WEBOTS_MOTION,V1.0,L0,R0,C\n0,P,-0.10,1e-300,-.5\n40,Q,*,-0,0x1p-3\n"
    mapping: Mapping = {"L0": ("R0", -1), "R0": ("L0", -1), "C": ("C", -1)}
    out = b"#WEBOTS_MOTION,V1.0,L0,R0,C\n0,P,-1e-300,0.10,.5\n40,Q,-0,*,-0x1p-3\n"
    assert _check(data, mapping) == ("gathered", out)
    assert mirror(loads(data, "m.motion"), mapping).data == out


def test_renaming_to_a_shorter_name_keeps_the_pose_lines_on_the_per_cell_path() -> None:
    # The per-cell path took the pose lines' place in the file from the renamed header: with a
    # name 3 bytes shorter it split 'bc\n0,P0,12\n100,P1' into the cells and wrote garbage.
    data = b"#WEBOTS_MOTION,V1.0,Jabc\n0,P0,12\n100,P1,12\n"
    doc = loads(data, "m.motion")
    plan = _mirror_plan(doc, {"Jabc": ("J", -1)})
    out = b"#WEBOTS_MOTION,V1.0,J\n0,P0,-12\n100,P1,-12\n"
    assert _mirror_bytes(doc, plan, gather=False) == out
    assert mirror(doc, {"Jabc": ("J", -1)}).data == out


@pytest.mark.parametrize(
    ("block", "n_lines"),
    [
        (b"0,P,1\n40,Q,2,3", 2),  # a line with one cell too many
        (b"0,P,1,2\n40,Q", 2),  # ... and one too few, the same count in all
        (b"0,P,,1\n40,Q,2,3", 2),  # an empty cell
        (b"0,P,1,2\n40,Q,2,\x00", 2),  # a NUL
        (b"0,P,1,2\r40,Q,2,3", 1),  # a stray CR
    ],
)
def test_the_gather_leaves_lines_that_are_not_plain_to_the_per_cell_path(
    block: bytes, n_lines: int
) -> None:
    import numpy as np

    negate = np.zeros((n_lines, 4), dtype=bool)
    assert permute_cells(block, n_lines, b"", [0, 1, 3, 2], negate) is None
    negate = np.zeros((2, 4), dtype=bool)
    negate[1, 2] = True
    plain = b"0,P,1,2\n40,Q,2,3"
    assert permute_cells(plain, 2, b"", [0, 1, 3, 2], negate) == b"0,P,2,1\n40,Q,-3,2"


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(case=mirror_cases())
def test_the_pose_block_is_where_the_split_lines_say(case: tuple[bytes, Mapping]) -> None:
    """``pose_block`` finds the pose lines without splitting the file: the span the split
    lines give (LF or CRLF, with or without a final newline, lines after a blank line)."""
    from motiontool.motionfmt.ops._cells import PoseLines, pose_block

    data, _mapping = case
    n = loads(data).n_poses
    lines = PoseLines.of_bytes(data, n)
    start = len(lines.header) + 1
    stop = start + sum(map(len, lines.poses)) + len(lines.poses) - 1
    assert pose_block(data, n) == (start, stop)
    assert data[start:stop].split(b"\n") == lines.poses
