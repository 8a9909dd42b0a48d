"""The reader that goes on from the last version (:mod:`motiontool.motionfmt.reread`) reads
every version as a full read does, over random edits of every kind."""

from __future__ import annotations

import math
import random

import pytest
from edits import edit, motion

from motiontool.motionfmt.reader import ReadResult, read_bytes
from motiontool.motionfmt.reread import Rereader

JOINTS = ["HeadYaw", "HeadPitch", "LShoulderPitch", "LShoulderRoll", "RShoulderPitch"]


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
    lines = motion(JOINTS, 300, rng)
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
    lines = motion(JOINTS, 500, rng)
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


@pytest.mark.parametrize("seed", range(20))
def test_the_lines_taken_as_unchanged_are(seed: int) -> None:
    """The first and last lines the reader takes from the last version are lines of it, byte for
    byte, and do not overlap, whatever bytes an edit changes."""
    from motiontool.motionfmt.reread import _unchanged

    rng = random.Random(seed)
    old = b"\n".join(motion(JOINTS, 30, rng)) + rng.choice([b"", b"\n"])
    for _ in range(50):
        new = bytearray(old)
        at = rng.randrange(len(new))
        new[at : at + rng.randrange(4)] = rng.choice([b"", b"\n", b",", b"7", b"\n9,a\n"])
        if new.endswith(b"\n") != old.endswith(b"\n"):
            continue
        a, b = _unchanged(old, bytes(new))
        old_lines, new_lines = old.split(b"\n"), bytes(new).split(b"\n")
        if old.endswith(b"\n"):
            old_lines.pop()
            new_lines.pop()
        assert a + b <= min(len(old_lines), len(new_lines))
        assert new_lines[:a] == old_lines[:a]
        assert new_lines[len(new_lines) - b :] == old_lines[len(old_lines) - b :]
