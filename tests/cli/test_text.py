"""How numbers and counts read in the reports for people (``cli/text.py``)."""

from __future__ import annotations

import pytest

from motiontool.cli.text import num, plural


@pytest.mark.parametrize(
    ("x", "text"), [(0.1, "0.1"), (4.0, "4"), (1e-7, "1e-07"), (123456.7, "123457"), (-0.5, "-0.5")]
)
def test_num_gives_at_most_six_significant_digits(x: float, text: str) -> None:
    assert num(x) == text


def test_plural_adds_an_s_unless_one() -> None:
    assert [plural(n, "file") for n in (0, 1, 2)] == ["0 files", "1 file", "2 files"]
