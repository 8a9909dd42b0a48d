"""The fast path for a pose line: the common case of a clean line (``time,name,number,...``,
``*`` cells included, no nan/inf or marker, valid increasing time), read with ``bytes.split``
and ``float``, without spans. Anything else goes to the exact path (:mod:`.pose_line`), which
must read the same (``tests/readpaths.py`` compares them)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from motiontool.motionfmt.cscan import INT_MAX
from motiontool.motionfmt.lines import Piece, decode_name
from motiontool.motionfmt.pose_values import NO_VALUE_MARKER
from motiontool.motionfmt.units import TIME_FIELD_MS

if TYPE_CHECKING:
    from motiontool.motionfmt._read_state import ReadState

__all__ = ["read_pose_fast"]

_NAN = float("nan")
_MINUTE, _SECOND, _MS = TIME_FIELD_MS


def read_pose_fast(state: ReadState, piece: Piece, prev_time: int) -> int | None:
    """The common case of a clean line, without spans; ``None`` sends it to the exact path."""
    raw = piece.data
    if raw.endswith(b"\r"):
        raw = raw[:-1]
    if b"\r" in raw or b"\0" in raw:
        return None
    toks = raw.split(b",")
    if len(toks) != state.n_joints + 2 or b"" in toks:
        return None
    values_raw = raw[len(toks[0]) + len(toks[1]) + 2 :]
    if b"_" in values_raw:
        return None  # float() reads '1_0' as 10
    cells = toks[2:]
    stars = b"*" in values_raw  # a cell '*' alone; float() refuses one with more ('* ', '*1')
    t_tok = toks[0]
    if t_tok.isdigit():
        if len(t_tok) > 9:
            return None
        t = int(t_tok)
    else:
        parts = t_tok.split(b":")
        if len(parts) > 3 or not all(p.isdigit() and len(p) < 6 for p in parts):
            return None
        t = int(parts[-1]) + _SECOND * int(parts[-2])
        if len(parts) == 3:
            t += _MINUTE * int(parts[0])
        if t > INT_MAX:
            return None  # Webots' int arithmetic wraps: the exact path wraps it too
    if t <= prev_time:
        return None
    try:
        numbers = list(map(float, [tok for tok in cells if tok != b"*"] if stars else cells))
    except ValueError:
        return None
    if not math.isfinite(sum(numbers)) or NO_VALUE_MARKER in numbers:
        return None
    values = numbers
    if stars:  # no command: NaN, as the exact path reads '*'
        state.star_seen = True
        read = iter(numbers)
        values = [_NAN if tok == b"*" else next(read) for tok in cells]
    res = state.result
    res.times_ms.append(t)
    res.pose_names.append(decode_name(toks[1]))
    state.cells.extend(values)
    state.pose_lines.append(piece.line)
    state.pose_cols0.append(piece.col0)
    return t
