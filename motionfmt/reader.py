"""Read ``.motion`` bytes exactly as Webots does, and report everything that is off.

The reader emulates ``wbu_motion_new`` (``src/controller/c/motion.c``) step by step: ``fgets``
with a 4096-byte buffer, ``strtok`` on ``",\\n\\r"``, ``str_to_time``, ``sscanf("%lf")``. It
records where Webots would stop (:attr:`ReadResult.rejected_at`) but, unlike Webots, goes on to
the end of the motion so that one pass reports every problem. ``docs/webots-format.md`` is the
reference.

Columns are 1-based byte offsets in the physical line (lines split on ``\\n``).
"""

from __future__ import annotations

import itertools
import math
import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from motiontool.motionfmt.clock import clock_overflow
from motiontool.motionfmt.cscan import INT_MAX, scan_double, scan_time
from motiontool.motionfmt.diagnostics import CODES, Diagnostic, Severity
from motiontool.motionfmt.errors import MotionSyntaxError

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = [
    "FGETS_PIECE",
    "HEADER",
    "NO_VALUE_MARKER",
    "VERSION",
    "ReadResult",
    "read_bytes",
    "token_spans",
]

HEADER = b"#WEBOTS_MOTION"
VERSION = b"V1.0"
NO_VALUE_MARKER = -9999999.9
"""Webots' internal 'undefined position': a cell holding this number behaves like ``*``."""
FGETS_PIECE = 4095
"""Webots reads lines with ``fgets(buffer, 4096, file)``: at most 4095 bytes a piece."""
BULK_MIN_BYTES = 1 << 20
"""Files of at least this size try the bulk path (pyarrow) before the line-by-line one."""

_BOM = b"\xef\xbb\xbf"
_NAN = float("nan")
_TOKEN = re.compile(rb"[^,\r\n]+")
_UNIT_SUFFIX = re.compile(rb"\s*(rad|deg|degrees?|m|mm|cm|\xc2\xb0)\s*$", re.IGNORECASE)
_INT_TOKEN = re.compile(rb"-?\d+")
_DIGITS_TOKEN = re.compile(rb"\d+")


def show(token: bytes, limit: int = 40) -> str:
    """A token as a quoted, printable string for messages (non-UTF-8 bytes escaped)."""
    text = token.decode("utf-8", "backslashreplace")
    if len(text) > limit:
        text = text[: limit - 3] + "..."
    return repr(text)


def _decode(raw: bytes) -> str:
    """Names keep undecodable bytes as surrogates, so they survive a round trip."""
    return raw.decode("utf-8", "surrogateescape")


def token_spans(piece: bytes) -> list[tuple[int, int]]:
    """(start, end) 0-based byte offsets of the tokens ``strtok(piece, ",\\n\\r")`` finds:
    the one cell tokeniser of motiontool (a C string ends at a NUL byte)."""
    nul = piece.find(b"\0")
    if nul >= 0:
        piece = piece[:nul]
    return [m.span() for m in _TOKEN.finditer(piece)]


@dataclass(frozen=True)
class _Piece:
    """What one ``fgets`` call returns: part of a physical line."""

    line: int  # 1-based physical line
    col0: int  # byte offset of the piece in its physical line
    data: bytes  # without the newline


class _PoseLine:
    """A pose line's piece cut into its tokens, for the exact path.

    Attributes:
        raw: the piece's bytes; line: its 1-based physical line.
        spans, tokens: the tokens (:func:`token_spans`) and their bytes.
        c0: add to a 0-based offset in the piece to get a 1-based column in the line.
    """

    __slots__ = ("c0", "line", "raw", "spans", "tokens")

    def __init__(self, piece: _Piece, spans: list[tuple[int, int]]) -> None:
        self.raw = piece.data
        self.line = piece.line
        self.c0 = piece.col0 + 1
        self.spans = spans
        self.tokens = [piece.data[a:b] for a, b in spans]


