"""JSON text of a report, always valid UTF-8, with the file's undecodable bytes made visible.

Names read from a file (joints, poses) and paths from the file system keep bytes that are not
UTF-8 as lone surrogates (Python's ``surrogateescape``), so that a command writing a motion
gives the bytes back unchanged. JSON must be UTF-8 text: here each such byte becomes the four
characters ``\\xNN`` (``b"Head\\xffYaw"`` reads ``"Head\\\\xffYaw"`` in the JSON source), and
the document says how many bytes were escaped in a top-level ``escaped_bytes`` field (present
only when there were any).
"""

from __future__ import annotations

import functools
import json
import math
import re
from collections.abc import Callable, Iterator, Sequence
from typing import Any

__all__ = [
    "ESCAPED_BYTES",
    "HOLE",
    "JsonList",
    "dumps",
    "dumps_around",
    "escape_undecodable",
    "indented",
    "list_pieces",
    "text_after",
]

ESCAPED_BYTES = "escaped_bytes"
"""The top-level field that counts the bytes written as ``\\xNN`` (absent when none were)."""

_SURROGATE = re.compile("[\udc80-\udcff]")
_LONE = re.compile("[\ud800-\udfff]")


def _escape(text: str) -> tuple[str, int]:
    if not _LONE.search(text):
        return text, 0
    count = 0

    def byte(m: re.Match[str]) -> str:
        nonlocal count
        count += 1
        return f"\\x{ord(m.group()) - 0xDC00:02x}"

    text = _SURROGATE.sub(byte, text)
    # Any other lone surrogate cannot come from a byte: replace it (U+FFFD) so the text encodes.
    text, other = _LONE.subn("\ufffd", text)
    return text, count + other


def escape_undecodable(value: Any) -> tuple[Any, int]:
    """``value`` (JSON types) with every undecodable byte in its strings written as ``\\xNN``,
    and how many were."""
    if isinstance(value, str):
        return _escape(value)
    if isinstance(value, dict | list | tuple) and not _LONE.search(
        json.dumps(value, ensure_ascii=False, check_circular=False)
    ):
        return value, 0  # no string to escape: one pass of the C encoder tells (a fix of a
        # million cells is walked in seconds)
    return _escape_walk(value)


def _escape_walk(value: Any) -> tuple[Any, int]:
    """:func:`escape_undecodable`, item by item."""
    if isinstance(value, str):
        return _escape(value)
    if isinstance(value, dict):
        out: dict[str, Any] = {}
        total = 0
        for k, v in value.items():
            key, n = _escape(k) if isinstance(k, str) else (k, 0)
            out[key], m = _escape_walk(v)
            total += n + m
        return out, total
    if isinstance(value, list | tuple):
        items = []
        total = 0
        for v in value:
            item, n = _escape_walk(v)
            items.append(item)
            total += n
        return items, total
    return value, 0


def dumps(
    doc: dict[str, Any],
    *,
    indent: int | None = 2,
    count_field: bool = True,
    allow_nan: bool = True,
) -> str:
    """``doc`` as JSON text (one trailing newline) that always encodes as strict UTF-8.

    With ``count_field``, a document where bytes had to be escaped gets ``escaped_bytes``
    (their number) as its last top-level field. ``allow_nan=False`` raises ``ValueError`` on a
    non-finite float (JSON has none), as :func:`json.dumps` does.
    """
    clean, count = escape_undecodable(doc)
    if count and count_field:
        clean[ESCAPED_BYTES] = count
    return json.dumps(clean, indent=indent, ensure_ascii=False, allow_nan=allow_nan) + "\n"


class _Unusual(Exception):
    """A value :func:`indented` leaves to :func:`json.dumps` (a key that is not a string, a
    type that is not JSON's)."""


_STRING = json.encoder.encode_basestring  # the C function, as json.dumps(ensure_ascii=False)
_CONSTANTS = {True: "true", False: "false"}
_FLOATS = {math.inf: "Infinity", -math.inf: "-Infinity"}


def indented(value: Any) -> str:
    """``json.dumps(value, indent=2, ensure_ascii=False)``, the same text, several times faster
    for the large documents of a report (a fix of a million cells): the standard library
    writes indented JSON in pure Python, a generator per nesting level."""
    out: list[str] = []
    try:
        _put(value, out, "\n")
    except _Unusual:
        return json.dumps(value, indent=2, ensure_ascii=False)
    return "".join(out)


