"""Webots' text world and PROTO syntax (``.wbt``, ``.proto``): tokens, nodes, fields, PROTO
interfaces. Pure Python; what a world means for a run is :mod:`motiontool.sim.world`.

The grammar read (Webots' VRML97 dialect): a ``#VRML_SIM R2023b utf8`` header, ``EXTERNPROTO
"url"`` lines (``IMPORTABLE EXTERNPROTO`` too), then nodes ``Type { field value ... }``, each
maybe named ``DEF name`` and used again as ``USE name``; ``NULL``. A value is a run of numbers
(``SFFloat``, ``SFVec3f``, ``SFRotation``...: a tuple of floats), a string, ``TRUE`` /
``FALSE``, a node, ``IS field`` (inside a PROTO body) or an ``[ ... ]`` list of those (MF
fields). Commas are white space and ``#`` starts a comment, as in VRML. A ``.proto`` file holds
``PROTO Name [ field TYPE name default ... ] { body }``; a body with template code
(``%< ... >%``, ``%{ ... }%``) is not read (its interface is), only the type of its first node.

Errors are :class:`~motiontool.errors.MotionSyntaxError`: ``world.wbt:12:3: message``.
"""

from __future__ import annotations

import bisect
import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import NamedTuple, TypeAlias

from motiontool.errors import MotionSyntaxError

__all__ = [
    "IsRef",
    "Node",
    "Proto",
    "Value",
    "WbtFile",
    "describe",
    "parse_wbt",
]

HEADER = "#VRML_SIM"
"""How a Webots world or PROTO file starts (``#VRML_SIM R2023b utf8``)."""

FIELD_KEYWORDS = ("field", "vrmlField", "hiddenField", "deprecatedField", "unconnectedField")
"""The words that declare a field of a PROTO interface."""


@dataclass(frozen=True)
class IsRef:
    """``IS name`` in a PROTO body: the value of the instance's field ``name``."""

    name: str


@dataclass
class Node:
    """A node: its type, its fields as written (in file order), where it starts.

    Attributes:
        type: the node type (``WorldInfo``, ``Solid``, ``Nao``).
        fields: field name -> value.
        line, column: where the type name is, 1-based.
        def_name: the ``DEF`` name, or None.
    """

    type: str
    fields: dict[str, Value]
    line: int
    column: int
    def_name: str | None = None


Value: TypeAlias = tuple[float, ...] | str | bool | Node | IsRef | list["Value"] | None
"""A field value: numbers, a string, a boolean, a node, ``IS``, NULL, or a list (MF)."""


@dataclass
class Proto:
    """A PROTO: its interface (field name -> default value) and the first node of its body.

    Attributes:
        name: the PROTO's name.
        defaults: the interface's fields and their default values.
        body: the first node of the body, or None when the body holds template code.
        base_type: the type of the body's first node (``Robot``, ``Solid``), template or not.
        line, column: where ``PROTO`` is.
    """

    name: str
    defaults: dict[str, Value]
    body: Node | None
    base_type: str | None
    line: int
    column: int


@dataclass
class WbtFile:
    """What a world or PROTO file holds.

    Attributes:
        path: the file, as named in messages.
        version: the header's version (``R2023b``).
        externprotos: each ``EXTERNPROTO`` URL with its line and column.
        nodes: the top-level nodes, in file order.
        protos: the PROTOs the file defines.
    """

    path: str
    version: str
    externprotos: list[tuple[str, int, int]] = field(default_factory=list)
    nodes: list[Node] = field(default_factory=list)
    protos: list[Proto] = field(default_factory=list)


_TOKEN = re.compile(
    r"""[ \t\r\n,]*(?:
        (?P<comment>\#[^\n]*)
      | (?P<template>%<.*?>%|%\{.*?\}%)
      | (?P<string>"(?:[^"\\\n]|\\.)*")
      | (?P<number>[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?(?![A-Za-z_]))
      | (?P<punct>[\[\]{}])
      | (?P<word>[^\s\[\]{}",#%]+|%(?![<{])[^\s\[\]{}",#]*)
      | (?P<bad>.|$))""",
    re.VERBOSE | re.DOTALL,
)
"""One token after white space (commas are white space); a template (JavaScript ``%< >%``, Lua
``%{ }%``) is one token; ``bad``: anything else, or the end of the text."""


class _Tok(NamedTuple):
    kind: str  # string, number, punct, word, template, eof
    text: str
    line: int
    column: int
    offset: int  # in the text


