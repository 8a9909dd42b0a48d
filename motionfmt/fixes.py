"""Fixes for what ``validate`` reports: byte edits of a ``.motion`` file, safe or not.

A **safe** fix leaves what Webots does exactly as it was: the same verdict and the same command
stream, bit for bit, at every controller time step. Each safe fix is checked after it is
applied (:func:`fix_bytes` compares the motions before and after, and refuses a result that
differs), not only argued:

- MT203 ``2rad`` -> ``2``: the ignored characters after the number go;
- MT204 ``-9999999.9`` -> ``*``: Webots reads its marker as no command;
- MT205 a joint named twice: the two columns become one, as Webots merges them (the later
  column's cell where it sends a command, else the earlier one's); applied only where the
  merged stream is proved equal at every millisecond.

An **unsafe** fix changes what the robot does, to what the author evidently meant:

- MT201 a blank line that ends the motion early goes (the poses after it play);
- MT202 an empty cell ``,,`` becomes ``,*,`` (no command, instead of the next values shifting
  one joint left);
- with a robot (:data:`ROBOT_CODES`, planned by :mod:`motiontool.kinematics.robot_fixes` and
  given to :func:`fix_bytes` as a :data:`RobotPlanner`): MT302 a value past its joint's limit
  becomes the limit (where the motor stops anyway), MT303 the segments too fast for a joint's
  maxVelocity are stretched, as ``retime`` fits a motion to its robot's limits.

Edits are on physical lines (``line``, 1-based; ``column`` .. ``end_column``, 1-based byte
columns, end exclusive), so a fix never touches a byte outside its span.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import NamedTuple, Protocol

from motiontool.motionfmt.diagnostics import (
    BEYOND_LIMITS,
    BLANK_LINE_ENDS,
    CODES,
    CUT_LINE,
    EMPTY_CELL,
    JOINT_TWICE,
    NO_VALUE_CELL,
    NUL_BYTE,
    TOO_FAST,
    TRAILING_CHARACTERS,
    Diagnostic,
    FixKind,
)
from motiontool.motionfmt.reader import ReadResult, read_bytes, token_spans

__all__ = [
    "ROBOT_CODES",
    "SAFE_CODES",
    "UNSAFE_CODES",
    "Fix",
    "FixResult",
    "RobotPlanner",
    "finding_fixes",
    "fix_bytes",
    "fixable",
    "merge_fixes",
    "plan_fixes",
    "proved",
    "same_stream",
]


def _fixed(kind: FixKind) -> frozenset[str]:
    return frozenset(c.id for c in CODES.values() if c.fix is kind)


SAFE_CODES = _fixed(FixKind.SAFE)
"""Codes a safe fix covers (the command stream stays bit-identical): their records say so."""
UNSAFE_CODES = _fixed(FixKind.UNSAFE)
"""Codes an unsafe fix covers (what the robot does changes, to what was evidently meant)."""
ROBOT_CODES = _fixed(FixKind.ROBOT)
"""Codes whose (unsafe) fix needs the robot's limits: a :data:`RobotPlanner` plans it."""


class RobotPlanner(Protocol):
    """Plans the fixes of :data:`ROBOT_CODES` (the caller knows the robot)."""

    @property
    def titles(self) -> Mapping[str, str]:
        """What the fix of each code it plans does, for people (a report that names a
        finding's fix without planning it)."""
        ...

    def __call__(self, data: bytes) -> list[Fix]:
        """Every robot fix of a file's bytes (what ``--fix --unsafe-fixes`` applies)."""
        ...

    def clamps(
        self, result: ReadResult, joint: str, lines: tuple[int, int], past: float | None
    ) -> list[Fix]:
        """The MT302 clamps of ``joint``'s cells on lines ``lines`` (first, last) of the file
        read as ``result`` past the same limit as the value ``past`` (None: either): one finding's
        fix, planned for it alone (a report of millions of findings never holds them all);
        none if MT302 is not planned."""
        ...

    def clamp_count(
        self, result: ReadResult, joint: str, lines: tuple[int, int], past: float | None
    ) -> int:
        """How many edits :meth:`clamps` makes, without making them (a report that only counts
        a fix of thousands of cells)."""
        ...

    def stretch(self, data: bytes, result: ReadResult) -> list[Fix]:
        """The MT303 retiming of the file (``data``, read as ``result``); none if MT303 is not
        planned."""
        ...


