"""The reader that goes on from the last version (:mod:`motiontool.motionfmt.reread`) reads
every version as a full read does, over random edits of every kind."""

from __future__ import annotations

import math
import random

import pytest

from motiontool.motionfmt.reader import ReadResult, read_bytes
from motiontool.motionfmt.reread import Rereader

JOINTS = ["HeadYaw", "HeadPitch", "LShoulderPitch", "LShoulderRoll", "RShoulderPitch"]


def motion(poses: int, rng: random.Random) -> list[bytes]:
    """The lines of a motion of ``poses`` poses, 40 ms apart, a few '*' cells."""
    lines = [b"#WEBOTS_MOTION,V1.0," + ",".join(JOINTS).encode()]
    for p in range(poses):
        cells = [b"*" if rng.random() < 0.02 else _number(rng) for _ in JOINTS]
        lines.append(b",".join([str(40 * (p + 1)).encode(), f"Pose{p}".encode(), *cells]))
    return lines


def _time(lines: list[bytes], at: int, rng: random.Random, wild: float = 0.2) -> bytes:
    """A time for a pose at line ``at``: just after the line before's, but for a share
    ``wild`` of them."""
    before = lines[at - 1].split(b",")[0] if at > 1 else b"0"
    after = lines[at + 1].split(b",")[0] if at + 1 < len(lines) else b""
    if rng.random() < wild or not before.isdigit():
        return str(rng.randrange(0, 40 * len(lines))).encode()
    if after.isdigit() and int(after) - int(before) > 1:  # between the two
        return str(rng.randrange(int(before) + 1, int(after))).encode()
    return str(int(before) + rng.randrange(1, 20)).encode()


def _valid(lines: list[bytes], at: int) -> bool:
    """Whether line ``at`` is a pose line that Webots reads, after the line before it."""
    cells = lines[at].split(b",")
    if len(cells) != len(JOINTS) + 2:
        return False
    before = lines[at - 1].split(b",")[0] if at > 1 else b"-1"
    try:
        later = int(cells[0]) > int(before)
        return later and all(c == b"*" or math.isfinite(float(c)) for c in cells[2:])
    except ValueError:
        return False


def _number(rng: random.Random) -> bytes:
    return repr(round(rng.uniform(-2.5, 2.5), 4)).encode()


def edit(lines: list[bytes], rng: random.Random) -> list[bytes]:
    """``lines`` with one random edit: a value, a time, a pose line inserted or removed, a blank
    line, the header, a cell made unreadable (or a line cut short), a '*', a NaN, the end."""
    lines = list(lines)
    broken = [i for i in range(1, len(lines)) if not _valid(lines, i)]
    if broken and rng.random() < 0.5:  # made valid again: a blank line first
        at = next((i for i in broken if not lines[i]), broken[0])
        if not lines[at]:
            del lines[at]
        else:
            time = _time(lines, at, rng, 0.0)
            lines[at] = b",".join([time, b"Fixed", *[_number(rng) for _ in JOINTS]])
        return lines
    kind = rng.randrange(11)
    at = rng.randrange(1, len(lines)) if len(lines) > 1 else 1
    cells = lines[at].split(b",") if at < len(lines) else []
    if kind <= 2 and len(cells) > 2:  # a value, most often
        cells[rng.randrange(2, len(cells))] = _number(rng)
    elif kind == 3 and cells:  # a time: may now come before the previous one
        cells[0] = _time(lines, at, rng)
    elif kind == 4:
        new = lines[min(at, len(lines) - 1)].split(b",")
        new[0] = _time(lines, at, rng)
        lines.insert(at, b",".join(new))
    elif kind == 5 and len(lines) > 2:
        del lines[at]
    elif kind == 6:
        lines.insert(at, b"")
    elif kind == 7:  # the header: a joint renamed, and back
        lines[0] = lines[0].replace(b"HeadYaw", b"HeadYw", 1) or lines[0]
        if b"HeadYaw" not in lines[0]:
            lines[0] = lines[0].replace(b"HeadYw", b"HeadYaw")
    elif kind == 8 and len(cells) > 2:  # unreadable, or one cell short
        if rng.random() < 0.5:
            cells[rng.randrange(2, len(cells))] = rng.choice([b"abc", b"1rad", b" ", b"-9999999.9"])
        else:
            cells.pop()
    elif kind == 9 and len(cells) > 2:
        cells[rng.randrange(2, len(cells))] = rng.choice([b"*", b"nan", b"inf"])
    elif kind == 10:
        lines.append(b",".join([str(40 * len(lines) + 40).encode(), b"End", *[b"0"] * 5]))
    if cells and kind not in (4, 5, 6, 7, 10):
        lines[at] = b",".join(cells)
    return lines


def same_read(got: ReadResult, want: ReadResult) -> None:
    assert list(got.diagnostics) == list(want.diagnostics)
    assert got.rejected_at == want.rejected_at
    assert got.joints == want.joints
    assert list(got.times_ms) == list(want.times_ms)
    assert list(got.pose_names) == list(want.pose_names)
    assert list(got.pose_lines) == list(want.pose_lines)
    assert got.nan_commands == want.nan_commands
    assert got.end_line == want.end_line
    cells, expected = list(got.cells), list(want.cells)
    assert len(cells) == len(expected)
    assert all(
        a == b or (math.isnan(a) and math.isnan(b)) for a, b in zip(cells, expected, strict=True)
    )
    for pose in range(0, len(want.times_ms), 37):  # the cells' columns, for findings
        for joint in (None, 0, len(want.joints) - 1):
            assert got.cell_span(pose, joint) == want.cell_span(pose, joint)


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("timestep_ms", [None, 20])
def test_every_version_reads_as_a_full_read(seed: int, timestep_ms: int | None) -> None:
    rng = random.Random(seed)
    lines = motion(300, rng)
    reader = Rereader()
    final = b"\n"
    for _ in range(150):
        if rng.random() < 0.03:
            final = b"" if final else b"\n"
        data = b"\n".join(lines) + final
        got = reader.read(data, "m.motion", timestep_ms=timestep_ms)
        same_read(got, read_bytes(data, "m.motion", timestep_ms=timestep_ms))
        lines = edit(lines, rng)
    assert reader.resumed > 60  # most edits are read from the last version


def test_a_value_edit_reads_only_its_line(monkeypatch: pytest.MonkeyPatch) -> None:
    """A one-value edit reads the changed line (and the header), not the file."""
    from motiontool.motionfmt import reader as reader_module

    rng = random.Random(1)
    lines = motion(500, rng)
    reader = Rereader()
    reader.read(b"\n".join(lines) + b"\n", "m.motion")
    read_lines: list[int] = []
    fast = reader_module.read_pose_fast

    def counted(state: object, piece: reader_module.Piece, prev_time: int) -> int | None:
        read_lines.append(piece.line)
        return fast(state, piece, prev_time)  # type: ignore[arg-type]

    monkeypatch.setattr(reader_module, "read_pose_fast", counted)
    cells = lines[250].split(b",")
    cells[3] = b"0.125"
    lines[250] = b",".join(cells)
    data = b"\n".join(lines) + b"\n"
    got = reader.read(data, "m.motion")
    assert reader.resumed == 1
    assert read_lines == [251, 252]  # the edited line, and the next one reads as before
    same_read(got, read_bytes(data, "m.motion"))
