"""A lossless, editable ``.motion`` document: ``dumps(loads(text)) == text``, byte for byte.

The document keeps every line as the bytes it was read from: spacing, ``+0.1``, digits of
precision, CRLF ends, a missing final newline, lines after a terminating blank line, bytes that
are not UTF-8. An edit re-renders only the cells it touches (new text in the canonical spelling of
:mod:`motiontool.motionfmt.writer`, keeping the cell's leading white space); everything else stays
as it was.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Iterable, Iterator, Sequence
from typing import TYPE_CHECKING, overload

from motiontool.errors import MotionSyntaxError, MotionToolError
from motiontool.motionfmt.cscan import scan_double
from motiontool.motionfmt.diagnostics import CUT_LINE
from motiontool.motionfmt.reader import NO_VALUE_MARKER, ReadResult, read_bytes, token_spans
from motiontool.motionfmt.writer import TimeStyle, format_time, format_value, pose_lines

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = ["MotionDocument", "dumps", "loads"]


class MotionDocument:
    """An editable ``.motion`` file that Webots accepts.

    Use :func:`loads` to make one. Poses are addressed by index (0-based, file order) and joints
    by column index (0-based) or name.
    """

    def __init__(self, data: bytes, path: str, *, as_text: bool = False) -> None:
        result = read_bytes(data, path)
        if not result.accepted:
            result.motion  # raises the error where Webots stops  # noqa: B018
        cut = [d for d in result.diagnostics if d.code == CUT_LINE]
        if cut:
            d = cut[0]
            raise MotionSyntaxError(d.message + " [MT111]", d.path, d.line, d.column)
        self.path = path
        self._as_text = as_text
        self._final_newline = data.endswith(b"\n")
        first = data.index(b"\n") + 1  # a file Webots accepts has a pose line after its header
        self._crlf = data[:first].endswith(b"\r\n")
        end = data.find(b"\n", first)
        first_pose = data[first : end if end >= 0 else len(data)]
        self.joints: tuple[str, ...] = tuple(result.joints)
        a, b = token_spans(first_pose)[0]
        self.time_style = TimeStyle.of(first_pose[a:b].decode("ascii").strip())
        self._result: ReadResult | None = result
        self._read = data  # the bytes of _result, while it is current (see _edited)
        # The lines, split from the bytes when first needed (an edit, a cell): a document only
        # read and written back never holds its bytes twice.
        self._lines: tuple[bytes, list[bytes], list[bytes]] | None = None
        self._n_read = len(result.times_ms)

    @property
    def _parts(self) -> tuple[bytes, list[bytes], list[bytes]]:
        """(header line, pose lines, lines after the terminating blank line), split from the
        bytes read on first use. The header is line 1 and the poses are lines 2..n+1: in a
        file Webots accepts, every line before the terminating blank line is a pose."""
        if self._lines is None:
            lines = self._read.split(b"\n")
            if self._final_newline:
                lines.pop()
            n = self._n_read
            self._lines = (lines[0], lines[1 : n + 1], lines[n + 1 :])
        return self._lines

    @property
    def _poses(self) -> list[bytes]:
        return self._parts[1]

    # -- reading ----------------------------------------------------------------------------------

    @property
    def n_poses(self) -> int:
        return self._n_read if self._lines is None else len(self._lines[1])

    @property
    def result(self) -> ReadResult:
        """The current content read as Webots reads it (re-read after edits)."""
        if self._result is None:
            data = self.to_bytes()
            if self._lines is not None:  # the bytes hold them now: split again if edited again
                self._n_read, self._lines = len(self._lines[1]), None
            self._read = data
            self._result = read_bytes(data, self.path)
        return self._result

    @property
    def motion(self) -> Motion:
        """The current content as a :class:`Motion`."""
        return self.result.motion

    def _edited(self) -> None:
        """Forget the last read (and its bytes): the lines changed."""
        self._result, self._read = None, b""

    def to_bytes(self) -> bytes:
        """The document's bytes; equal to the input until an edit."""
        if self._result is not None:  # no edit since they were read: the same bytes
            return self._read
        header, poses, suffix = self._parts
        body = b"\n".join([header, *poses, *suffix])
        return body + b"\n" if self._final_newline else body

    def copy(self) -> MotionDocument:
        """A document to edit on its own: the same content as this one, which its edits leave
        as it is (nothing is read again: the two share the bytes and the read until either
        is edited)."""
        twin = object.__new__(MotionDocument)
        twin.__dict__.update(self.__dict__)
        if self._lines is not None:
            header, poses, suffix = self._lines
            twin._lines = (header, list(poses), list(suffix))
        return twin

    def dumps(self) -> bytes | str:
        """The document as it was given to :func:`loads`: ``str`` in, ``str`` out."""
        data = self.to_bytes()
        return data.decode("utf-8", "surrogateescape") if self._as_text else data

    # -- editing ----------------------------------------------------------------------------------

    def _column(self, joint: int | str) -> int:
        if isinstance(joint, int):
            if not 0 <= joint < len(self.joints):
                raise MotionToolError(f"joint index {joint} out of range 0..{len(self.joints) - 1}")
            return joint
        for j in range(len(self.joints) - 1, -1, -1):
            if self.joints[j] == joint:
                return j
        raise MotionToolError(f"no joint {joint!r}; the file has {', '.join(self.joints)}")

    def _cell(self, pose: int, cell: int) -> bytes:
        line = self._poses[pose]
        a, b = token_spans(line)[cell]
        return line[a:b]

    def _set_cell(self, pose: int, cell: int, text: str) -> None:
        a, b = token_spans(self._poses[pose])[cell]
        self._put(pose, a, b, text)
        self._edited()

    def _put(self, pose: int, a: int, b: int, text: str) -> None:
        """Token ``[a, b)`` (byte offsets) of pose line ``pose`` spelt ``text``, keeping the
        token's leading white space (the caller says the document was edited)."""
        line = self._poses[pose]
        token = line[a:b]
        lead = len(token) - len(token.lstrip(b" \t"))
        self._poses[pose] = line[: a + lead] + text.encode("utf-8") + line[b:]

    def set_value(self, pose: int, joint: int | str, value: float) -> None:
        """Set one cell; NaN writes ``*`` (no command). Cells equal to ``value`` keep their
        spelling (a literal ``nan`` cell is a command, so NaN replaces it with ``*``)."""
        j = self._column(joint)
        token = self._cell(pose, 2 + j)
        scanned = None if token == b"*" else scan_double(token)
        if scanned is None or scanned.value == NO_VALUE_MARKER:
            if math.isnan(value):
                return  # already no command
        elif scanned.value == value:
            return
        self._set_cell(pose, 2 + j, format_value(value))

    def set_time(self, pose: int, time_ms: int) -> None:
        """Set a pose time in milliseconds, spelt in the file's own time style; it must stay
        after the previous pose's time and before the next one's (as :meth:`set_times`)."""
        p = range(self.n_poses)[pose]  # IndexError out of range; -1 is the last pose
        times = list(self.result.times_ms)
        times[p] = time_ms
        _check_increasing(times)
        self._set_cell(p, 0, format_time(time_ms, self.time_style))

    def set_times(self, times_ms: Sequence[int]) -> None:
        """Set every pose time at once (P values, milliseconds, strictly increasing)."""
        if len(times_ms) != self.n_poses:
            raise MotionToolError(f"expected {self.n_poses} times, got {len(times_ms)}")
        _check_increasing(times_ms)
        read = self.result
        pairs = zip(read.times_ms, times_ms, strict=True)
        changed = [p for p, (was, now) in enumerate(pairs) if was != now]
        # The time cells as read, found a block of lines at a time: each line is edited once.
        spans = read.cell_spans(changed, [None] * len(changed))
        try:
            for p, (_line, start, end) in zip(changed, spans, strict=True):
                self._put(p, start - 1, end - 1, format_time(int(times_ms[p]), self.time_style))
        finally:
            if changed:
                self._edited()

    def delete_pose(self, pose: int) -> None:
        """Remove one pose line."""
        if self.n_poses == 1:
            raise MotionToolError("cannot delete the only pose: a motion needs at least one")
        del self._poses[pose]
        self._edited()

    def insert_pose(self, index: int, time_ms: int, name: str, values: Sequence[float]) -> None:
        """Insert a new pose line before pose ``index`` (``n_poses`` appends), canonically spelt."""
        import numpy as np

        if len(values) != len(self.joints):
            raise MotionToolError(f"expected {len(self.joints)} values, got {len(values)}")
        self.insert_poses([index], [time_ms], [name], np.array([values], dtype=np.float64))

    def insert_poses(
        self,
        at: Sequence[int],
        times_ms: Sequence[int],
        names: Sequence[str],
        values: npt.NDArray[np.float64],
    ) -> None:
        """Insert new pose lines, canonically spelt: pose k (``times_ms[k]``, ``names[k]``, the
        row ``values[k]`` in rad or m, NaN for ``*``) before the pose now at index ``at[k]``
        (``n_poses`` appends); ``at`` does not decrease, and poses given one index keep their
        order. One pass over the lines, whatever their number."""
        if values.ndim != 2 or values.shape[1] != len(self.joints):
            raise MotionToolError(f"expected {len(self.joints)} values a pose, got {values.shape}")
        if not at:
            return
        ends = [*at[1:], self.n_poses]
        if any(not 0 <= a <= b <= self.n_poses for a, b in zip(at, ends, strict=True)):
            raise MotionToolError(
                f"cannot insert poses at indices that decrease or pass {self.n_poses}"
            )
        eol = b"\r" if self._crlf else b""
        header, poses, suffix = self._parts  # left as they are until every new line is made
        open_end = eol and not suffix and not self._final_newline
        if open_end:  # the last line has no end; the one that is last after this gets none
            poses = [*poses[:-1], poses[-1] + eol]
        out: list[bytes] = []
        done = 0
        for lo in range(0, len(at), _NEW_LINES):  # a block's cells are strings while spelt
            hi = lo + _NEW_LINES
            lines = pose_lines(times_ms[lo:hi], names[lo:hi], values[lo:hi], self.time_style)
            for index, line in zip(at[lo:hi], lines, strict=True):
                out.extend(poses[done:index])
                out.append(line.encode("utf-8") + eol)
                done = index
        out.extend(poses[done:])
        if open_end:
            out[-1] = out[-1][: -len(eol)]
        self._lines = (header, out, suffix)
        self._edited()

    def stream_edited(
        self, keep: Sequence[bool], after: Callable[[int], Iterable[list[str]]]
    ) -> Iterator[bytes]:
        """The bytes of this document with pose ``p`` left out where ``keep[p]`` is False and,
        after pose ``p``, the new pose lines that ``after(p)`` gives (blocks of canonical line
        texts, without their ends): what :meth:`delete_pose` and :meth:`insert_poses` would
        make, a block of about :data:`_STREAM_BYTES` at a time, never all held. The last pose
        stays, last (the ends of the lines are then those of :meth:`insert_poses`)."""
        header, poses, suffix = self._parts
        if len(keep) != len(poses) or not keep[-1]:
            raise MotionToolError("the last pose of a streamed edit must stay")
        eol = b"\r" if self._crlf else b""
        lines: list[bytes] = [header]
        size = 0
        for p, line in enumerate(poses):
            if keep[p]:
                lines.append(line)
                size += len(line)
            for block in after(p):
                if p == len(poses) - 1:
                    raise MotionToolError("no pose line may follow the last pose")
                new = [text.encode("utf-8") + eol for text in block]
                lines += new
                size += sum(map(len, new))
                if size >= _STREAM_BYTES:
                    yield b"\n".join(lines[:-1]) + b"\n"  # a line follows each but the last
                    lines, size = lines[-1:], 0
            if size >= _STREAM_BYTES:
                yield b"\n".join(lines[:-1]) + b"\n"
                lines, size = lines[-1:], 0
        lines += suffix
        yield b"\n".join(lines) + (b"\n" if self._final_newline else b"")


