"""JSON text of a report, always valid UTF-8, with the file's undecodable bytes made visible.

Names read from a file (joints, poses) and paths from the file system keep bytes that are not
UTF-8 as lone surrogates (Python's ``surrogateescape``), so that a command writing a motion
gives the bytes back unchanged. JSON must be UTF-8 text: here each such byte becomes the four
characters ``\\xNN`` (``b"Head\\xffYaw"`` reads ``"Head\\\\xffYaw"`` in the JSON source), and
the document says how many bytes were escaped in a top-level ``escaped_bytes`` field (present
only when there were any).
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from typing import Any

__all__ = [
    "ESCAPED_BYTES",
    "HOLE",
    "dumps",
    "dumps_around",
    "escape_undecodable",
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
    pad = "\n" + "  " * (level + 1)
    first = True
    for text in texts:
        yield ("[" if first else ",") + pad + text.replace("\n", pad)
        first = False
    yield "[]" if first else "\n" + "  " * level + "]"
