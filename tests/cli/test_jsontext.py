"""``jsontext.indented`` writes exactly what ``json.dumps(indent=2, ensure_ascii=False)`` writes
(the reports' findings go through it; the standard library writes indented JSON in pure
Python), for any JSON value: nested, with lists of plain dicts (a fix's edits, written by the
C encoder at once) and strings that look like the text between them."""

from __future__ import annotations

import json
import math
from typing import Any

from hypothesis import given, settings
from hypothesis import strategies as st

from motiontool.cli.jsontext import indented

_TRICKY = ["}", "},", "},\n  {", "{", "[", "]", '"', "\\", "\n", "\u2028", "\udcff", "é", ""]
_TEXT = st.one_of(st.text(max_size=8), st.sampled_from(_TRICKY))
_PLAIN = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-(2**70), 2**70),
    st.floats(allow_nan=True, allow_infinity=True),
    _TEXT,
)
_KEYS = st.one_of(_TEXT, st.integers(-5, 5))
_FLAT = st.dictionaries(_KEYS, _PLAIN, max_size=4)


def _values() -> st.SearchStrategy[Any]:
    return st.recursive(
        _PLAIN | _FLAT,
        lambda inner: (
            st.lists(inner, max_size=4)
            | st.lists(_FLAT, max_size=5)
            | st.lists(inner, max_size=3).map(tuple)
            | st.dictionaries(_KEYS, inner, max_size=4)
        ),
        max_leaves=30,
    )


@settings(max_examples=600, deadline=None)
@given(_values())
def test_indented_is_json_dumps(value: Any) -> None:
    assert indented(value) == json.dumps(value, indent=2, ensure_ascii=False)


def test_a_list_of_plain_dicts_and_its_look_alikes() -> None:
    edits = [{"line": i, "column": 3, "replacement": "},\n  {"} for i in range(3)]
    for value in (
        {"edits": edits},
        [{"a": 1}, {}],
        [{}, {"a": 1}],
        [{"a": 1}, 2],
        [{"a": {"b": 1}}, {"a": 2}],
        [{"a": math.nan, "b": -math.inf, 3: None}],
        ({"a": (1,)},),
    ):
        assert indented(value) == json.dumps(value, indent=2, ensure_ascii=False), value
