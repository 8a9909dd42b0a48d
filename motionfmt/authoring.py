"""Authoring: mirror, concatenate, trim and scale motions without losing what is kept.

Every function takes lossless :class:`~motiontool.motionfmt.document.MotionDocument` inputs and
returns a new document (the inputs are not modified). Lines and cells an operation keeps keep
their spelling (spacing, ``+0.1``, digits, CRLF); new poses and changed numbers are spelt
canonically (shortest round-trip repr), so every value is the exact double intended.

* :func:`mirror` swaps each left/right pair of columns and negates the joints whose mirror image
  turns the other way, from a ``{joint: (partner, sign)}`` map
  (:func:`motiontool.kinematics.mirror.mirror_map` derives it from a robot model). A negated
  cell keeps its digits (``0.10`` -> ``-0.10``); ``mirror(mirror(x))`` commands what ``x`` does.
* :func:`concat` plays motions one after another, with a transition from one's last pose to the
  next one's first pose that is the shortest whole-ms duration within maxVelocity x margin
  (:func:`~motiontool.motionfmt.transform.fit_limits`, the logic of ``retime --fit-limits``).
* :func:`trim` keeps a time window with exact boundary poses: the targets Webots' player
  commands there (:func:`~motiontool.motionfmt.player.commands_at`; ``*`` where it sends none).
* :func:`scale` scales every joint's excursion about a reference pose and clips to the limits.

Pure numpy: robot knowledge (mirror maps, limits) comes in as plain mappings.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from motiontool.motionfmt.document import MotionDocument, loads
from motiontool.motionfmt.errors import MotionToolError
from motiontool.motionfmt.nonfinite import refuse_non_finite
from motiontool.motionfmt.reader import NO_VALUE_MARKER, token_spans
from motiontool.motionfmt.transform import DEFAULT_MARGIN, MAX_TIME_MS, fit_limits
from motiontool.motionfmt.writer import TimeStyle, _pose_line, format_time, format_value

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = [
    "Clip",
    "Concatenated",
    "Mirrored",
    "Scaled",
    "Transition",
    "Trimmed",
    "concat",
    "mirror",
    "scale",
    "trim",
]


# --------------------------------------------------------------------------- lines and cells


@dataclass
class _Lines:
    """A document's physical lines: header, one line per pose, the ignored rest.

    ``eol`` is ``b"\\r"`` for a CRLF file (lines are split on ``\\n``), ``b""`` otherwise.
    """

    header: bytes
    poses: list[bytes]
    suffix: list[bytes]
    eol: bytes
    final_newline: bool

    @classmethod
    def of(cls, doc: MotionDocument) -> _Lines:
        return cls.of_bytes(doc.to_bytes(), doc.n_poses)

    @classmethod
    def of_bytes(cls, data: bytes, n_poses: int) -> _Lines:
        """The lines of a document's bytes ``data`` that has ``n_poses`` pose lines."""
        final = data.endswith(b"\n")
        lines = data.split(b"\n")
        if final:
            lines.pop()
        eol = b"\r" if lines[0].endswith(b"\r") else b""
        return cls(lines[0], lines[1 : n_poses + 1], lines[n_poses + 1 :], eol, final)

    def to_bytes(self) -> bytes:
        body = b"\n".join([self.header, *self.poses, *self.suffix])
        return body + b"\n" if self.final_newline else body


def _cells(line: bytes) -> list[bytes] | None:
    """The cells of a pose line split on ``,`` (the end's ``\\r`` kept on the last cell's
    outside: see :func:`_join_cells`), or None when the line needs Webots' tokenizer (empty
    cells, a NUL, a ``\\r`` inside)."""
    body = line[:-1] if line.endswith(b"\r") else line
    if b"\r" in body or b"\0" in body:
        return None
    parts = body.split(b",")
    return None if b"" in parts else parts


def _replace(line: bytes, changes: Mapping[int, bytes]) -> bytes:
    """``line`` with its cells (0: time, 1: name, 2..: values) replaced as ``changes`` says."""
    if not changes:
        return line
    parts = _cells(line)
    if parts is not None:
        for k, text in changes.items():
            parts[k] = text
        return b",".join(parts) + (b"\r" if line.endswith(b"\r") else b"")
    spans = token_spans(line)
    out = line
    for k in sorted(changes, reverse=True):
        a, b = spans[k]
        out = out[:a] + changes[k] + out[b:]
    return out


def _tokens(line: bytes) -> list[bytes]:
    """Every cell of a pose line as Webots' tokenizer finds it."""
    parts = _cells(line)
    if parts is not None:
        return parts
    return [line[a:b] for a, b in token_spans(line)]