@dataclass
class ReadResult:
    """Everything a read found.

    Attributes:
        path: the file as the user named it.
        diagnostics: every finding, in file order.
        rejected_at: the error at which Webots' loader stops, or ``None`` when Webots loads the
            file (it may still mis-read it: see the warnings).
        joints: header joint names (undecodable bytes kept as surrogates).
        pose_names, times_ms, rows: the poses Webots reads, in file order; ``rows[p][j]`` is NaN
            for ``*`` and the -9999999.9 marker (no command), and for a literal ``nan`` (a
            command: see ``nan_commands``).
        nan_commands: (pose, column) of every cell that holds a literal ``nan``: NaN in
            ``rows``, but a value Webots sends to the motor, unlike ``*``.
        pose_lines: 1-based physical line of each pose.
        end_line: the blank line that ends the motion early, or ``None``.
    """

    path: str
    diagnostics: list[Diagnostic] = field(default_factory=list)
    rejected_at: Diagnostic | None = None
    joints: list[str] = field(default_factory=list)
    pose_names: list[str] = field(default_factory=list)
    times_ms: list[int] = field(default_factory=list)
    rows: list[list[float]] = field(default_factory=list)
    pose_lines: list[int] = field(default_factory=list)
    nan_commands: list[tuple[int, int]] = field(default_factory=list)
    end_line: int | None = None
    _motion: Motion | None = field(default=None, repr=False)
    _data: bytes = field(default=b"", repr=False)
    _cols0: list[int] = field(default_factory=list, repr=False)
    _line_starts: list[int] = field(default_factory=list, repr=False)
    _span_cache: dict[int, list[tuple[int, int]]] = field(default_factory=dict, repr=False)

    def header_spans(self) -> list[tuple[int, int]]:
        """1-based (column, end column) of each joint name in the header (line 1)."""
        end = self._data.find(b"\n")
        line = self._data[: end if end >= 0 else len(self._data)][:FGETS_PIECE]
        return [(a + 1, b + 1) for a, b in token_spans(line)[2:]]

    def cell_span(self, pose: int, joint: int | None = None) -> tuple[int, int, int]:
        """(line, column, end column), 1-based, of a pose's value cell for column ``joint``
        (0-based), or of its time token when ``joint`` is None — for diagnostics on cells."""
        line = self.pose_lines[pose]
        col0 = self._cols0[pose] if self._cols0 else 0
        if not self._line_starts:
            starts = [0]
            find = self._data.find
            pos = find(b"\n")
            while pos >= 0:
                starts.append(pos + 1)
                pos = find(b"\n", pos + 1)
            self._line_starts = starts
        spans = self._span_cache.get(pose)
        if spans is None:  # tokenised once per pose, however many diagnostics it gets
            start = self._line_starts[line - 1]
            end = self._data.find(b"\n", start)
            content = self._data[start : end if end >= 0 else len(self._data)]
            spans = self._span_cache[pose] = token_spans(content[col0 : col0 + FGETS_PIECE])
        a, b = spans[0 if joint is None else 2 + joint]
        return line, col0 + a + 1, col0 + b + 1

    @property
    def commanded(self) -> npt.NDArray[np.bool_]:
        """(P, J) bool: True where the cell is a command (a number, ``nan`` and ``inf``
        included), False for ``*`` and the -9999999.9 marker."""
        import numpy as np

        rows = np.asarray(self.rows, dtype=np.float64).reshape(len(self.times_ms), len(self.joints))
        mask = ~np.isnan(rows)
        for p, j in self.nan_commands:
            mask[p, j] = True
        return mask

    @property
    def accepted(self) -> bool:
        """Whether Webots' ``wbu_motion_new`` loads this file."""
        return self.rejected_at is None

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.severity is Severity.ERROR]

    @property
    def motion(self) -> Motion:
        """The motion Webots plays; raises :class:`MotionSyntaxError` if Webots rejects it."""
        if self.rejected_at is not None:
            d = self.rejected_at
            raise MotionSyntaxError(f"{d.message} [{d.code}]", d.path, d.line, d.column)
        if self._motion is None:
            from motiontool.motionfmt.motion import Motion

            self._motion = Motion(
                joints=tuple(self.joints),
                pose_names=tuple(self.pose_names),
                times_ms=self.times_ms,  # type: ignore[arg-type]
                values=self.rows,  # type: ignore[arg-type]
                commanded=self.commanded,
            )
        return self._motion


