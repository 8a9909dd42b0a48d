"""A plain-loop oracle of Webots' motion loader and player, written from docs/webots-format.md.

It shares no code with ``motiontool.motionfmt``: lines come from an fgets-like loop, tokens from
a strtok-like loop, numbers and times from the C library's own ``sscanf`` (through ctypes), and the
player is a step-by-step loop over the rules of that page.
"""

from __future__ import annotations

import ctypes
import ctypes.util
from dataclasses import dataclass, field

_libc = ctypes.CDLL(ctypes.util.find_library("c"))
_libc.sscanf.restype = ctypes.c_int
UNDEFINED = -9999999.9


def c_scan_double(token: bytes) -> float | None:
    value = ctypes.c_double()
    n = _libc.sscanf(ctypes.c_char_p(token), b"%lf", ctypes.byref(value))
    return value.value if n == 1 else None


def c_scan_time(token: bytes) -> int | None:
    if any(c not in b"0123456789:" for c in token):
        return None
    k = token.count(b":")
    v = [ctypes.c_int(0), ctypes.c_int(0), ctypes.c_int(0)]
    if k == 0:
        r = _libc.sscanf(ctypes.c_char_p(token), b"%d", ctypes.byref(v[2]))
    elif k == 1:
        r = _libc.sscanf(ctypes.c_char_p(token), b"%d:%d", ctypes.byref(v[1]), ctypes.byref(v[2]))
    elif k == 2:
        r = _libc.sscanf(ctypes.c_char_p(token), b"%d:%d:%d", *(ctypes.byref(x) for x in v))
    else:
        return None
    if r != k + 1:
        return None
    total = ctypes.c_int(v[0].value * 60000 + v[1].value * 1000 + v[2].value).value
    return None if total == -1 else total


def fgets_lines(data: bytes) -> list[tuple[int, bytes]]:
    """(physical line number, piece) for every fgets(buf, 4096) call that returns data."""
    out = []
    pos = 0
    line = 1
    while pos < len(data):
        end = data.find(b"\n", pos)
        stop = len(data) if end < 0 else end + 1
        piece = data[pos : min(stop, pos + 4095)]
        out.append((line, piece))
        pos += len(piece)
        if piece.endswith(b"\n"):
            line += 1
    return out


def strtok(piece: bytes) -> list[bytes]:
    piece = piece.split(b"\0")[0]
    tokens, current = [], b""
    for i in range(len(piece)):
        ch = piece[i : i + 1]
        if ch in (b",", b"\n", b"\r"):
            if current:
                tokens.append(current)
            current = b""
        else:
            current += ch
    if current:
        tokens.append(current)
    return tokens


@dataclass
class Loaded:
    ok: bool
    stop_line: int | None = None  # physical line where the loader gives up
    joints: list[bytes] = field(default_factory=list)
    times: list[int] = field(default_factory=list)
    values: list[list[float]] = field(default_factory=list)


def webots_load(data: bytes) -> Loaded:
    lines = fgets_lines(data)
    if not lines:
        return Loaded(False, 1)
    header_line, header = lines[0]
    tokens = strtok(header)
    if len(tokens) < 2 or tokens[0] != b"#WEBOTS_MOTION" or tokens[1] != b"V1.0":
        return Loaded(False, header_line)
    joints = tokens[2:]
    result = Loaded(True, None, joints)
    prev = -1
    for line_no, piece in lines[1:]:
        tokens = strtok(piece)
        if not tokens:
            break
        t = c_scan_time(tokens[0])
        if t is None or t <= prev or len(tokens) < 2:
            return Loaded(False, line_no)
        prev = t
        row = []
        for j in range(len(joints)):
            if 2 + j >= len(tokens):
                return Loaded(False, line_no)
            tok = tokens[2 + j]
            if tok == b"*":
                row.append(UNDEFINED)
                continue
            v = c_scan_double(tok)
            if v is None:
                return Loaded(False, line_no)
            row.append(v)
        if len(tokens) > 2 + len(joints):
            return Loaded(False, line_no)
        result.times.append(t)
        result.values.append(row)
    if not joints or not result.times:
        return Loaded(False, None)
    return result


def webots_play(
    times: list[int], values: list[list[float]], timestep: int, max_rows: int | None = None
) -> list[tuple[int, list[float | None]]]:
    """(elapsed, targets) per step; None where no command is sent. ``elapsed`` is a C int:
    ``elapsed += timestep`` wraps past 2**31 - 1 (a motion may then never stop: ``max_rows``
    stops the loop after that many rows)."""
    rows = []
    elapsed = 0
    duration = times[-1]
    last = len(times) - 1
    while True:
        targets: list[float | None] = []
        for j in range(len(values[0])):
            if elapsed <= times[0]:
                pos = values[0][j]
            elif elapsed >= times[last]:
                pos = values[last][j]
            else:
                pos = UNDEFINED
                for a in range(last):
                    b = a + 1
                    if times[a] <= elapsed <= times[b]:
                        if values[a][j] == UNDEFINED or values[b][j] == UNDEFINED:
                            pos = UNDEFINED
                        else:
                            pos = values[a][j] + float(elapsed - times[a]) * (
                                values[b][j] - values[a][j]
                            ) / float(times[b] - times[a])
                        break
            targets.append(None if pos == UNDEFINED else pos)
        rows.append((elapsed, targets))
        if elapsed >= duration or len(rows) == max_rows:
            break
        elapsed = ctypes.c_int(elapsed + timestep).value  # int arithmetic: wraps
    return rows