_MERGE_PROOF_CELLS = 20_000_000
"""Largest (milliseconds x joints) for which a column merge (MT205) is proved equal at every
millisecond; a longer file keeps its duplicate column."""


class Fix(NamedTuple):
    """One edit: on physical line ``line``, bytes ``column`` .. ``end_column`` (1-based, end
    exclusive) become ``replacement``; ``end_column`` None means to the end of the line, and a
    ``replacement`` of None deletes the whole line.

    Attributes:
        code: the diagnostic it fixes.
        safe: True when Webots' command stream stays bit-identical.
        title: what it does, for people (``write '2'``).
        joint: the joint (column) it edits, where it edits one joint's cell.
    """

    code: str
    line: int
    column: int
    end_column: int | None
    replacement: bytes | None
    safe: bool
    title: str
    joint: str | None = None


def fixable(d: Diagnostic, *, unsafe: bool = False) -> bool:
    """Whether a fix exists for diagnostic ``d`` (an unsafe one only with ``unsafe``)."""
    return d.code in SAFE_CODES or (unsafe and d.code in UNSAFE_CODES)


def _cell_fixes(d: Diagnostic, lines: Sequence[bytes]) -> list[Fix]:
    end = d.end_column
    if d.code == TRAILING_CHARACTERS and end is not None:
        kept = lines[d.line - 1][: d.column - 1].rsplit(b",", 1)[-1].strip()
        text = kept.decode("utf-8", "replace")
        return [Fix(TRAILING_CHARACTERS, d.line, d.column, end, b"", True, f"write '{text}'")]
    if d.code == NO_VALUE_CELL and end is not None:
        return [Fix(NO_VALUE_CELL, d.line, d.column, end, b"*", True, "write '*' (no command)")]
    if d.code == EMPTY_CELL:
        return [Fix(EMPTY_CELL, d.line, d.column, d.column, b"*", False, "write '*' in the cell")]
    if d.code == BLANK_LINE_ENDS and d.column == 1 and not lines[d.line - 1].strip():
        return [Fix(BLANK_LINE_ENDS, d.line, 1, None, None, False, "remove the blank line")]
    return []


def plan_fixes(
    data: bytes,
    path: str = "<string>",
    *,
    unsafe: bool = False,
    result: ReadResult | None = None,
) -> list[Fix]:
    """The fixes for the findings in ``data`` (safe ones; unsafe ones too with ``unsafe``),
    in file order. A file Webots rejects gets none, but for an empty cell (``,,``) that may be
    why it is rejected, with ``unsafe``: no fix is made over a syntax error it does not cover."""
    result = result if result is not None else read_bytes(data, path)
    lines = data.split(b"\n")
    fixes: list[Fix] = []
    codes: set[str] = set()
    for d in result.diagnostics:  # one pass (a file's findings may be read back from disk)
        codes.add(d.code)
        fixes.extend(finding_fixes(d, result, lines, unsafe=unsafe))
    if JOINT_TWICE in codes and result.accepted:
        fixes.extend(merge_fixes(result, lines, codes))
    return sorted(fixes, key=lambda f: (f.line, f.column))


def finding_fixes(
    d: Diagnostic, result: ReadResult, lines: Sequence[bytes], *, unsafe: bool = False
) -> list[Fix]:
    """The fixes of one of ``result``'s findings, ``d`` (the file's ``lines``), but a duplicated
    joint's merge (MT205, :func:`merge_fixes`: one edit of the whole file fixes them all): safe
    ones, unsafe ones too with ``unsafe``. A file Webots rejects gets none, but for an empty
    cell (``,,``) that may be why it is rejected, with ``unsafe``: no fix is made over a
    syntax error it does not cover."""
    if not result.accepted:
        return _cell_fixes(d, lines) if unsafe and d.code == EMPTY_CELL else []
    return _cell_fixes(d, lines) if fixable(d, unsafe=unsafe) else []