class _Reader:
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
    ) -> None:
        self.data = data
        self.bulk_min_bytes = bulk_min_bytes
        self.exact = exact
        self.path = path
        self.timestep_ms = timestep_ms
        self.result = ReadResult(path=path, _data=data)
        self.lines = data.split(b"\n")
        self.has_final_newline = data.endswith(b"\n")
        if self.has_final_newline:
            self.lines.pop()  # fgets returns NULL after the last newline
        self.joint_tokens: list[bytes] = []
        self.n_joints = 0
        self.star_seen = False
        self.header_end = (1, 1)
        self.pose_cols0: list[int] = self.result._cols0

    # -- reporting ------------------------------------------------------------------------------

    def report(
        self,
        code: str,
        line: int,
        column: int,
        message: str,
        hint: str | None = None,
        *,
        joint: str | None = None,
        time_ms: int | None = None,
        end_column: int | None = None,
        severity: Severity | None = None,
        rejects: bool | None = None,
    ) -> None:
        """Record a finding; ``severity`` and ``rejects`` default to the code's (see
        :class:`~motiontool.motionfmt.diagnostics.Code`), the first rejecting one is where
        Webots stops."""
        spec = CODES[code]
        diag = Diagnostic(
            code=code,
            severity=spec.severity if severity is None else severity,
            path=self.path,
            line=line,
            column=column,
            message=message,
            hint=hint,
            joint=joint,
            time_ms=time_ms,
            end_column=end_column,
        )
        self.result.diagnostics.append(diag)
        if (spec.rejects if rejects is None else rejects) and self.result.rejected_at is None:
            self.result.rejected_at = diag

    # -- pieces -----------------------------------------------------------------------------------

    def pieces(self) -> Iterator[_Piece]:
        """The lines as Webots' ``fgets`` returns them, with long lines cut into pieces."""
        last = len(self.lines) - 1
        for i, content in enumerate(self.lines):
            has_newline = i < last or self.has_final_newline
            full_length = len(content) + (1 if has_newline else 0)
            if full_length <= FGETS_PIECE:
                yield _Piece(i + 1, 0, content)
                continue
            self.report(
                "MT111",
                i + 1,
                FGETS_PIECE + 1,
                f"line is {len(content)} bytes long; Webots reads at most {FGETS_PIECE - 1} bytes"
                f" of a line (plus its newline) at a time and reads the rest as a new line",
                "split the motion into fewer joints, or shorten pose names and numbers",
                end_column=len(content) + 1,
            )
            for start in range(0, full_length, FGETS_PIECE):
                yield _Piece(i + 1, start, content[start : start + FGETS_PIECE])

    # -- header ---------------------------------------------------------------------------------

    def read_header(self, piece: _Piece) -> bool:
        """Check the header; return whether the pose lines can be read against it."""
        raw = piece.data
        spans = token_spans(raw)
        tokens = [raw[a:b] for a, b in spans]
        nul = raw.find(b"\0")
        if nul >= 0:
            self.report("MT114", piece.line, nul + 1, "NUL byte in the header: Webots stops there")
        if not tokens:
            self.report(
                "MT101",
                piece.line,
                1,
                "the first line is empty; expected the header '#WEBOTS_MOTION,V1.0,<joint>,...'",
                "the header must be the very first line of the file",
            )
            return False
        first = tokens[0]
        proceed = True
        if first != HEADER:
            hint = None
            if first.startswith(_BOM):
                hint = "the file starts with a UTF-8 byte-order mark (BOM): save it without BOM"
            elif first.strip() == HEADER:
                hint = "remove the white space around '#WEBOTS_MOTION'"
            elif first.upper() == HEADER:
                hint = "the header is case-sensitive: write '#WEBOTS_MOTION'"
            else:
                proceed = first.strip(b" \t").upper().lstrip(_BOM) == HEADER
            self.report(
                "MT101",
                piece.line,
                spans[0][0] + 1,
                f"expected '#WEBOTS_MOTION' as the first token, found {show(first)}",
                hint,
                end_column=spans[0][1] + 1,
            )
            proceed = proceed or hint is not None
        if len(tokens) < 2:
            end = spans[-1][1] + 1
            self.report(
                "MT102",
                piece.line,
                end,
                "expected the version 'V1.0' after '#WEBOTS_MOTION', found end of line",
                "the header is '#WEBOTS_MOTION,V1.0,<joint>,<joint>,...'",
            )
            return False
        if tokens[1] != VERSION:
            hint = None
            if tokens[1].strip() == VERSION:
                hint = "remove the white space around 'V1.0'"
            elif tokens[1].upper() == VERSION.upper():
                hint = "the version is case-sensitive: write 'V1.0'"
            self.report(
                "MT102",
                piece.line,
                spans[1][0] + 1,
                f"expected the version 'V1.0' after '#WEBOTS_MOTION', found {show(tokens[1])}",
                hint or "V1.0 is the only version Webots reads",
                end_column=spans[1][1] + 1,
            )
        if not proceed:
            return False
        self.joint_tokens = tokens[2:]
        self.n_joints = len(self.joint_tokens)
        self.result.joints = [_decode(t) for t in self.joint_tokens]
        self.header_end = (piece.line, spans[-1][1] + 1)
        seen: dict[bytes, int] = {}
        for j, (tok, (a, b)) in enumerate(zip(self.joint_tokens, spans[2:], strict=True)):
            name = self.result.joints[j]
            if tok != tok.strip():
                self.report(
                    "MT210",
                    piece.line,
                    a + 1,
                    f"joint name {show(tok)} has leading or trailing white space; Webots looks"
                    f" for a motor named exactly that",
                    f"write {show(tok.strip())}",
                    joint=name,
                    end_column=b + 1,
                )
            if tok in seen:
                self.report(
                    "MT205",
                    piece.line,
                    a + 1,
                    f"joint {show(tok)} is named twice (columns {seen[tok] + 1} and {j + 1});"
                    f" both drive the same motor and the later column wins",
                    "remove one of the two columns",
                    joint=name,
                    end_column=b + 1,
                )
            seen[tok] = j
        return True

    # -- pose lines -----------------------------------------------------------------------------

    def read_pose_fast(self, piece: _Piece, prev_time: int) -> int | None:
        """The common case of a clean line, without spans; ``None`` sends it to the slow path."""
        raw = piece.data
        if raw.endswith(b"\r"):
            raw = raw[:-1]
        if b"\r" in raw or b"\0" in raw:
            return None
        toks = raw.split(b",")
        if len(toks) != self.n_joints + 2 or b"" in toks:
            return None
        values_raw = raw[len(toks[0]) + len(toks[1]) + 2 :]
        if b"_" in values_raw or b"*" in values_raw:
            return None  # float() reads '1_0' as 10; '*' needs the full path
        t_tok = toks[0]
        if t_tok.isdigit():
            if len(t_tok) > 9:
                return None
            t = int(t_tok)
        else:
            parts = t_tok.split(b":")
            if len(parts) > 3 or not all(p.isdigit() and len(p) < 6 for p in parts):
                return None
            t = int(parts[-1]) + 1000 * int(parts[-2])
            if len(parts) == 3:
                t += 60000 * int(parts[0])
            if t > INT_MAX:
                return None  # Webots' int arithmetic wraps: the exact path wraps it too
        if t <= prev_time:
            return None
        try:
            values = list(map(float, toks[2:]))
        except ValueError:
            return None
        if not math.isfinite(sum(values)) or NO_VALUE_MARKER in values:
            return None
        res = self.result
        res.times_ms.append(t)
        res.pose_names.append(_decode(toks[1]))
        res.rows.append(values)
        res.pose_lines.append(piece.line)
        self.pose_cols0.append(piece.col0)
        return t

    def read_pose_slow(
        self, piece: _Piece, spans: list[tuple[int, int]], prev: tuple[int, int]
    ) -> int | None:
        """Check one pose line fully; return its time as Webots reads it, or ``None``."""
        pose = _PoseLine(piece, spans)
        self.pose_nul(pose)
        self.empty_cells(pose)
        time_ms, ok = self.pose_time(pose, prev)
        if len(pose.tokens) < 2:
            self.missing_pose_name(pose, time_ms)
            return time_ms
        values, nan_columns, values_ok = self.pose_values(pose, time_ms)
        count_ok = self.value_count(pose, time_ms)
        if ok and values_ok and count_ok and time_ms is not None:
            res = self.result
            res.nan_commands.extend((len(res.times_ms), j) for j in nan_columns)
            res.times_ms.append(time_ms)
            res.pose_names.append(_decode(pose.tokens[1]))
            res.rows.append(values)
            res.pose_lines.append(pose.line)
            self.pose_cols0.append(piece.col0)
        return time_ms

    def pose_nul(self, pose: _PoseLine) -> None:
        """A NUL byte: Webots' C string ends there (the tokens stop before it)."""
        nul = pose.raw.find(b"\0")
        if nul >= 0:
            self.report(
                "MT114",
                pose.line,
                pose.c0 + nul,
                "NUL byte: Webots' C strings end there, so the rest of the line is lost",
                "remove the NUL byte",
            )

    def empty_cells(self, pose: _PoseLine) -> None:
        """Empty cells (``,,``), which ``strtok`` collapses."""
        spans, c0 = pose.spans, pose.c0
        for k in range(1, len(spans)):
            gap = pose.raw[spans[k - 1][1] : spans[k][0]]
            if gap.count(b",") > 1:
                where = spans[k - 1][1] + gap.index(b",") + 1
                self.report(
                    "MT202",
                    pose.line,
                    c0 + where,
                    "empty cell: Webots skips ',,' so every value after it moves one joint left",
                    "write '*' for a joint that gets no command in this pose",
                    end_column=c0 + where + 1,
                )

    def pose_time(self, pose: _PoseLine, prev: tuple[int, int]) -> tuple[int | None, bool]:
        """The pose time as Webots reads it (None if it cannot), and whether it is valid and
        after the previous pose's; ``prev`` is (time in ms, line) of that pose."""
        t_tok = pose.tokens[0]
        a0, b0 = pose.spans[0]
        line, c0 = pose.line, pose.c0
        scanned = scan_time(t_tok)
        time_ms: int | None = None if scanned is None else scanned.ms
        if _well_formed_time(t_tok) and (scanned is None or scanned.exact_ms > INT_MAX):
            # Digits Webots accepts, but the arithmetic overflows a C int.
            outcome = "rejects it" if scanned is None else f"reads it as {scanned.ms} ms"
            self.report(
                "MT112",
                line,
                c0 + a0,
                f"pose time {show(t_tok)} is {_exact_time(t_tok)} ms, beyond the {INT_MAX} ms"
                f" a C int holds; Webots {outcome}",
                "motions longer than 24 days are not supported",
                end_column=c0 + b0,
                rejects=scanned is None,  # a wrapped time Webots reads does not reject
            )
        elif scanned is None:
            self.report(
                "MT105",
                line,
                c0 + a0,
                f"expected a pose time ('m:s:ms', 's:ms' or 'ms'), found {show(t_tok)}",
                _time_hint(t_tok),
                end_column=c0 + b0,
            )
        if time_ms is None:
            return None, False
        prev_time, prev_line = prev
        if time_ms <= prev_time:
            self.report(
                "MT106",
                line,
                c0 + a0,
                f"pose time {time_ms} ms is not after the previous pose's {prev_time} ms"
                f" (line {prev_line})",
                "pose times must strictly increase",
                time_ms=time_ms,
                end_column=c0 + b0,
            )
            return time_ms, False
        return time_ms, True

    def missing_pose_name(self, pose: _PoseLine, time_ms: int | None) -> None:
        """A line of one token: no pose name (not reported after a time Webots cannot read)."""
        if time_ms is not None:
            self.report(
                "MT107",
                pose.line,
                pose.c0 + pose.spans[0][1],
                "expected a pose name after the time, found end of line",
                "a pose line is 'time,name,value,...'",
                time_ms=time_ms,
            )

    def pose_values(
        self, pose: _PoseLine, time_ms: int | None
    ) -> tuple[list[float], list[int], bool]:
        """The first J value cells: (values, columns of the ``nan`` commands, all readable)."""
        values: list[float] = []
        nan_columns: list[int] = []
        ok = True
        for j in range(min(self.n_joints, len(pose.tokens) - 2)):
            cell = self.cell_value(pose, j, time_ms)
            if cell is None:
                ok = False
                values.append(_NAN)
                continue
            value, command = cell
            if command and math.isnan(value):
                nan_columns.append(j)
            values.append(value)
        return values, nan_columns, ok

    def cell_value(self, pose: _PoseLine, j: int, time_ms: int | None) -> tuple[float, bool] | None:
        """Value cell ``j`` (0-based joint) as ``sscanf("%lf")`` reads it: (value, whether it is a
        command), NaN for no command (``*``, the -9999999.9 marker); None if Webots cannot read
        it."""
        tok = pose.tokens[2 + j]
        a, b = pose.spans[2 + j]
        line, c0 = pose.line, pose.c0
        joint = self.result.joints[j]
        if tok == b"*":
            self.star_seen = True
            return _NAN, False
        scanned = scan_double(tok)
        if scanned is None:
            hint = None
            if tok.strip(b" \t") == b"*":
                hint = "'*' must stand alone: remove the white space around it"
            elif tok.strip() == b"":
                hint = "a cell of white space is not empty to Webots: write a number or '*'"
            self.report(
                "MT108",
                line,
                c0 + a,
                f"expected a number or '*' for {joint}, found {show(tok)}",
                hint,
                joint=joint,
                time_ms=time_ms,
                end_column=c0 + b,
            )
            return None
        value, end = scanned
        rest = tok[end:]
        if rest.strip(b" \t\v\f"):
            unit = _UNIT_SUFFIX.match(rest)
            self.report(
                "MT203",
                line,
                c0 + a + end,
                f"{joint} = {show(tok)} reads as {value!r}: Webots ignores {show(rest)}",
                "values are plain numbers in radians (metres for linear joints)"
                if unit
                else f"write {show(tok[:end].strip())}",
                joint=joint,
                time_ms=time_ms,
                end_column=c0 + b,
            )
        if not math.isfinite(value):
            self.report(
                "MT113",
                line,
                c0 + a,
                f"{joint} = {show(tok)} is not a finite number; Webots sends it to the motor",
                "write a number, or '*' for no command",
                joint=joint,
                time_ms=time_ms,
                end_column=c0 + b,
            )
            return (_NAN if math.isnan(value) else value), True
        if value == NO_VALUE_MARKER:
            self.report(
                "MT204",
                line,
                c0 + a,
                f"{joint} = {show(tok)} is Webots' 'no value' marker: the cell reads as '*'",
                "write '*' if no command is meant",
                joint=joint,
                time_ms=time_ms,
                end_column=c0 + b,
            )
            self.star_seen = True
            return _NAN, False
        return value, True

    def value_count(self, pose: _PoseLine, time_ms: int | None) -> bool:
        """Whether the line has exactly J values, one per joint (MT109, MT110 if not)."""
        n = self.n_joints
        values_toks = pose.tokens[2:]
        if len(values_toks) < n:
            missing = self.result.joints[len(values_toks) :]
            names = ", ".join(missing[:3]) + (", ..." if len(missing) > 3 else "")
            self.report(
                "MT109",
                pose.line,
                pose.c0 + pose.spans[-1][1],
                f"expected {n} values (one per joint), found {len(values_toks)}; no value for"
                f" {names}",
                "write '*' for a joint that gets no command in this pose",
                time_ms=time_ms,
            )
            return False
        if len(values_toks) > n:
            a, b = pose.spans[2 + n]
            self.report(
                "MT110",
                pose.line,
                pose.c0 + a,
                f"expected {n} values (one per joint), found {len(values_toks)}; extra"
                f" {show(values_toks[n])}",
                _decimal_comma_hint(values_toks),
                time_ms=time_ms,
                end_column=pose.c0 + b,
            )
            return False
        return True

    # -- whole file -----------------------------------------------------------------------------

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
        self.check_utf8()
        pieces = self.pieces()
        header_piece = next(pieces)
        if not self.read_header(header_piece):
            return res
        # The bulk path reads clean files only: not one whose header Webots already rejects.
        bulk = not self.exact and res.accepted and len(self.data) >= self.bulk_min_bytes
        if bulk and header_piece.col0 == 0 and self.read_bulk():
            return res
        prev = (-1, header_piece.line)
        last_line = header_piece.line
        pose_lines_seen = 0
        fast = not self.exact
        for piece in pieces:
            t = self.read_pose_fast(piece, prev[0]) if fast else None
            if t is None:
                spans = token_spans(piece.data)
                if not spans:
                    self.blank_line(piece)
                    break
                before = len(res.diagnostics)
                t = self.read_pose_slow(piece, spans, prev)
                if piece.col0:
                    # The rest of a cut line: MT111 said why; keep only where Webots stops.
                    del res.diagnostics[before + 1 :]
            pose_lines_seen += 1
            last_line = piece.line
            if t is not None:
                prev = (t, piece.line)
        if not self.joint_tokens:  # Webots counts joints and poses after reading every line
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
        if self.n_joints == 0 or not res.accepted:
            return res
        self.check_motion()
        return res

    def read_bulk(self) -> bool:
        """Read a large clean file in one go (see :mod:`._bulk`); False to take the exact path."""
        from motiontool.motionfmt._bulk import read_clean_body

        if len(self.lines[0]) + 1 > FGETS_PIECE:
            return False
        body = self.data[len(self.lines[0]) + 1 :]
        got = read_clean_body(body, self.n_joints, NO_VALUE_MARKER, FGETS_PIECE - 1)
        if got is None:
            return False
        times, names, values = got
        res = self.result
        res.times_ms = times
        res.pose_names = names
        res.rows = values  # type: ignore[assignment]  # (P, J) float64 array
        res.pose_lines = list(range(2, len(times) + 2))
        self.pose_cols0.extend([0] * len(times))
        self.check_motion()
        return True

    def blank_line(self, piece: _Piece) -> None:
        """A line with no token ends the motion; warn if anything follows it."""
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
        self.report(
            "MT201",
            piece.line,
            piece.col0 + 1,
            f"{what}: Webots ignores everything after it ({where})",
            "remove the blank line",
        )

    def check_utf8(self) -> None:
        try:
            self.data.decode("utf-8")
        except UnicodeDecodeError:
            pass
        else:
            return
        for i, content in enumerate(self.lines):
            try:
                content.decode("utf-8")
            except UnicodeDecodeError as exc:
                bad = content[exc.start]
                where = "a joint name" if i == 0 else "this line"
                consequence = (
                    "; no motor name will match it" if i == 0 else "; other tools may not read it"
                )
                self.report(
                    "MT208",
                    i + 1,
                    exc.start + 1,
                    f"byte 0x{bad:02X} in {where} is not UTF-8{consequence}",
                    "save the file as UTF-8",
                )

    # -- checks on the motion Webots reads -------------------------------------------------------

    def cell_column(self, pose: int, cell: int) -> tuple[int, int]:
        """1-based (column, end column) of token ``cell`` (0 = time) of pose ``pose``."""
        line = self.result.pose_lines[pose]
        col0 = self.pose_cols0[pose]
        content = self.lines[line - 1][col0 : col0 + FGETS_PIECE]
        a, b = token_spans(content)[cell]
        return col0 + a + 1, col0 + b + 1

    def check_motion(self) -> None:
        res = self.result
        times = res.times_ms
        if not times:
            return
        if times[0] > 0:
            col, end = self.cell_column(0, 0)
            self.report(
                "MT206",
                res.pose_lines[0],
                col,
                f"first pose is at {times[0]} ms: Webots commands it at once (t = 0), so the"
                f" robot jumps to it instead of moving there in {times[0]} ms",
                "add a first pose at 00:00:000 that holds the robot's start position",
                time_ms=times[0],
                end_column=end,
            )
        step = self.timestep_ms
        if step:
            for p, t in enumerate(times):
                if t % step:
                    col, end = self.cell_column(p, 0)
                    lo = t - t % step
                    fits = lo + step <= INT_MAX  # the step after may be past a C int (MT115)
                    steps = f"steps at {lo} and {lo + step} ms" if fits else f"step at {lo} ms"
                    self.report(
                        "MT209",
                        res.pose_lines[p],
                        col,
                        f"pose at {t} ms is not a multiple of the {step} ms time step: the"
                        f" controller never commands it exactly ({steps})",
                        f"move it to {lo} or {lo + step} ms" if fits else f"move it to {lo} ms",
                        time_ms=t,
                        end_column=end,
                    )
            self.check_clock(step)
        if self.star_seen:
            self.check_uncommanded()

    def check_clock(self, step: int) -> None:
        """MT115: Webots' int playback time wraps before the motion ends (see :mod:`.clock`)."""
        res = self.result
        overflow = clock_overflow(int(res.times_ms[-1]), step) if step <= INT_MAX else None
        if overflow is None:
            return
        col, end = self.cell_column(len(res.times_ms) - 1, 0)
        self.report(
            "MT115",
            res.pose_lines[-1],
            col,
            overflow.message,
            overflow.hint,
            time_ms=res.times_ms[-1],
            end_column=end,
        )

    def check_uncommanded(self) -> None:
        """Report runs of ``*`` cells: the joint gets no command over the segments they touch."""
        res = self.result
        times = res.times_ms
        n_poses = len(times)
        header_spans = token_spans(self.lines[0])[2:]
        nan_cells = set(res.nan_commands)  # a literal 'nan' is a command, not a '*'
        for j, joint in enumerate(res.joints):
            column = [row[j] for row in res.rows]
            undefined = [v != v and (p, j) not in nan_cells for p, v in enumerate(column)]
            if all(undefined):
                a, b = header_spans[j]
                self.report(
                    "MT211",
                    1,
                    a + 1,
                    f"{joint} is '*' in every pose: this motion never commands it",
                    "remove the column if the motion is not meant to drive this joint",
                    joint=joint,
                    end_column=b + 1,
                )
                continue
            p = 0
            while p < n_poses:
                if not undefined[p]:
                    p += 1
                    continue
                q = p
                while q + 1 < n_poses and undefined[q + 1]:
                    q += 1
                start = times[p - 1] if p > 0 else 0
                col, end = self.cell_column(p, 2 + j)
                if q + 1 < n_poses:
                    message = (
                        f"'*' leaves {joint} uncommanded from {start} ms to {times[q + 1]} ms:"
                        " it holds its previous target instead of moving"
                    )
                    severity = Severity.WARNING
                else:  # a trailing run only holds the last target: worth knowing, not a trap
                    message = (
                        f"'*' leaves {joint} uncommanded from {start} ms to the end:"
                        " it holds its last target"
                    )
                    severity = Severity.INFO
                self.report(
                    "MT207",
                    res.pose_lines[p],
                    col,
                    message,
                    "write a value where the joint should move; '*' does not interpolate",
                    joint=joint,
                    time_ms=times[p],
                    end_column=end,
                    severity=severity,
                )
                p = q + 1


