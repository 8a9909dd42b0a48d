"""Emulation of the C library calls Webots uses to read ``.motion`` tokens.

Webots' loader (``src/controller/c/motion.c``) reads a value with ``sscanf(token, "%lf", &v)``
and a time with ``sscanf(token, "%d:%d:%d", ...)`` after checking the token's characters. These
functions reproduce glibc's behaviour exactly, including its quirks, so that ``motiontool`` reads
every token to the same double as a Webots controller does:

* ``%lf`` first collects the longest run of characters that *looks like* a number (sign, digits,
  one dot, an exponent mark followed by an optional sign, or a hex float after ``0x``; ``nan``,
  ``inf``, ``infinity`` case-insensitively), then hands that run to ``strtod``. The conversion
  fails only when ``strtod`` takes nothing from it, or when a partial ``nan`` / ``infinity`` was
  read: ``1e+`` reads as 1.0, ``2rad`` as 2.0, ``infinit`` fails, ``0x`` fails.
* ``%d`` goes through ``strtol`` (64-bit, saturating) and is then truncated to a 32-bit ``int``;
  the time arithmetic ``m * 60000 + s * 1000 + ms`` wraps around like the C code does in practice.
"""

from __future__ import annotations

import re
from typing import NamedTuple

from motiontool.motionfmt.units import TIME_FIELD_MS, time_fields_ms

__all__ = ["INT_MAX", "PLAIN_DECIMAL", "ScannedDouble", "ScannedTime", "scan_double", "scan_time"]

INT_MAX = 2**31 - 1
_LONG_MAX = 2**63 - 1
_C_SPACE = b" \t\n\v\f\r"
_DIGITS = frozenset(b"0123456789")
_XDIGITS = frozenset(b"0123456789abcdefABCDEF")
_TIME_CHARS = frozenset(b"0123456789:")

# What glibc's strtod takes from the front of the collected run.
_STRTOD_HEX = re.compile(
    rb"[+-]?0[xX](?:[0-9a-fA-F]+\.?[0-9a-fA-F]*|\.[0-9a-fA-F]+)(?:[pP][+-]?\d+)?"
)
PLAIN_DECIMAL = re.compile(rb"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")
"""A decimal number as strtod reads it (no hex, no white space); a cell that is one and
nothing else reads as ``float(cell)``."""


class ScannedDouble(NamedTuple):
    """A value read by ``sscanf("%lf")``.

    Attributes:
        value: the double Webots stores.
        end: index in the token one past the last byte ``strtod`` converted; bytes from there on
            are ignored by Webots (``2rad`` reads as 2.0 with ``end == 1``).
    """

    value: float
    end: int


class ScannedTime(NamedTuple):
    """A pose time read as Webots reads it.

    Attributes:
        ms: the time Webots uses, in milliseconds (after 32-bit truncation and wrap-around).
        exact_ms: the time the token means, in milliseconds, with unbounded integers.
    """

    ms: int
    exact_ms: int


def _wrap32(x: int) -> int:
    """Two's-complement wrap of an integer to a C ``int``."""
    return (x + 2**31) % 2**32 - 2**31


def _strtod_prefix(run: bytes) -> tuple[float, int] | None:
    """Value and length of the longest prefix of ``run`` that glibc's strtod converts."""
    m = _STRTOD_HEX.match(run)
    if m is not None:
        text = m.group()
        try:
            return float.fromhex(text.decode("ascii")), m.end()
        except OverflowError:
            return (float("-inf") if text.startswith(b"-") else float("inf")), m.end()
    m = PLAIN_DECIMAL.match(run)
    if m is not None:
        return float(m.group()), m.end()
    return None


def _match_word(token: bytes, i: int, word: bytes) -> bool:
    return token[i : i + len(word)].lower() == word