def _lf_block(block: bytes, n_lines: int, eol: bytes) -> bytes | None:
    """``block`` (``n_lines`` pose lines joined with ``\\n``) without its ``\\r``s, or None
    when a line needs Webots' tokenizer for its ends or a NUL (a stray ``\\r``, an end unlike
    ``eol``). Empty cells are the callers' to find: a two-byte ``in`` scan of 26 MB takes
    30-40 ms, a one-byte one (``memchr``) 2 ms."""
    if eol:
        if block.count(b"\r") != n_lines or not block.endswith(b"\r"):
            return None
        if block.count(b"\r\n") != n_lines - 1:
            return None
        block = block.replace(b"\r", b"")
    elif b"\r" in block:
        return None
    return None if b"\0" in block else block


def _columns(
    poses: list[bytes], n_cells: int, eol: bytes, block: bytes | None = None
) -> list[list[bytes]] | None:
    """The cells of every pose line, column by column (``n_cells`` columns, time first), in
    one ``split`` of the whole block; None when a line needs Webots' tokenizer (empty cells,
    a NUL, a stray ``\\r``, an end unlike ``eol``). ``block``: the lines already joined with
    ``\\n``, when the caller has them (a slice of the file's bytes)."""
    lf = _lf_block(b"\n".join(poses) if block is None else block, len(poses), eol)
    if lf is None or b",," in lf or b",\n" in lf or b"\n," in lf:
        return None
    if lf.startswith(b",") or lf.endswith(b","):
        return None
    flat = lf.replace(b"\n", b",").split(b",")
    if len(flat) != n_cells * len(poses):
        return None
    return [flat[k::n_cells] for k in range(n_cells)]


def _lines_of(columns: list[list[bytes]], eol: bytes) -> list[bytes]:
    """Pose lines from cells given column by column (see :func:`_columns`)."""
    lines = list(map(b",".join, zip(*columns, strict=True)))
    return [line + eol for line in lines] if eol else lines


def _set_time(line: bytes, token: bytes) -> bytes:
    """``line`` with its time cell (which never has white space: MT105) replaced by ``token``."""
    return token + line[line.index(b",") :]


#: What a finite number's cell can start with, besides '-', '.' and a digit, in a file Webots
#: accepts: white space (sscanf skips it) and '+'.
_ODD_STARTS = (b", ", b",+", b",\t", b",\x0b", b",\x0c")


def _odd_start(block: bytes) -> bool:
    """Whether a cell of ``block`` (after the first of its line) starts with white space or
    '+' (a few ``in`` scans: a regex over a 26 MB file costs more than all of them)."""
    return any(odd in block for odd in _ODD_STARTS)


def _negate_column(column: list[bytes], flags: list[bool], plain: bool) -> list[bytes]:
    """:func:`_negate` on the cells where ``flags`` is True; ``plain``: every cell starts with
    '-', '.', a digit or '*' (then the fast paths)."""
    if not plain:
        return [_negate(t) if f else t for t, f in zip(column, flags, strict=True)]
    if all(flags):  # every cell a nonzero number: prefix '-', then drop double minus signs
        block = (b"\n" + b"\n".join(column)).replace(b"\n", b"\n-").replace(b"\n--", b"\n")
        return block.split(b"\n")[1:]
    return [
        (t[1:] if t[0] == 45 else b"-" + t) if f else t  # 45: '-'
        for t, f in zip(column, flags, strict=True)
    ]


#: Input bytes rearranged per step of :func:`_permute_cells`.
_GATHER_BYTES = 1 << 20