_STREAM_BYTES = 1 << 20
"""The size of the blocks :meth:`MotionDocument.stream_edited` gives, bytes (about)."""

_NEW_LINES = 8192
"""New pose lines :meth:`MotionDocument.insert_poses` spells at a time: each cell is a Python
string until its line is joined, so a block's cells, not all of them, are held."""


def _check_increasing(times_ms: Sequence[int]) -> None:
    """Raise :class:`MotionToolError` naming the first two poses (0-based) whose times (ms) do
    not strictly increase."""
    for p, (a, b) in enumerate(itertools.pairwise(times_ms)):
        if b <= a:
            raise MotionToolError(
                f"pose times must strictly increase: pose {p + 1} at {b} ms is not after"
                f" pose {p} at {a} ms"
            )


@overload
def loads(data: bytes, path: str = ...) -> MotionDocument: ...
@overload
def loads(data: str, path: str = ...) -> MotionDocument: ...
def loads(data: bytes | str, path: str = "<string>") -> MotionDocument:
    """Parse a file Webots accepts into an editable document.

    Raises:
        MotionSyntaxError: at the first error where Webots stops, or at a line Webots cuts.
    """
    if isinstance(data, str):
        return MotionDocument(data.encode("utf-8", "surrogateescape"), path, as_text=True)
    return MotionDocument(bytes(data), path)


def dumps(doc: MotionDocument) -> bytes | str:
    """The document's content; ``dumps(loads(x)) == x`` for every file Webots accepts."""
    return doc.dumps()
