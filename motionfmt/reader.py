"""Read ``.motion`` bytes exactly as Webots does, and report everything that is off.

The reader emulates ``wbu_motion_new`` (``src/controller/c/motion.c``) step by step: ``fgets``
with a 4096-byte buffer, ``strtok`` on ``",\\n\\r"``, ``str_to_time``, ``sscanf("%lf")``. It
records where Webots would stop (:attr:`ReadResult.rejected_at`) but, unlike Webots, goes on to
the end of the motion so that one pass reports every problem. ``docs/webots-format.md`` is the
reference.

This module drives the read; each step has its own module, taking the read's shared state
(:mod:`._read_state`):

* :mod:`.lines`: how ``fgets`` and ``strtok`` cut the file into pieces and cells (MT111, MT208);
* :mod:`.header`: the header line (MT101, MT102, MT205, MT210);
* a pose line on one of three paths that must read alike (``tests/readpaths.py``): the fast
  path for clean lines (:mod:`.pose_fast`), the exact path with every check (:mod:`.pose_line`,
  its time :mod:`.pose_time` and its cells :mod:`.pose_values`), and the bulk path for large
  clean files (:mod:`._bulk`, numpy's ``loadtxt``);
* :mod:`.motion_checks`: the whole motion (MT206, MT207, MT209, MT211, MT115);
* :mod:`.read_result`: what the read found, :class:`ReadResult`.

Here: a blank line ends the motion (MT201), no joint (MT103), no pose (MT104).

Columns are 1-based byte offsets in the physical line (lines split on ``\\n``).
"""

from __future__ import annotations

import functools
from array import array
from collections.abc import Iterator

from motiontool.motionfmt._read_state import ReadState
from motiontool.motionfmt.diagnostics import BLANK_LINE_ENDS, Related
from motiontool.motionfmt.header import HEADER, VERSION, read_header
from motiontool.motionfmt.lines import (
    FGETS_PIECE,
    Piece,
    check_utf8,
    fgets_pieces,
    show,
    token_spans,
)
from motiontool.motionfmt.motion_checks import check_motion
from motiontool.motionfmt.pose_fast import read_pose_fast
from motiontool.motionfmt.pose_line import read_pose_exact
from motiontool.motionfmt.pose_values import NO_VALUE_MARKER
from motiontool.motionfmt.read_result import ReadResult

__all__ = [
    "FGETS_PIECE",
    "HEADER",
    "NO_VALUE_MARKER",
    "VERSION",
    "ReadResult",
    "read_bytes",
    "token_spans",
]

BULK_MIN_BYTES = 1 << 20
"""Files of at least this size try the bulk path (:mod:`._bulk`) before the line-by-line one."""