def _tokens(text: str, path: str) -> Iterator[_Tok]:
    """The tokens of ``text`` (comments and white space dropped), read as they are asked for."""
    newlines = [i for i, c in enumerate(text) if c == "\n"]
    for match in _TOKEN.finditer(text):
        kind = match.lastgroup or "bad"
        start = match.start(kind) if match.lastgroup else match.end()
        if kind == "comment":
            continue
        line = bisect.bisect_left(newlines, start) + 1
        column = start - (newlines[line - 2] + 1 if line > 1 else 0) + 1
        if kind == "bad":
            what = text[start : start + 2]
            if start >= len(text):
                yield _Tok("eof", "", line, column, start)
                return
            if what[:1] == '"':
                raise MotionSyntaxError("string not closed on its line", path, line, column)
            if what in ("%<", "%{"):
                closer = ">%" if what == "%<" else "}%"
                raise MotionSyntaxError(
                    f"template code '{what}' is not closed by '{closer}' before the end of the"
                    " file",
                    path,
                    line,
                    column,
                )
            raise MotionSyntaxError(f"unexpected character {what[:1]!r}", path, line, column)
        yield _Tok(kind, match.group(kind), line, column, start)
    raise AssertionError("the token pattern ends at the end of the text")  # pragma: no cover


class _Parser:
    """A recursive-descent reader over the tokens of one file."""

    def __init__(self, text: str, path: str) -> None:
        self.path = path
        self.header = text.split("\n", 1)[0].lstrip("\ufeff")
        self.text = text
        self.stream = _tokens(text, path)
        self.toks: list[_Tok] = []
        self.pos = 0
        self.done = False  # a PROTO body with template code ends what is read
        self.defs: dict[str, Node] = {}
        self.open: list[_Tok] = []  # the brackets open, for the message at a truncated end

    def peek(self) -> _Tok:
        while self.pos >= len(self.toks):
            self.toks.append(next(self.stream))
        return self.toks[self.pos]

    def take(self) -> _Tok:
        tok = self.peek()
        if tok.kind == "eof":
            raise self.truncated()
        self.pos += 1
        return tok

    def truncated(self) -> MotionSyntaxError:
        tok = self.toks[-1]
        if self.open:
            opener = self.open[-1]
            what = f"'{opener.text}' opened at {opener.line}:{opener.column} is not closed"
        else:
            what = "a value is missing"
        return MotionSyntaxError(f"unexpected end of file: {what}", self.path, tok.line, tok.column)

    def error(self, tok: _Tok, message: str) -> MotionSyntaxError:
        return MotionSyntaxError(message, self.path, tok.line, tok.column)

    def expect(self, text: str, after: str) -> _Tok:
        tok = self.take()
        if tok.text != text or tok.kind not in ("punct", "word"):
            raise self.error(tok, f"expected '{text}' {after}, got {_show(tok)}")
        return tok

    def word(self, what: str) -> _Tok:
        tok = self.take()
        if tok.kind != "word":
            raise self.error(tok, f"expected {what}, got {_show(tok)}")
        return tok

    # -- the file

    def file(self) -> WbtFile:
        out = WbtFile(self.path, self.version())
        while not self.done and self.peek().kind != "eof":
            tok = self.peek()
            if tok.kind == "word" and tok.text == "IMPORTABLE":
                self.take()
                tok = self.peek()
            if tok.kind == "word" and tok.text == "EXTERNPROTO":
                self.take()
                url = self.take()
                if url.kind != "string":
                    raise self.error(url, f"expected the PROTO's URL in quotes, got {_show(url)}")
                out.externprotos.append((_unquote(url.text), url.line, url.column))
            elif tok.kind == "word" and tok.text == "PROTO":
                out.protos.append(self.proto())
            else:
                node = self.node()
                if not isinstance(node, Node):
                    raise self.error(tok, f"expected a node, got {_show(tok)}")
                out.nodes.append(node)
        return out

    def version(self) -> str:
        """The version of the ``#VRML_SIM`` header (a comment to the tokenizer)."""
        head = self.header
        if not head.startswith(HEADER):
            raise MotionSyntaxError(
                f"not a Webots world or PROTO file: it must start with '{HEADER} <version> utf8'",
                self.path,
                1,
                1,
            )
        parts = head.split()
        return parts[1] if len(parts) > 1 else ""

    def proto(self) -> Proto:
        start = self.take()  # PROTO
        name = self.word("the PROTO's name")
        self.open.append(self.expect("[", f"after PROTO {name.text}"))
        defaults: dict[str, Value] = {}
        while self.peek().text != "]" or self.peek().kind != "punct":
            keyword = self.word("'field' or ']'")
            if keyword.text not in FIELD_KEYWORDS:
                raise self.error(keyword, f"expected 'field' or ']', got {_show(keyword)}")
            self.word("a field type")
            if self.peek().text == "{" and self.peek().kind == "punct":
                self.skip_group()  # the field's allowed values
            fname = self.word("a field name")
            defaults[fname.text] = self.value(fname)
        self.take()
        self.open.pop()
        opener = self.expect("{", f"after the interface of PROTO {name.text}")
        self.open.append(opener)
        rest = self.text[opener.offset + 1 :]
        if "%<" in rest or "%{" in rest:  # template code: the body is not read (nor tokenized)
            self.done = True
            while self.peek().kind == "template":
                self.take()
            base = self.peek().text if self.peek().kind == "word" else None
            return Proto(name.text, defaults, None, base, start.line, start.column)
        body_start = self.pos
        depth = 1
        while depth:
            tok = self.take()
            if tok.kind == "punct" and tok.text in "{[":
                depth += 1
            elif tok.kind == "punct" and tok.text in "}]":
                depth -= 1
        self.open.pop()
        body_end = self.pos - 1
        base = next(
            (t.text for t in self.toks[body_start:body_end] if t.kind == "word"),
            None,
        )
        body = None
        if body_start < body_end:
            inner = _Parser.__new__(_Parser)
            inner.path, inner.header, inner.defs, inner.open = self.path, "", {}, [opener]
            close = self.toks[body_end]  # the body's '}': the end of what the inner parser reads
            inner.toks = [*self.toks[body_start:body_end], close._replace(kind="eof", text="")]
            inner.pos, inner.done, inner.stream = 0, False, iter(())
            found = inner.node()
            body = found if isinstance(found, Node) else None
        return Proto(name.text, defaults, body, base, start.line, start.column)

    def skip_group(self) -> None:
        """Skip a ``{ ... }`` (a field's allowed values)."""
        self.open.append(self.take())
        depth = 1
        while depth:
            tok = self.take()
            if tok.kind == "punct" and tok.text == "{":
                depth += 1
            elif tok.kind == "punct" and tok.text == "}":
                depth -= 1
        self.open.pop()

    # -- nodes and values

    def node(self) -> Node | None:
        tok = self.take()
        if tok.kind != "word":
            raise self.error(tok, f"expected a node, got {_show(tok)}")
        if tok.text == "NULL":
            return None
        if tok.text == "USE":
            name = self.word("a DEF name after USE")
            if name.text not in self.defs:
                raise self.error(name, f"USE {name.text}: no node was named DEF {name.text} before")
            return self.defs[name.text]
        def_name = None
        if tok.text == "DEF":
            def_name = self.word("a name after DEF").text
            tok = self.word("a node type after DEF " + def_name)
        if not (tok.text[:1].isalpha() or tok.text[:1] == "_"):
            raise self.error(tok, f"expected a node type, got {_show(tok)}")
        opener = self.expect("{", f"after node type '{tok.text}'")
        self.open.append(opener)
        fields: dict[str, Value] = {}
        while not (self.peek().kind == "punct" and self.peek().text == "}"):
            name = self.peek()
            if name.kind == "template":
                self.take()  # template code between fields
                continue
            if name.kind != "word" or not (name.text[:1].isalpha() or name.text[:1] == "_"):
                self.take()
                raise self.error(
                    name, f"expected a field name or '}}' in {tok.text}, got {_show(name)}"
                )
            self.take()
            fields[name.text] = self.value(name)
        self.take()
        self.open.pop()
        node = Node(tok.text, fields, tok.line, tok.column, def_name)
        if def_name is not None:
            self.defs[def_name] = node
        return node

    def value(self, owner: _Tok) -> Value:
        tok = self.peek()
        if tok.kind == "eof":
            raise self.truncated()
        if tok.kind == "number":
            numbers = []
            while self.peek().kind == "number":
                numbers.append(float(self.take().text))
            return tuple(numbers)
        if tok.kind == "string":
            return _unquote(self.take().text)
        if tok.kind == "template":
            self.take()
            return None
        if tok.kind == "punct" and tok.text == "[":
            self.open.append(self.take())
            items: list[Value] = []
            while not (self.peek().kind == "punct" and self.peek().text == "]"):
                item = self.value(owner)
                if isinstance(item, tuple):
                    items.extend((v,) for v in item)
                else:
                    items.append(item)
            self.take()
            self.open.pop()
            return items
        if tok.kind == "word":
            if tok.text in ("TRUE", "FALSE"):
                self.take()
                return tok.text == "TRUE"
            if tok.text == "IS":
                self.take()
                return IsRef(self.word("a field name after IS").text)
            return self.node()
        self.take()
        raise self.error(tok, f"expected a value for field '{owner.text}', got {_show(tok)}")


def parse_wbt(text: str, path: str = "<string>") -> WbtFile:
    """The nodes, EXTERNPROTOs and PROTOs of a world or PROTO file's ``text``.

    Raises:
        MotionSyntaxError: not a Webots file, or a syntax error (``path:line:col: message``).
    """
    try:
        return _Parser(text, path).file()
    except RecursionError:  # the parser descends once per level of nested nodes
        raise MotionSyntaxError("nodes nested too deeply to read", path, 1, 1) from None


def _unquote(text: str) -> str:
    return re.sub(r"\\(.)", r"\1", text[1:-1])


def _show(tok: _Tok) -> str:
    if tok.kind == "eof":
        return "the end of the file"
    text = tok.text if len(tok.text) <= 30 else tok.text[:27] + "..."
    return f"'{text}'"


def describe(value: Value) -> str:
    """A field value as a message shows it: ``a Box node``, ``0 0 0.025``, ``TRUE``."""
    if isinstance(value, Node):
        return f"a {value.type} node"
    if isinstance(value, tuple):
        return " ".join(f"{v:g}" for v in value) or "nothing"
    if isinstance(value, list):
        return "a list"
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if value is None:
        return "NULL"
    return repr(value)