def _well_formed_time(tok: bytes) -> bool:
    """Digits and at most two colons, every field non-empty: the shape Webots accepts."""
    fields = tok.split(b":")
    return len(fields) <= 3 and all(f.isdigit() for f in fields)


def _exact_time(tok: bytes) -> int:
    fields = [int(f) for f in tok.split(b":")]
    fields = [0] * (3 - len(fields)) + fields
    return fields[0] * 60000 + fields[1] * 1000 + fields[2]


def _time_hint(tok: bytes) -> str:
    stripped = tok.strip(b" \t")
    if stripped.startswith(b"#"):
        return "'#' does not start a comment: .motion files have no comments; remove the line"
    if not stripped:
        return (
            "this line holds only white space, which Webots does not take for a blank line;"
            " delete the spaces"
        )
    if stripped != tok:
        return "remove the white space around the time"
    if tok.startswith((b"-", b"+")):
        return "pose times are unsigned milliseconds"
    if b"." in tok:
        return "times are integer milliseconds: write 'm:s:ms', e.g. 00:01:500"
    if tok.count(b":") > 2:
        return "at most two ':' (minutes:seconds:milliseconds)"
    if b":" in tok:
        return "every field of 'm:s:ms' needs at least one digit"
    return "write the time as 'm:s:ms', e.g. 00:01:500"


def _decimal_comma_hint(values: list[bytes]) -> str | None:
    for a, b in itertools.pairwise(values):
        if _INT_TOKEN.fullmatch(a.strip()) and _DIGITS_TOKEN.fullmatch(b.strip()):
            return (
                f"decimal comma? '{a.strip().decode()},{b.strip().decode()}' splits into two"
                f" values: write '{a.strip().decode()}.{b.strip().decode()}'"
            )
    return None


def read_bytes(
    data: bytes, path: str = "<string>", *, timestep_ms: int | None = None
) -> ReadResult:
    """Read a ``.motion`` file's bytes as Webots does and collect every diagnostic.

    Args:
        data: the file's content, as bytes.
        path: how diagnostics name the file.
        timestep_ms: the controller time step in milliseconds; when given, pose times that are
            not a multiple of it are reported.

    Returns:
        The poses Webots reads and the diagnostics; never raises on bad content.
    """
    if timestep_ms is not None and timestep_ms <= 0:
        raise ValueError(f"timestep_ms must be positive, got {timestep_ms}")
    return _Reader(data, path, timestep_ms).read()