def merge_fixes(result: ReadResult, lines: Sequence[bytes], codes: set[str]) -> list[Fix]:
    """MT205: one column per joint, each pose's cell as Webots' merge leaves it; none where a
    pose line is not plain (an empty cell, a cut line: ``codes``, those of the file's findings)
    or the proof would be too long."""
    if codes & {EMPTY_CELL, CUT_LINE, NUL_BYTE}:
        return []
    joints = list(result.joints)
    n = len(result.times_ms)
    if not n or (result.times_ms[-1] + 1) * len(joints) > _MERGE_PROOF_CELLS:
        return []
    keep: dict[str, int] = {}
    drop: dict[int, int] = {}  # later column -> the column it merges into
    for j, name in enumerate(joints):
        if name in keep:
            drop[j] = keep[name]
        else:
            keep[name] = j
    commanded = result.motion.commanded
    header = _remove_cells(lines[0], [j + 2 for j in drop])  # + 2: the two header tokens
    fixes = [Fix(JOINT_TWICE, 1, 1, None, header, True, "merge the columns of a joint named twice")]
    for k in range(n):
        row = lines[k + 1]
        spans = token_spans(row.rstrip(b"\r"))
        if len(spans) != len(joints) + 2:
            return []
        cells = [row[a:b] for a, b in spans]
        for later, earlier in drop.items():
            if commanded[k, later]:
                cells[earlier + 2] = cells[later + 2]
        merged = _remove_cells(_with_cells(row, spans, cells), [j + 2 for j in drop])
        fixes.append(Fix(JOINT_TWICE, k + 2, 1, None, merged, True, "merge the columns"))
    return fixes


def _with_cells(row: bytes, spans: list[tuple[int, int]], cells: list[bytes]) -> bytes:
    out = bytearray()
    at = 0
    for (a, b), cell in zip(spans, cells, strict=True):
        out += row[at:a] + cell
        at = b
    return bytes(out + row[at:])


def _remove_cells(row: bytes, indexes: Iterable[int]) -> bytes:
    """``row`` without the tokens at ``indexes`` and the comma before each (and without its
    ``\r``: :func:`_edit` keeps the line's own end)."""
    body = row.rstrip(b"\r")
    spans = token_spans(body)
    gone = set(indexes)
    out = bytearray()
    at = 0
    for i, (a, b) in enumerate(spans):
        if i in gone:
            start = body.rfind(b",", 0, a)
            out += body[at:start]
            at = b
    return bytes(out + body[at:])


class FixResult(NamedTuple):
    """What :func:`apply_fixes` did.

    Attributes:
        data: the fixed bytes.
        applied: the fixes applied, in file order.
        refused: fixes left out because the proof failed (a safe fix that would change the
            command stream; none is expected: a test runs every safe fix over the corpus).
    """

    data: bytes
    applied: tuple[Fix, ...]
    refused: tuple[Fix, ...]


def _edit(lines: list[bytes | None], fix: Fix) -> None:
    i = fix.line - 1
    line = lines[i]
    if line is None:
        return
    if fix.replacement is None:  # the whole line goes
        lines[i] = None
        return
    body = line.rstrip(b"\r")
    if fix.end_column is None:  # the line from ``column`` on, its CR kept
        lines[i] = line[: fix.column - 1] + fix.replacement + line[len(body) :]
        return
    lines[i] = line[: fix.column - 1] + fix.replacement + line[fix.end_column - 1 :]


def _apply(data: bytes, fixes: Sequence[Fix]) -> bytes:
    lines: list[bytes | None] = list(data.split(b"\n"))
    # Right to left on a line, so that earlier columns stay where they are.
    for fix in sorted(fixes, key=lambda f: (f.line, -f.column)):
        _edit(lines, fix)
    return b"\n".join(line for line in lines if line is not None)


_ROUNDS = (
    (TRAILING_CHARACTERS, NO_VALUE_CELL),
    (JOINT_TWICE,),
    (EMPTY_CELL,),
    (BLANK_LINE_ENDS,),
)
"""Fixes are applied a group of codes at a time, each group planned on the bytes the previous
one left (a merge rewrites whole lines; a removed line moves the ones after it)."""
_ROBOT_ROUNDS = ((BEYOND_LIMITS,), (TOO_FAST,))
"""The robot's rounds, last: on the file as Webots then reads it (values, then times)."""