def _put(value: Any, out: list[str], newline: str) -> None:
    """Append ``value``'s indented text to ``out``, ``newline`` the line break and indentation
    of the level it is at."""
    kind = type(value)
    if kind is str:
        out.append(_STRING(value))
    elif kind is int:
        out.append(int.__repr__(value))
    elif kind is float:
        out.append(
            float.__repr__(value) if value == value and value not in _FLOATS else _float(value)
        )
    elif kind is bool:
        out.append(_CONSTANTS[value])
    elif value is None:
        out.append("null")
    elif kind is dict:
        if not value:
            out.append("{}")
            return
        inner = newline + "  "
        if all(type(v) in _FLAT for v in value.values()):  # one call of the C encoder
            text = "".join(_flat_encoder(inner)(value, 0))
            out.append("{" + inner + text[1:-1] + newline + "}")
            return
        separator = "{" + inner
        for key, item in value.items():
            if type(key) is not str:
                raise _Unusual
            out.append(separator + _STRING(key) + ": ")
            _put(item, out, inner)
            separator = "," + inner
        out.append(newline + "}")
    elif kind is list or kind is tuple:
        if not value:
            out.append("[]")
            return
        inner = newline + "  "
        if _flat_dicts(value):  # one call of the C encoder for them all (a fix's edits)
            fields = inner + "  "
            text = "".join(_flat_encoder(fields)(value, 0))[2:-2]  # without '[{' and '}]'
            text = text.replace("}," + fields + "{", inner + "}," + inner + "{" + fields)
            out.append("[" + inner + "{" + fields + text + inner + "}" + newline + "]")
            return
        separator = "[" + inner
        for item in value:
            out.append(separator)
            _put(item, out, inner)
            separator = "," + inner
        out.append(newline + "]")
    else:
        raise _Unusual


_FLAT = frozenset((str, int, float, bool, type(None)))
"""The types of a dict's values that :func:`_flat_encoder` writes as :func:`json.dumps` does."""


@functools.cache
def _flat_encoder(inner: str) -> Callable[[Any, int], Sequence[str]]:
    """The C encoder of the standard library (as :func:`json.dumps` makes it, no circular
    check) that writes a dict of plain values (string keys) with its items separated by
    ``inner`` (a line break and indentation), as they are in an indented document (without
    the breaks after ``{`` and before ``}``)."""
    make = json.encoder.c_make_encoder  # type: ignore[attr-defined]
    if make is None:  # an interpreter without the C accelerator
        encoder = json.JSONEncoder(ensure_ascii=False, separators=("," + inner, ": "))
        return lambda value, _level: [encoder.encode(value)]
    return make(None, None, _STRING, None, ": ", "," + inner, False, False, True)  # type: ignore[no-any-return]


def _flat_dicts(items: list[Any] | tuple[Any, ...]) -> bool:
    """Whether every item is a non-empty dict of plain values: written by the C encoder, such a
    list's only ``},`` followed by a line break are between its items (a string's line break
    is written ``\\n``, and no value ends with ``}``)."""
    return (
        type(items[0]) is dict
        and {type(item) for item in items} == {dict}
        and all(items)
        and {type(v) for item in items for v in item.values()} <= _FLAT
    )


def _float(value: float) -> str:
    """A non-finite float as :func:`json.dumps` writes it (``allow_nan``, the default)."""
    return "NaN" if value != value else _FLOATS[value]


HOLE = "\x00 findings \x00"
"""Where a list written piece by piece goes in a document (:func:`dumps_around`): a report
streams its findings there as they are made, the rest of the document around them."""


def dumps_around(doc: dict[str, Any], level: int) -> tuple[str, str, int]:
    """``doc`` as the JSON text it has at nesting ``level`` of an indented document, cut at
    :data:`HOLE` (the list written piece by piece), and the undecodable bytes it escaped."""
    clean, escaped = escape_undecodable(doc)
    text = json.dumps(clean, indent=2, ensure_ascii=False).replace("\n", "\n" + "  " * level)
    before, after = text.split(json.dumps(HOLE))
    return before, after, escaped


def text_after(
    doc: dict[str, Any], escaped_in_list: int, count_in: dict[str, Any] | None = None
) -> str:
    """The text of ``doc`` after its :data:`HOLE` list, once that list is written (the fields
    after it filled in by now), with one trailing newline. Where bytes were escaped (those
    of the list, ``escaped_in_list``, and those of the rest of ``doc``), their number is
    ``escaped_bytes``, the last field of ``count_in`` (default: ``doc``)."""
    _before, after, escaped = dumps_around(doc, 0)
    if escaped + escaped_in_list:
        (doc if count_in is None else count_in)[ESCAPED_BYTES] = escaped + escaped_in_list
        after = dumps_around(doc, 0)[1]
    return after + "\n"


def list_pieces(texts: Iterator[str], level: int) -> Iterator[str]:
    """The pieces of a JSON list at nesting ``level`` whose items are ``texts`` (each an
    indented document of its own): exactly what :func:`json.dumps` writes for the list."""
    items = JsonList(level)
    for text in texts:
        yield items.item(text)
    yield items.close()


class JsonList:
    """A JSON list at nesting ``level`` written an item at a time, as :func:`list_pieces`
    writes it, for items handed over one by one."""

    def __init__(self, level: int) -> None:
        self.level = level
        self.pad = "\n" + "  " * (level + 1)
        self.first = True

    def item(self, text: str) -> str:
        """The piece for the next item, ``text`` (an indented document of its own)."""
        piece = ("[" if self.first else ",") + self.pad + text.replace("\n", self.pad)
        self.first = False
        return piece

    def close(self) -> str:
        """The end of the list."""
        return "[]" if self.first else "\n" + "  " * self.level + "]"
