"""The header line, ``#WEBOTS_MOTION,V1.0,<joint>,...``, as Webots reads it: the magic word
(MT101), the version (MT102), a NUL byte (MT114) and the joint names (MT210, MT205)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from motiontool.motionfmt.diagnostics import JOINT_TWICE, NUL_BYTE
from motiontool.motionfmt.lines import Piece, decode_name, separator_hint, show, token_spans

if TYPE_CHECKING:
    from motiontool.motionfmt._read_state import ReadState

__all__ = ["HEADER", "VERSION", "read_header"]

HEADER = b"#WEBOTS_MOTION"
VERSION = b"V1.0"

_BOM = b"\xef\xbb\xbf"


def read_header(state: ReadState, piece: Piece) -> bool:
    """Check the header; return whether the pose lines can be read against it (then
    ``state``'s joints are set)."""
    raw = piece.data
    spans = token_spans(raw)
    tokens = [raw[a:b] for a, b in spans]
    nul = raw.find(b"\0")
    if nul >= 0:
        state.report(NUL_BYTE, piece.line, nul + 1, "NUL byte in the header: Webots stops there")
    if not tokens:
        state.report(
            "MT101",
            piece.line,
            1,
            "the first line is empty; expected the header '#WEBOTS_MOTION,V1.0,<joint>,...'",
            "the header must be the very first line of the file",
        )
        return False
    separated = separator_hint(
        tokens[0], len(HEADER), "'#WEBOTS_MOTION,V1.0,<joint>,...' and 'time,name,value,...'"
    )
    if tokens[0].startswith(HEADER) and separated:  # one cell: no version to check either
        state.report(
            "MT101",
            piece.line,
            spans[0][0] + 1,
            f"expected '#WEBOTS_MOTION' as the first token, found {show(tokens[0])}",
            separated,
            end_column=spans[0][1] + 1,
        )
        return False
    proceed = _magic_word(state, piece.line, tokens[0], spans[0])
    if len(tokens) < 2:
        state.report(
            "MT102",
            piece.line,
            spans[-1][1] + 1,
            "expected the version 'V1.0' after '#WEBOTS_MOTION', found end of line",
            "the header is '#WEBOTS_MOTION,V1.0,<joint>,<joint>,...'",
        )
        return False
    _version(state, piece.line, tokens[1], spans[1])
    if not proceed:
        return False
    state.joint_tokens = tokens[2:]
    state.n_joints = len(state.joint_tokens)
    state.result.joints = [decode_name(t) for t in state.joint_tokens]
    state.header_end = (piece.line, spans[-1][1] + 1)
    _joint_names(state, piece.line, spans[2:])
    return True


def _magic_word(state: ReadState, line: int, first: bytes, span: tuple[int, int]) -> bool:
    """MT101 unless the first token is ``#WEBOTS_MOTION``; whether to go on reading the pose
    lines anyway (the word is recognisably meant, so later findings are worth reporting)."""
    if first == HEADER:
        return True
    hint = None
    proceed = True
    if first.startswith(_BOM):
        hint = "the file starts with a UTF-8 byte-order mark (BOM): save it without BOM"
    elif first.strip() == HEADER:
        hint = "remove the white space around '#WEBOTS_MOTION'"
    elif first.upper() == HEADER:
        hint = "the header is case-sensitive: write '#WEBOTS_MOTION'"
    else:
        proceed = first.strip(b" \t").upper().lstrip(_BOM) == HEADER
    state.report(
        "MT101",
        line,
        span[0] + 1,
        f"expected '#WEBOTS_MOTION' as the first token, found {show(first)}",
        hint,
        end_column=span[1] + 1,
    )
    return proceed or hint is not None


def _version(state: ReadState, line: int, token: bytes, span: tuple[int, int]) -> None:
    """MT102 unless the second token is ``V1.0``."""
    if token == VERSION:
        return
    hint = None
    if token.strip() == VERSION:
        hint = "remove the white space around 'V1.0'"
    elif token.upper() == VERSION.upper():
        hint = "the version is case-sensitive: write 'V1.0'"
    state.report(
        "MT102",
        line,
        span[0] + 1,
        f"expected the version 'V1.0' after '#WEBOTS_MOTION', found {show(token)}",
        hint or "V1.0 is the only version Webots reads",
        end_column=span[1] + 1,
    )


def _joint_names(state: ReadState, line: int, spans: list[tuple[int, int]]) -> None:
    """MT210 for a name with white space around it, MT205 for a name given twice."""
    seen: dict[bytes, int] = {}
    for j, (tok, (a, b)) in enumerate(zip(state.joint_tokens, spans, strict=True)):
        name = state.result.joints[j]
        if tok != tok.strip():
            state.report(
                "MT210",
                line,
                a + 1,
                f"joint name {show(tok)} has leading or trailing white space; Webots looks"
                f" for a motor named exactly that",
                f"write {show(tok.strip())}",
                joint=name,
                end_column=b + 1,
            )
        if tok in seen:
            state.report(
                JOINT_TWICE,
                line,
                a + 1,
                f"joint {show(tok)} is named twice (columns {seen[tok] + 1} and {j + 1});"
                f" both drive the same motor and the later column wins",
                "remove one of the two columns",
                joint=name,
                end_column=b + 1,
            )
        seen[tok] = j