def _disjoint(fixes: Sequence[Fix]) -> list[Fix]:
    """The fixes whose spans do not overlap an earlier one's on the same line (the others are
    planned again in the next round)."""
    kept: list[Fix] = []
    for f in sorted(fixes, key=lambda f: (f.line, f.column)):
        last = kept[-1] if kept else None
        whole = f.end_column is None or f.replacement is None
        if last is not None and last.line == f.line:
            last_whole = last.end_column is None or last.replacement is None
            if whole or last_whole or f.column < (last.end_column or 0):
                continue
        kept.append(f)
    return kept


def fix_bytes(
    data: bytes,
    path: str = "<string>",
    *,
    unsafe: bool = False,
    robot: RobotPlanner | None = None,
    select: Callable[[str], bool] | None = None,
) -> FixResult:
    """``data`` with every fix applied (the unsafe ones too with ``unsafe``, and with a
    ``robot`` planner those of :data:`ROBOT_CODES`; only those of the codes ``select`` keeps,
    where given), round after round until none is left; each round of safe fixes is proved
    to play exactly as before (:func:`same_stream`) and refused otherwise; unsafe ones must
    leave a file Webots loads."""
    current = data
    applied: list[Fix] = []
    refused: list[Fix] = []
    rounds = _ROUNDS + (_ROBOT_ROUNDS if unsafe and robot is not None else ())
    for _ in range(8):
        progressed = False
        for codes in rounds:
            planned = (
                robot(current)
                if robot is not None and codes[0] in ROBOT_CODES
                else plan_fixes(current, path, unsafe=unsafe)
            )
            fixes = [f for f in planned if f.code in codes and (select is None or select(f.code))]
            fixes = [f for f in _disjoint(fixes) if (f.code, f.line) not in _keys(refused)]
            if not fixes:
                continue
            candidate = _apply(current, fixes)
            if fixes[0].safe:
                ok = same_stream(current, candidate, path)
            else:
                ok = read_bytes(candidate, path).accepted
            if ok and candidate != current:
                current, progressed = candidate, True
                applied += fixes
            else:
                refused += fixes
        if not progressed:
            break
    return FixResult(current, tuple(applied), tuple(refused))


def proved(data: bytes, fixes: Sequence[Fix], path: str = "<string>") -> bool:
    """Whether ``data`` with ``fixes`` applied plays exactly as ``data`` (:func:`same_stream`):
    the proof :func:`fix_bytes` asks of a round of safe fixes before it applies them."""
    return same_stream(data, _apply(data, fixes), path)


def _keys(fixes: Sequence[Fix]) -> set[tuple[str, int]]:
    return {(f.code, f.line) for f in fixes}


def same_stream(before: bytes, after: bytes, path: str = "<string>") -> bool:
    """Whether ``after`` plays exactly as ``before`` in Webots: both rejected, or the same
    pose times and, for every motor, the same command (bit for bit) at every millisecond."""
    import numpy as np

    from motiontool.motionfmt.player import commands_at, hold_targets

    a, b = read_bytes(before, path), read_bytes(after, path)
    if a.accepted != b.accepted:
        return False
    if not a.accepted:
        return before == after
    ma, mb = a.motion, b.motion
    if not np.array_equal(ma.times_ms, mb.times_ms):
        return False
    names = list(dict.fromkeys(ma.joints))
    if list(dict.fromkeys(mb.joints)) != names:
        return False
    if ma.joints == mb.joints:  # no merge: the cells themselves, bit for bit where sent
        if not np.array_equal(ma.commanded, mb.commanded):
            return False
        sent = ma.commanded
        va, vb = ma.values.view(np.int64), mb.values.view(np.int64)
        return bool(np.array_equal(va[sent], vb[sent]))
    elapsed = np.arange(int(ma.times_ms[-1]) + 1, dtype=np.int64)
    held = []
    for m in (ma, mb):
        targets, sent = commands_at(m, elapsed)
        merged = hold_targets(targets, sent, m.joints, names)
        held.append((merged.targets.view(np.int64), merged.sent))
    return bool(np.array_equal(held[0][0], held[1][0]) and np.array_equal(held[0][1], held[1][1]))