class _Reader(ReadState):
    """One pass over one file; see :func:`read_bytes`.

    ``exact=True`` reads every pose line on the exact (slow) path, skipping the fast line path
    and the bulk path: the reference the faster paths are tested against.
    """

    def __init__(
        self,
        data: bytes,
        path: str,
        timestep_ms: int | None,
        bulk_min_bytes: int = BULK_MIN_BYTES,
        *,
        exact: bool = False,
        keep_values: bool = True,
    ) -> None:
        super().__init__(data, path, timestep_ms)
        self.bulk_min_bytes = bulk_min_bytes
        self.exact = exact
        self.keep_values = keep_values
        self.body_findings: int | None = None
        """How many findings the header and the pose lines gave (those before the checks of
        the whole motion), once the poses are read; None until then: what :mod:`.reread`
        keeps of a read to read an edit of the file again."""

    def read(self) -> ReadResult:
        res = self.result
        if not self.data:
            self.report(
                "MT100",
                1,
                1,
                "file is empty; expected the header '#WEBOTS_MOTION,V1.0,<joint>,...'",
            )
            return res
        check_utf8(self)
        pieces = fgets_pieces(self)
        header_piece = next(pieces)
        if not read_header(self, header_piece):
            return res
        # The bulk path reads clean files only: not one whose header Webots already rejects.
        bulk = not self.exact and res.accepted and len(self.data) >= self.bulk_min_bytes
        if bulk and header_piece.col0 == 0 and self.read_bulk():
            return res
        last_line, pose_lines_seen = self.read_poses(pieces, (-1, header_piece.line))
        if self.names_line is not None:
            self.names_below_header(self.names_line)
        elif not self.joint_tokens:  # Webots counts joints and poses after reading every line
            self.report(
                "MT103",
                *self.header_end,
                "the header names no joint; expected '#WEBOTS_MOTION,V1.0,<joint>,...'",
                "list the motor names after 'V1.0', separated by commas",
            )
        if pose_lines_seen == 0:
            self.report(
                "MT104",
                res.end_line or last_line + 1,
                1,
                "no pose; expected at least one line 'time,name,value,...' after the header",
            )
        self.body_findings = len(res.diagnostics)
        if self.n_joints == 0 or not res.accepted:
            return res
        check_motion(self)
        return res

    def read_poses(self, pieces: Iterator[Piece], prev: tuple[int, int]) -> tuple[int, int]:
        """Read the pose lines up to the end or a blank line, each on the fast path if it can
        (unless ``exact``) and on the exact path if not, after the pose ``prev`` (its time in
        ms and its line; (-1, 1) for the header); (the last line read, how many)."""
        last_line = prev[1]
        pose_lines_seen = 0
        fast = not self.exact
        for piece in pieces:
            t = read_pose_fast(self, piece, prev[0]) if fast else None
            if t is None:
                spans = token_spans(piece.data)
                if not spans:
                    self.blank_line(piece)
                    break
                if pose_lines_seen == 0 and self.n_joints == 0 and _names(piece, spans):
                    # Webots stops here (not a time): MT103 says why, once, at the end.
                    self.names_line, self.muted = piece.line, "MT110"
                    pose_lines_seen, last_line = 1, piece.line
                    continue
                if piece.col0:
                    t = self.read_cut_rest(piece, spans, prev)
                else:
                    t = read_pose_exact(self, piece, spans, prev)
            pose_lines_seen += 1
            last_line = piece.line
            if t is not None:
                prev = (t, piece.line)
        return last_line, pose_lines_seen

    def read_cut_rest(
        self, piece: Piece, spans: list[tuple[int, int]], prev: tuple[int, int]
    ) -> int | None:
        """Read the rest of a cut line (MT111 said why) as the pose line Webots reads it as, and
        keep two of its findings: the first, and the one that makes Webots reject the file
        there (MT109 after an MT203 in ``5,P2,2rad``) where it is another; its time or None."""
        res = self.result
        before, decided = len(res.diagnostics), res.rejected_at
        res.rejected_at = None  # which finding of this line rejects, if any
        t = read_pose_exact(self, piece, spans, prev)
        found, rejects = res.diagnostics[before:], res.rejected_at
        res.rejected_at = decided or rejects
        del res.diagnostics[before:]
        while self.rejecting and self.rejecting[-1] >= before:
            self.rejecting.pop()
        for d in found[:1] + [d for d in found[1:] if d is rejects]:
            res.diagnostics.append(d)
            if d is rejects:
                self.rejecting.append(len(res.diagnostics) - 1)
        return t

    def names_below_header(self, line: int) -> None:
        """MT103 at ``line``, which holds the joint names the header lacks: where Webots
        stops, and the reason for the "expected 0 values" (MT110) on each later line, counted
        instead of reported."""
        res = self.result
        decided = res.rejected_at
        muted, self.muted = self.muted_count, None
        raw = self.lines[line - 1]
        spans = token_spans(raw)
        names = raw[spans[0][0] : spans[-1][1]]
        findings = "1 finding" if muted == 1 else f"{muted} findings"
        later = f" ({findings} 'expected 0 values' on later lines not shown)" if muted else ""
        why = "but Webots reads them only from the header line: the header names no joint"
        self.report(
            "MT103",
            line,
            spans[0][0] + 1,
            f"the joint names are on line {line}, {why}{later}",
            f"move them to the end of line 1: {show(HEADER + b',' + VERSION + b',' + names, 80)}",
            end_column=spans[-1][1] + 1,
            # What identifies it in fingerprints: neither its line nor the count below it.
            stable=f"the joint names are below the header, {why}",
        )
        if decided is None or decided.line >= line:  # Webots stops at this line, not after it
            res.rejected_at = res.diagnostics[len(res.diagnostics) - 1]

    def read_bulk(self) -> bool:
        """Read a large clean file in one go (see :mod:`._bulk`); False to take the exact path."""
        from motiontool.motionfmt._bulk import read_clean_body, read_values

        header_end = self.data.find(b"\n")
        if header_end < 0 or header_end + 1 > FGETS_PIECE:
            return False
        body = (self.data, self.n_joints, NO_VALUE_MARKER, FGETS_PIECE - 1, header_end + 1)
        got = read_clean_body(*body, keep_values=self.keep_values)
        if got is None:
            return False
        times, names, values = got
        res = self.result
        res.times_ms = array("q")
        res.times_ms.frombytes(times.data.cast("B"))
        res.pose_names = names
        if values is None:  # read again if asked for
            res.cells_later(functools.partial(read_values, *body))
        else:
            res.cells = values.reshape(-1)
        res.pose_lines = range(2, len(times) + 2)  # a pose a line: no list of them
        self.body_findings = len(res.diagnostics)
        check_motion(self)
        return True

    def blank_line(self, piece: Piece) -> None:
        """A line with no token ends the motion; warn if anything follows it (MT201)."""
        res = self.result
        res.end_line = piece.line
        later = [i + 1 for i in range(piece.line, len(self.lines)) if token_spans(self.lines[i])]
        if not later:
            return
        where = f"line {later[0]}" if len(later) == 1 else f"lines {later[0]}-{later[-1]}"
        what = (
            "the end of this cut line reads as a blank line, which ends the motion"
            if piece.col0
            else "blank line ends the motion"
        )
        stable = f"{what}: Webots ignores everything after it"
        ignored = f"the first of {len(later)} lines" if len(later) > 1 else "the line"
        self.report(
            BLANK_LINE_ENDS,
            piece.line,
            piece.col0 + 1,
            f"{stable} ({where})",
            "remove the blank line",
            related=(Related(later[0], 1, f"{ignored} Webots ignores"),),
            stable=stable,
        )


def _names(piece: Piece, spans: list[tuple[int, int]]) -> bool:
    """Whether a line that starts with a letter (not a time) stands where the first pose line
    should, after a header that names no joint: the joint names, put on a line of their own."""
    return piece.col0 == 0 and piece.data[spans[0][0] : spans[0][0] + 1].isalpha()


def read_bytes(
    data: bytes,
    path: str = "<string>",
    *,
    timestep_ms: int | None = None,
    keep_values: bool = True,
) -> ReadResult:
    """Read a ``.motion`` file's bytes as Webots does and collect every diagnostic.

    Args:
        data: the file's content, as bytes.
        path: how diagnostics name the file.
        timestep_ms: the controller time step in milliseconds; when given, pose times that are
            not a multiple of it are reported.
        keep_values: False where nothing is expected to read the values (a check of the
            syntax only): a large clean file's values are then checked but not kept, and
            :attr:`ReadResult.cells` reads them again if asked for.

    Returns:
        The poses Webots reads and the diagnostics; never raises on bad content.
    """
    if timestep_ms is not None and timestep_ms <= 0:
        raise ValueError(f"timestep_ms must be positive, got {timestep_ms}")
    return _Reader(data, path, timestep_ms, keep_values=keep_values).read()