def _permute_cells(
    block: bytes,
    n_lines: int,
    eol: bytes,
    cells: Sequence[int],
    negate: npt.NDArray[np.bool_],
) -> bytes | None:
    """The pose block with every line's cells rearranged, by a numpy gather of its bytes.

    Output cell ``k`` of line ``p`` is input cell ``cells[k]`` of that line, negated where
    ``negate[p, k]`` (shape (n_lines, len(cells)), bool; column 0, the time, never) as
    :func:`_negate_column` does it on plain cells: a leading ``-`` is dropped, otherwise one is
    put in front. The bytes :func:`_columns`, :func:`_negate_column` and :func:`_lines_of`
    give, without a Python object per cell. None (the caller takes that path) unless every
    line is plain: ends as ``eol`` says, no NUL (:func:`_lf_block`), exactly ``len(cells)``
    cells, none empty nor starting with white space or ``+`` (:data:`_ODD_STARTS`). Those
    conditions imply the ones of that path's fast, plain case, where it is exact.
    """
    import numpy as np

    plain = _lf_block(block, n_lines, eol)
    if plain is None or bool(negate[:, 0].any()):
        return None
    n_cells = len(cells)
    size = len(plain)
    end = eol + b"\n"
    # Bytes the output has and the input may not: ',' and ',-' (a cell put after a separator
    # with a minus sign), then the line end (whose start is the last line's end, ``eol``).
    buf = np.frombuffer(plain + b",-" + end, dtype=np.uint8)
    text = buf[:size]
    seps = np.flatnonzero((text == 44) | (text == 10))  # 44: ',', 10: '\n'
    if seps.shape[0] != n_lines * n_cells - 1:
        return None
    newline = text[seps] == 10
    if int(np.count_nonzero(newline)) != n_lines - 1:
        return None
    if not bool(newline[n_cells - 1 :: n_cells].all()):
        return None  # a line with more or fewer cells than the others
    # int32 offsets where the output and the input both stay below 2 GiB (halves the memory).
    bound = len(buf) + n_lines * (n_cells + len(end))
    idx: type[np.signedinteger[Any]] = np.int32 if bound < 2**31 else np.int64
    bounds = np.empty(n_lines * n_cells + 1, dtype=idx)
    bounds[0] = -1
    bounds[1:-1] = seps
    bounds[-1] = size
    starts = (bounds[:-1] + 1).reshape(n_lines, n_cells)
    stops = bounds[1:].reshape(n_lines, n_cells)
    if int((stops - starts).min()) < 1:
        return None  # an empty cell
    odd = np.zeros(256, dtype=bool)
    odd[[start[1] for start in _ODD_STARTS]] = True
    if bool(odd[text[starts]].any()):
        return None  # a cell that starts with white space or '+'
    order = np.asarray(cells, dtype=np.intp)
    # Lines are done about a megabyte of input at a time: the index arrays stay small (one
    # index for the whole file is 4 bytes per byte, and fresh memory is slow to touch).
    rows = max(1, _GATHER_BYTES * n_lines // max(size, 1))
    parts = []
    for a in range(0, n_lines, rows):
        b = min(a + rows, n_lines)
        neg = negate[a:b]
        first = starts[a:b, order]
        last = stops[a:b, order]
        minus = text[first] == 45  # 45: '-'
        first += neg & minus  # drop the minus sign
        # Two pieces per output cell: what comes before it (nothing, the line end, ',' or
        # ',-'), then the cell's bytes; after the last line, its end (eol).
        piece_at = np.empty((b - a, n_cells, 2), dtype=idx)
        piece_len = np.empty((b - a, n_cells, 2), dtype=idx)
        piece_at[:, :, 0] = size
        piece_len[:, :, 0] = 1
        piece_len[:, :, 0] += neg & ~minus  # put a minus sign in
        piece_at[:, 0, 0] = size + 2
        piece_len[:, 0, 0] = len(end)
        if a == 0:
            piece_len[0, 0, 0] = 0
        piece_at[:, :, 1] = first
        piece_len[:, :, 1] = last - first
        at = piece_at.ravel()
        length = piece_len.ravel()
        if b == n_lines:
            at = np.append(at, np.asarray(size + 2, dtype=idx))
            length = np.append(length, np.asarray(len(eol), dtype=idx))
        # Concatenated ranges: output byte i of a piece is input byte at + i.
        out_end = np.cumsum(length, dtype=idx)
        shift = at - (out_end - length)
        index = np.repeat(shift, length)
        index += np.arange(int(out_end[-1]), dtype=idx)
        parts.append(np.take(buf, index).tobytes())
    return b"".join(parts)


def _respell(token: bytes, value: float) -> bytes:
    """``value`` spelt canonically, keeping ``token``'s leading white space."""
    lead = token[: len(token) - len(token.lstrip())]
    return lead + format_value(value).encode("ascii")


def _negate(token: bytes) -> bytes:
    """The cell that reads as minus ``token``'s number, with the same digits."""
    head = token[:1]
    if head == b"-":
        return token[1:]
    if head.isdigit() or head == b".":
        return b"-" + token
    body = token.lstrip()
    lead = token[: len(token) - len(body)]
    if body[:1] == b"-":
        return lead + body[1:]
    if body[:1] == b"+":
        return lead + b"-" + body[1:]
    return lead + b"-" + body


def _with_eol(line: bytes, eol: bytes) -> bytes:
    return (line[:-1] if line.endswith(b"\r") else line) + eol


def _refuse_duplicates(doc: MotionDocument, what: str) -> None:
    seen: set[str] = set()
    for name in doc.joints:
        if name in seen:
            raise MotionToolError(
                f"{doc.path}: joint '{name}' is named twice (MT205); {what} needs each joint "
                "once: remove or rename the extra column first"
            )
        seen.add(name)


def _repair(
    doc: MotionDocument,
    values: npt.NDArray[np.float64],
    commanded: npt.NDArray[np.bool_],
) -> MotionDocument:
    """Re-spell canonically every cell of ``doc`` that does not read as ``values`` (NaN and
    ``commanded`` False: ``*``); a safety net under the textual edits."""
    import numpy as np

    got = doc.motion
    same = (got.values == values) | (~got.commanded & ~commanded)
    same &= got.commanded == commanded
    for p, j in np.argwhere(~same).tolist():
        doc.set_value(p, j, float(values[p, j]) if commanded[p, j] else math.nan)
    return doc


# --------------------------------------------------------------------------- mirror


@dataclass(frozen=True, eq=False)
class Mirrored:
    """What :func:`mirror` did.

    Attributes:
        data: the mirrored file's bytes.
        path: its name (the input's).
        swapped: column pairs whose values were exchanged, as (left-or-first, partner) names.
        negated: joints (output columns) whose values changed sign.
        renamed: (old, new) header names: a column whose partner is not in the file is renamed
            to the partner.
        unmapped: columns the map does not know (not motors of the robot): left unchanged.
    """

    data: bytes
    path: str
    swapped: tuple[tuple[str, str], ...]
    negated: tuple[str, ...]
    renamed: tuple[tuple[str, str], ...]
    unmapped: tuple[str, ...]

    @functools.cached_property
    def document(self) -> MotionDocument:
        """The mirrored document (read on first use)."""
        return loads(self.data, self.path)


@dataclass(frozen=True, eq=False)
class _MirrorPlan:
    """What :func:`mirror` writes: output column ``j`` (header name ``names[j]``) holds input
    column ``source[j]`` times ``signs[j]``; ``flip`` (P, J) bool: the cells whose text is
    negated; ``values`` (P, J) float64, rad (m), and ``commanded`` (P, J) bool: the result."""

    joints: tuple[str, ...]
    source: list[int]
    signs: list[int]
    names: list[str]
    flip: npt.NDArray[np.bool_]
    values: npt.NDArray[np.float64]
    commanded: npt.NDArray[np.bool_]
    swapped: tuple[tuple[str, str], ...]
    renamed: tuple[tuple[str, str], ...]
    unmapped: tuple[str, ...]

    @property
    def moves(self) -> list[int]:
        """The output columns whose cells change: taken from another column, or negated."""
        return [
            j
            for j, (k, s) in enumerate(zip(self.source, self.signs, strict=True))
            if k != j or s < 0
        ]


def _mirror_plan(doc: MotionDocument, mapping: Mapping[str, tuple[str, int]]) -> _MirrorPlan:
    """The columns, signs and names of ``doc``'s mirror image (see :func:`mirror`)."""
    import numpy as np

    _refuse_duplicates(doc, "mirroring")
    motion = doc.motion
    refuse_non_finite(motion, doc.result, "mirroring")
    joints = motion.joints
    col = {name: j for j, name in enumerate(joints)}
    source: list[int] = []
    signs: list[int] = []
    names: list[str] = []
    swapped: list[tuple[str, str]] = []
    renamed: list[tuple[str, str]] = []
    unmapped: list[str] = []
    for j, name in enumerate(joints):
        if name not in mapping:
            source.append(j)
            signs.append(1)
            names.append(name)
            unmapped.append(name)
            continue
        partner, sign = mapping[name]
        if sign not in (1, -1):
            raise MotionToolError(f"the mirror sign of {name} must be +1 or -1, got {sign}")
        if partner == name or partner not in col:
            source.append(j)
            names.append(partner)
            if partner != name:
                renamed.append((name, partner))
        else:
            source.append(col[partner])
            names.append(name)
            if j < col[partner]:
                swapped.append((name, partner))
        signs.append(sign)

    src = np.asarray(source, dtype=np.intp)
    sgn = np.asarray(signs, dtype=np.float64)
    values = motion.values[:, src] * sgn + 0.0  # + 0.0: no '-0'
    commanded = motion.commanded[:, src]
    flip = (sgn < 0)[None, :] & commanded & (motion.values[:, src] != 0.0)
    if np.any(flip & (values == NO_VALUE_MARKER)):
        raise MotionToolError(
            f"{doc.path}: a value of {-NO_VALUE_MARKER} negated is Webots' 'no value' marker "
            f"{NO_VALUE_MARKER}: the mirror cannot be written"
        )
    return _MirrorPlan(
        joints,
        source,
        signs,
        names,
        flip,
        values,
        commanded,
        tuple(swapped),
        tuple(renamed),
        tuple(unmapped),
    )


def _mirror_header(header: bytes, plan: _MirrorPlan) -> bytes:
    """The header line with the renamed columns' new names."""
    if not plan.renamed:
        return header
    spans = token_spans(header[:-1] if header.endswith(b"\r") else header)
    old = [name for name, _new in plan.renamed]
    for j in sorted((j for j, name in enumerate(plan.joints) if name in old), reverse=True):
        a, b = spans[2 + j]
        header = header[:a] + plan.names[j].encode("utf-8", "surrogateescape") + header[b:]
    return header


def _pose_span(lines: _Lines) -> tuple[int, int]:
    """(start, stop): where the pose lines are in the bytes ``lines`` was split from."""
    start = len(lines.header) + 1
    return start, start + sum(map(len, lines.poses)) + len(lines.poses) - 1


def _mirror_gather(doc: MotionDocument, plan: _MirrorPlan) -> bytes | None:
    """The bytes of ``doc``'s mirror image, the pose lines rearranged by :func:`_permute_cells`;
    None where that does not apply (then the per-cell path of :func:`_mirror_bytes`)."""
    import numpy as np

    if not plan.moves:
        return None
    data = doc.to_bytes()
    lines = _Lines.of_bytes(data, doc.n_poses)
    start, stop = _pose_span(lines)
    negate = np.zeros((len(lines.poses), 2 + len(plan.source)), dtype=bool)
    negate[:, 2:] = plan.flip
    cells = [0, 1, *(2 + k for k in plan.source)]
    out = _permute_cells(data[start:stop], len(lines.poses), lines.eol, cells, negate)
    if out is None:
        return None
    return b"".join([_mirror_header(lines.header, plan), b"\n", out, data[stop:]])


def _mirror_bytes(doc: MotionDocument, plan: _MirrorPlan, *, gather: bool = True) -> bytes:
    """The bytes of ``doc``'s mirror image as ``plan`` says.

    ``gather``: plain pose lines are rearranged by :func:`_mirror_gather`; False takes the
    per-cell path below for every file: the reference the gather is tested against (the bytes
    are the same).
    """
    if gather:
        gathered = _mirror_gather(doc, plan)
        if gathered is not None:
            return gathered
    source, signs, moves = plan.source, plan.signs, plan.moves
    data = doc.to_bytes()
    lines = _Lines.of_bytes(data, doc.n_poses)
    start, stop = _pose_span(lines)  # before the header is renamed: a slice of ``data``
    lines.header = _mirror_header(lines.header, plan)
    fast = plain = False
    if moves:
        block = data[start:stop]
        columns = _columns(lines.poses, 2 + len(source), lines.eol, block)
        if columns is None:  # lines Webots' tokenizer must split: one by one
            rows = [_tokens(line) for line in lines.poses]
            columns = [list(c) for c in zip(*rows, strict=True)]
            fast = False
        else:
            fast = True
        plain = fast and not _odd_start(block)
        new_columns = list(columns)
        for j in moves:
            column = columns[2 + source[j]]
            if signs[j] < 0:
                column = _negate_column(column, plan.flip[:, j].tolist(), plain)
            new_columns[2 + j] = column
        if fast:
            last = lines.poses[-1]
            lines.poses = _lines_of(new_columns, lines.eol)
            if lines.eol and not last.endswith(lines.eol):
                lines.poses[-1] = lines.poses[-1][: -len(lines.eol)]
        else:
            lines.poses = [
                _replace(line, {2 + j: new_columns[2 + j][p] for j in moves})
                for p, line in enumerate(lines.poses)
            ]
    data = lines.to_bytes()
    if not (moves and fast and plain):
        # Cells negated by the slow path (white space, '+') are checked, and re-spelt if they
        # do not read as intended; the fast path's textual negation of a plain decimal number
        # is exact (strtod rounds correctly, symmetrically about 0).
        data = _repair(loads(data, doc.path), plan.values, plan.commanded).to_bytes()
    return data


def mirror(doc: MotionDocument, mapping: Mapping[str, tuple[str, int]]) -> Mirrored:
    """Mirror ``doc`` left/right: ``q'[partner] = sign * q[joint]`` for every mapped column.

    Args:
        doc: the document (not modified).
        mapping: ``{joint: (partner, sign)}``, sign +1 or -1, symmetric (the partner maps back
            with the same sign); a centre joint is its own partner.

    Where both columns of a pair are in the file their cells are exchanged (the header stays);
    a column whose partner is missing is renamed to it. ``*`` stays ``*``, a zero is not
    negated, and a negated number keeps its digits.

    Raises:
        MotionToolError: a joint named twice, or a ``nan``/``inf`` command.
    """
    plan = _mirror_plan(doc, mapping)
    data = _mirror_bytes(doc, plan)
    negated = tuple(plan.names[j] for j in range(len(plan.names)) if plan.signs[j] < 0)
    return Mirrored(data, doc.path, plan.swapped, negated, plan.renamed, plan.unmapped)


# --------------------------------------------------------------------------- concat


@dataclass(frozen=True)
class Transition:
    """One transition :func:`concat` inserted.

    Attributes:
        into: the path of the motion the transition leads into.
        start_ms: when it starts (the previous motion's last pose), ms, in the result.
        duration_ms: how long it lasts, ms.
        joint: the joint that needed the most time ('' when none moves or it was given).
        fitted: True when the duration was fitted to the velocity limits, False when given.
    """

    into: str
    start_ms: int
    duration_ms: int
    joint: str
    fitted: bool


@dataclass(frozen=True)
class Concatenated:
    """What :func:`concat` did.

    Attributes:
        document: the joined document (the first input's header and lines first).
        transitions: one per joint between two inputs.
        reordered: inputs whose columns were put in the first input's order.
        dropped_lines: lines after a terminating blank line (ignored by Webots) left out.
        unconstrained: joints without a velocity limit (not constrained by the fit).
    """

    document: MotionDocument
    transitions: tuple[Transition, ...]
    reordered: tuple[str, ...]
    dropped_lines: int
    unconstrained: tuple[str, ...]


def concat(
    docs: Sequence[MotionDocument],
    *,
    transition_ms: int | None = None,
    max_velocity: Mapping[str, float] | None = None,
    margin: float = DEFAULT_MARGIN,
) -> Concatenated:
    """Join ``docs`` one after another.

    Args:
        docs: two or more documents with the same joints (each once; any column order: the
            later ones are put in the first one's order, cell by cell, keeping spellings).
        transition_ms: the time from one motion's last pose to the next one's first pose, ms
            (>= 1). When None it is fitted: the shortest whole-ms duration in which every
            joint that both poses command moves within ``margin`` x its maximum velocity
            (``max_velocity``, rad/s or m/s), at least 1 ms.
        max_velocity: ``{joint: max velocity}``, rad/s (m/s); needed when ``transition_ms`` is
            None. A joint not in it is not constrained.
        margin: the fraction of the maximum velocity the transition may use, in (0, 1].

    Each next motion's times are shifted so that its first pose lands at the end of the
    transition (a first pose at t > 0 loses its lead-in: the transition replaces it).

    Raises:
        MotionToolError: fewer than two inputs, different joints, a joint named twice, a
            ``nan``/``inf`` command, or a result past :data:`MAX_TIME_MS`.
    """
    import numpy as np

    if len(docs) < 2:
        raise MotionToolError("concat needs two motions or more")
    if transition_ms is None and max_velocity is None:
        raise MotionToolError("give a transition time, or velocity limits to fit one")
    if transition_ms is not None and transition_ms < 1:
        raise MotionToolError(f"the transition must last at least 1 ms, got {transition_ms} ms")
    first = docs[0]
    joints = first.joints
    for doc in docs:
        _refuse_duplicates(doc, "concat")
        refuse_non_finite(doc.motion, doc.result, "concatenating")
    want = set(joints)
    for doc in docs[1:]:
        have = set(doc.joints)
        if have != want:
            missing = [j for j in joints if j not in have]
            extra = [j for j in doc.joints if j not in want]
            parts = []
            if missing:
                parts.append("lacks " + ", ".join(missing))
            if extra:
                parts.append("has " + ", ".join(extra) + " that the first does not")
            raise MotionToolError(
                f"{doc.path} does not have the joints of {first.path}: it "
                + " and ".join(parts)
                + "; concat needs the same joints in every motion (add the missing columns, "
                "e.g. as '*')"
            )
    limits = dict(max_velocity or {})
    unconstrained = tuple(j for j in joints if not math.isfinite(limits.get(j, math.inf)))

    base = _Lines.of(first)
    eol = base.eol
    out_poses = [_with_eol(line, eol) for line in base.poses]
    dropped = len(base.suffix)
    motion = first.motion
    end = int(motion.times_ms[-1])
    last_row = np.where(motion.commanded[-1], motion.values[-1], np.nan)
    transitions = []
    reordered = []
    style = first.time_style
    final_newline = base.final_newline
    for doc in docs[1:]:
        m = doc.motion
        order = [m.joints.index(name) for name in joints]
        if order != list(range(len(joints))):
            reordered.append(doc.path)
        values = m.values[:, order]
        commanded = m.commanded[:, order]
        start = np.where(commanded[0], values[0], np.nan)
        if transition_ms is None:
            retimed = fit_limits(
                [0, 1], joints, np.vstack([last_row, start]), limits, margin=margin
            )
            duration = int(retimed.times_ms[-1])
            joint = retimed.stretches[0].joint if retimed.stretches else ""
            fitted = True
        else:
            duration, joint, fitted = transition_ms, "", False
        shift = end + duration - int(m.times_ms[0])
        new_times = [int(t) + shift for t in m.times_ms]
        if new_times[-1] > MAX_TIME_MS:
            raise MotionToolError(
                f"joining {doc.path} would put its last pose at {new_times[-1]} ms, past the "
                f"longest time a .motion file can hold, {MAX_TIME_MS} ms"
            )
        transitions.append(Transition(doc.path, end, duration, joint, fitted))
        lines = _Lines.of(doc)
        stamps = [format_time(t, style).encode("ascii") for t in new_times]
        poses = lines.poses
        if order != list(range(len(joints))):
            columns = _columns(poses, 2 + len(joints), lines.eol)
            if columns is None:
                columns = [list(c) for c in zip(*map(_tokens, poses), strict=True)]
            poses = _lines_of([columns[0], columns[1], *(columns[2 + k] for k in order)], b"")
        ends = [eol] * len(poses)
        out_poses.extend(
            _set_time(line[:-1] if line.endswith(b"\r") else line, stamp) + end
            for line, stamp, end in zip(poses, stamps, ends, strict=True)
        )
        dropped += len(lines.suffix)
        final_newline = lines.final_newline
        end = new_times[-1]
        last_row = np.where(commanded[-1], values[-1], np.nan)
    if not final_newline:
        out_poses[-1] = _with_eol(out_poses[-1], b"")
    out = _Lines(base.header, out_poses, [], eol, final_newline)
    document = loads(out.to_bytes(), first.path)
    return Concatenated(document, tuple(transitions), tuple(reordered), dropped, unconstrained)


# --------------------------------------------------------------------------- trim


@dataclass(frozen=True)
class Trimmed:
    """What :func:`trim` did.

    Attributes:
        document: the trimmed document.
        from_ms, to_ms: the window kept, ms, in the input's times (``to_ms`` clamped to the
            input's last pose).
        shift_ms: how much earlier every kept time is in the result, ms (0 with keep_times).
        kept: input poses kept (their lines keep their spelling, but for the time).
        inserted: boundary poses added (0, 1 or 2).
    """

    document: MotionDocument
    from_ms: int
    to_ms: int
    shift_ms: int
    kept: int
    inserted: int


def _boundary_line(motion: Motion, at_ms: int, time_ms: int, style: TimeStyle, eol: bytes) -> bytes:
    import numpy as np

    from motiontool.motionfmt.player import commands_at

    targets, sent = commands_at(motion, np.asarray([at_ms], dtype=np.int64))
    row = np.where(sent[0], targets[0], np.nan).tolist()
    return _pose_line(time_ms, f"Pose{time_ms}ms", row, style).encode("utf-8") + eol


def trim(
    doc: MotionDocument,
    from_ms: int | None = None,
    to_ms: int | None = None,
    *,
    keep_times: bool = False,
) -> Trimmed:
    """Keep the part of ``doc`` between ``from_ms`` and ``to_ms`` (playback times, ms).

    The poses strictly inside are kept as written; at each boundary without a pose, a new pose
    holds exactly what Webots' player commands there (its interpolation, bit for bit; ``*``
    where a segment touching ``*`` sends no command). Times are shifted so the result starts
    at 0, unless ``keep_times`` (then the first pose is at ``from_ms``: MT206). ``to_ms`` past
    the last pose is clamped to it; ``from_ms`` before the first pose starts with the first
    pose's targets, which Webots commands from t = 0. A boundary that is a pose of the file
    keeps its line as written: where the segment into it touches ``*``, Webots sends that joint
    nothing at that one instant in the original, and the trimmed file commands it there.

    Raises:
        MotionToolError: ``from_ms >= to_ms``, a negative time, ``from_ms`` at or past the end,
            or a ``nan``/``inf`` command.
    """
    import numpy as np

    motion = doc.motion
    refuse_non_finite(motion, doc.result, "trimming")
    times = motion.times_ms
    last = int(times[-1])
    lo = 0 if from_ms is None else int(from_ms)
    hi = last if to_ms is None else min(int(to_ms), last)
    if lo < 0 or (to_ms is not None and to_ms < 0):
        raise MotionToolError("trim times cannot be negative")
    if lo >= hi:
        raise MotionToolError(
            f"nothing to keep between {lo} ms and {hi} ms (the motion ends at {last} ms): "
            "the window must start before it ends and before the last pose"
        )
    shift = 0 if keep_times else lo
    lines = _Lines.of(doc)
    style = doc.time_style
    eol = lines.eol
    inside = np.flatnonzero((times >= lo) & (times <= hi)).tolist()
    poses: list[bytes] = []
    inserted = 0
    if not inside or int(times[inside[0]]) != lo:
        poses.append(_boundary_line(motion, lo, lo - shift, style, eol))
        inserted += 1
    for p in inside:
        t = int(times[p]) - shift
        line = lines.poses[p]
        if shift:
            line = _set_time(line, format_time(t, style).encode("ascii"))
        poses.append(_with_eol(line, eol))
    if not inside or int(times[inside[-1]]) != hi:
        poses.append(_boundary_line(motion, hi, hi - shift, style, eol))
        inserted += 1
    if not lines.final_newline and not lines.suffix:
        poses[-1] = _with_eol(poses[-1], b"")
    out = _Lines(lines.header, poses, lines.suffix, eol, lines.final_newline)
    document = loads(out.to_bytes(), doc.path)
    return Trimmed(document, lo, hi, shift, len(inside), inserted)


# --------------------------------------------------------------------------- scale


@dataclass(frozen=True)
class Clip:
    """The cells of one joint that :func:`scale` clipped to its limits.

    Attributes:
        joint: the joint.
        count: how many cells.
        worst_excess: the largest distance of a scaled value beyond the limit, rad (m).
        unit: ``'rad'`` or ``'m'``.
        at_ms: the pose time of that worst cell, ms.
        bound: the limit it was clipped to, rad (m).
        side: ``'upper'`` or ``'lower'``: which limit ``bound`` is.
    """

    joint: str
    count: int
    worst_excess: float
    unit: str
    at_ms: int
    bound: float
    side: str


@dataclass(frozen=True)
class Scaled:
    """What :func:`scale` did.

    Attributes:
        document: the scaled document.
        amplitude: the factor K.
        about: the reference: ``'first'``, ``'zero'`` or a pose name.
        reference: (J,) the reference value of every column, rad (m); NaN for a column never
            commanded.
        changed: cells whose value changed.
        clips: per joint, the cells clipped to the limits (joints without any: not listed).
        unlimited: columns without limits (not clipped).
    """

    document: MotionDocument
    amplitude: float
    about: str
    reference: tuple[float, ...]
    changed: int
    clips: tuple[Clip, ...]
    unlimited: tuple[str, ...]

    @property
    def clipped(self) -> int:
        """How many cells were clipped, in all."""
        return sum(c.count for c in self.clips)


def _first_commanded(motion: Motion) -> npt.NDArray[np.float64]:
    import numpy as np

    c = motion.commanded
    has = c.any(axis=0)
    idx = np.argmax(c, axis=0)
    out: npt.NDArray[np.float64] = motion.values[idx, np.arange(c.shape[1])].copy()
    out[~has] = np.nan
    return out


def scale(
    doc: MotionDocument,
    amplitude: float,
    *,
    about: str = "first",
    limits: Mapping[str, tuple[float, float, str]] | None = None,
) -> Scaled:
    """Scale every joint's excursion: ``q' = ref + amplitude * (q - ref)``, clipped to limits.

    Args:
        doc: the document (not modified).
        amplitude: the factor K, finite and >= 0 (1 changes nothing, 0 holds the reference).
        about: the reference pose: ``'first'`` (each joint's first commanded value),
            ``'zero'`` (0 rad, the robot's zero pose), or the name of a pose of the file (its
            value; a joint that is ``*`` there uses its first commanded value).
        limits: ``{joint: (lower, upper, unit)}``, rad or m; a scaled value beyond is set to
            the bound and reported in :attr:`Scaled.clips`. Columns not in it are not clipped.

    ``*`` stays ``*``; cells whose value does not change keep their spelling.

    Raises:
        MotionToolError: a bad amplitude, an unknown pose name, a ``nan``/``inf`` command.
    """
    import numpy as np

    if not (math.isfinite(amplitude) and amplitude >= 0):
        raise MotionToolError(f"the amplitude must be a finite number >= 0, got {amplitude}")
    motion = doc.motion
    refuse_non_finite(motion, doc.result, "scaling")
    first = _first_commanded(motion)
    if about == "first":
        ref = first
    elif about == "zero":
        ref = np.zeros(motion.n_joints)
    elif about in motion.pose_names:
        p = motion.pose_names.index(about)
        ref = np.where(motion.commanded[p], motion.values[p], first)
    else:
        shown = ", ".join(f"'{n}'" for n in motion.pose_names[:5])
        more = ", ..." if motion.n_poses > 5 else ""
        raise MotionToolError(
            f"no pose named '{about}' in {doc.path}; give first, zero, or a pose name "
            f"({shown}{more})"
        )
    values = motion.values
    commanded = motion.commanded
    with np.errstate(invalid="ignore"):
        new = ref + amplitude * (values - ref)
    new = np.where(commanded, new, np.nan)
    clips = []
    unlimited = []
    if limits is None:
        limits = {}
    for j, name in enumerate(motion.joints):
        if name not in limits:
            unlimited.append(name)
            continue
        lower, upper, unit = limits[name]
        column = new[:, j]
        with np.errstate(invalid="ignore"):
            excess = np.maximum(column - upper, lower - column)
        out = np.flatnonzero(excess > 0)
        if out.shape[0]:
            worst = int(out[np.argmax(excess[out])])
            bound = upper if column[worst] > upper else lower
            clips.append(
                Clip(
                    name,
                    int(out.shape[0]),
                    float(excess[worst]),
                    unit,
                    int(motion.times_ms[worst]),
                    bound,
                    "upper" if column[worst] > upper else "lower",
                )
            )
            with np.errstate(invalid="ignore"):
                new[:, j] = np.clip(column, lower, upper)
    new = new + 0.0
    changed = commanded & (new != values)
    lines = _Lines.of(doc)
    rows = np.flatnonzero(changed.any(axis=1)).tolist()
    for p in rows:
        line = lines.poses[p]
        tokens = _tokens(line)
        cols = np.flatnonzero(changed[p]).tolist()
        lines.poses[p] = _replace(
            line, {2 + j: _respell(tokens[2 + j], float(new[p, j])) for j in cols}
        )
    document = _repair(loads(lines.to_bytes(), doc.path), new, commanded)
    return Scaled(
        document,
        amplitude,
        about,
        tuple(float(x) for x in ref),
        int(changed.sum()),
        tuple(clips),
        tuple(unlimited),
    )
