"""A document's pose lines with new times, written a block of lines at a time: what ``trim``
(a window of poses, shifted, between boundary poses) and ``retime --speed`` / ``--duration``
(every pose) write, so that neither holds its result (the lines are sliced from the input's
bytes and only the time cells that change are re-spelt)."""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from typing import TYPE_CHECKING

from motiontool.motionfmt.ops import _cells
from motiontool.motionfmt.ops._cells import (
    header_eol,
    pose_block,
    pose_line_blocks,
    set_time,
    with_eol,
)
from motiontool.motionfmt.writer import format_time

if TYPE_CHECKING:
    from motiontool.motionfmt.document import MotionDocument

__all__ = ["retimed_blocks"]


def retimed_blocks(
    doc: MotionDocument,
    poses: range,
    times_ms: Sequence[int],
    before: bytes = b"",
    after: bytes = b"",
    *,
    ends_as_header: bool = True,
) -> Iterator[bytes]:
    """The bytes of ``doc`` with only the pose lines ``poses`` (consecutive), pose
    ``poses[k]`` at ``times_ms[k]`` (ms: its time cell re-spelt in ``doc``'s time style where
    the time changes), after the pose line ``before`` and followed by ``after`` (lines without
    their ends; ``b""``: none), a block of :data:`~motiontool.motionfmt.ops._cells.BLOCK_LINES`
    lines at a time, never all held.

    The header, and what follows the last pose (lines after a terminating blank line, the
    final newline or its absence, which the last line then has too), stay as they are; every
    pose line ends as the header does (``ends_as_header``; False: as it did)."""
    data = doc.to_bytes()
    start, stop = pose_block(data, doc.n_poses)
    header = data[: start - 1]
    tail = data[stop:]
    eol = header_eol(header)
    last_eol = eol if tail else b""  # the end of the result's last line
    yield header
    if before:  # never the last line: a kept pose or ``after`` follows
        yield b"\n" + before + eol
    old = doc.result.times_ms
    style = doc.time_style
    size = _cells.BLOCK_LINES
    blocks = pose_line_blocks(data, (start, stop), size, poses.start, poses.stop)
    for a, lines in blocks:
        b = a + len(lines)
        for k, (was, now) in enumerate(
            zip(old[a:b].tolist(), times_ms[a - poses.start : b - poses.start], strict=True)
        ):
            if was != now:
                lines[k] = set_time(lines[k], format_time(int(now), style).encode("ascii"))
        if not ends_as_header:
            yield b"".join([b"\n" + line for line in lines])
            continue
        ends = [eol] * len(lines)
        if b == poses.stop and not after:
            ends[-1] = last_eol
        yield b"".join([b"\n" + with_eol(line, e) for line, e in zip(lines, ends, strict=True)])
    if after:
        yield b"\n" + after + last_eol
    yield tail