def scan_double(token: bytes) -> ScannedDouble | None:
    """Read ``token`` as glibc's ``sscanf(token, "%lf", &v)`` does.

    Args:
        token: the raw bytes of one comma-separated cell (no ``,``, ``\\r`` or ``\\n`` inside).

    Returns:
        The value and where its text ends, or ``None`` where ``sscanf`` does not return 1
        (Webots then rejects the file).
    """
    if PLAIN_DECIMAL.fullmatch(token) is not None:  # a plain decimal, the whole cell: strtod's
        return ScannedDouble(float(token), len(token))  # conversion, without the walk below
    return _scan_double(token)


def _scan_double(token: bytes) -> ScannedDouble | None:
    """:func:`scan_double` of any token: glibc's vfscanf walk, then strtod."""
    n = len(token)
    i = 0
    while i < n and token[i] in _C_SPACE:
        i += 1
    if i == n:
        return None  # input failure: nothing but white space
    start = i
    if token[i] in b"+-":
        i += 1
        if i == n:
            return None
    if token[i] | 0x20 in (ord("n"), ord("i")):  # ASCII lower case for letters
        return _scan_nan_inf(token, start, i)
    j, hexa = _collect_number(token, i)
    run = token[start:j]
    got_sign = i - start
    if len(run) == got_sign or (hexa and len(run) == 2 + got_sign):
        return None
    converted = _strtod_prefix(run)
    if converted is None:
        return None
    value, length = converted
    return ScannedDouble(value, start + length)


def _scan_nan_inf(token: bytes, start: int, i: int) -> ScannedDouble | None:
    """``nan``, ``inf`` or ``infinity`` (any case) at ``i``, its sign from ``start``; None for a
    partial word, on which glibc fails."""
    if token[i] | 0x20 == ord("n"):
        if not _match_word(token, i, b"nan"):
            return None
        return ScannedDouble(float(token[start : i + 3]), i + 3)
    if not _match_word(token, i, b"inf"):
        return None
    j = i + 3
    if j < len(token) and token[j] | 0x20 == ord("i"):
        if not _match_word(token, j, b"inity"):
            return None  # glibc fails on a partial "infinity"
        j += 5
    return ScannedDouble(float(token[start:j]), j)


def _collect_number(token: bytes, i: int) -> tuple[int, bool]:
    """The numeric state machine of glibc's vfscanf: the end of the run that looks like a
    number from ``i`` (after the sign), and whether it is a hex float; strtod converts it next."""
    n = len(token)
    j = i
    hexa = got_digit = got_e = got_dot = False
    exp_char = ord("e")
    if token[j] == ord("0"):
        j += 1
        if j < n and token[j] in b"xX":
            hexa = True
            exp_char = ord("p")
            j += 1
        else:
            got_digit = True
    while j < n:
        ch = token[j]
        if ch in _DIGITS or (hexa and not got_e and ch in _XDIGITS):
            got_digit = True
        elif got_e and token[j - 1] | 0x20 == exp_char and ch in b"+-":
            pass
        elif got_digit and not got_e and ch | 0x20 == exp_char:
            got_e = got_dot = True
        elif ch == ord(".") and not got_dot:
            got_dot = True
        else:
            break
        j += 1
    return j, hexa


def scan_time(token: bytes) -> ScannedTime | None:
    """Read a pose time token as Webots' ``str_to_time`` does.

    Accepted forms are ``ms``, ``s:ms`` and ``m:s:ms``: digits and colons only, every field
    non-empty, any number of digits per field.

    Returns:
        The time in milliseconds, or ``None`` where Webots rejects the token (also when the
        arithmetic lands on -1, Webots' "undefined time").
    """
    if not token or any(b not in _TIME_CHARS for b in token):
        return None
    fields = token.split(b":")
    if len(fields) > 3 or not all(fields):
        return None
    exact = [int(f) for f in fields]
    ints = [_wrap32(min(v, _LONG_MAX)) for v in exact]
    ints = [0] * (3 - len(ints)) + ints
    minute, second, _ms = TIME_FIELD_MS
    ms = _wrap32(_wrap32(_wrap32(ints[0] * minute) + _wrap32(ints[1] * second)) + ints[2])
    if ms == -1:
        return None
    return ScannedTime(ms, time_fields_ms(exact))
