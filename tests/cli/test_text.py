"""How numbers, counts and text from the user's files read in the reports for people
(``cli/text.py``)."""

from __future__ import annotations

import pytest

from motiontool.cli.text import num, plural, shown


@pytest.mark.parametrize(
    ("x", "text"), [(0.1, "0.1"), (4.0, "4"), (1e-7, "1e-07"), (123456.7, "123457"), (-0.5, "-0.5")]
)
def test_num_gives_at_most_six_significant_digits(x: float, text: str) -> None:
    assert num(x) == text


def test_plural_adds_an_s_unless_one() -> None:
    assert [plural(n, "file") for n in (0, 1, 2)] == ["0 files", "1 file", "2 files"]


def test_shown_escapes_control_characters() -> None:
    assert shown("joint 'Head\x1b[31mYaw'\r\x07\x7f\x9b ok") == (
        "joint 'Head\\x1b[31mYaw'\\r\\x07\\x7f\\x9b ok"
    )
    assert shown("left\u202etfel, caf\u00e9") == "left\\u202etfel, caf\u00e9"


def test_shown_caps_a_long_run_of_text_with_an_ellipsis() -> None:
    text = shown(f"unknown joint '{'H' * 4000}' for robot nao")
    assert len(text) < 120 and "..." in text
    assert text.startswith("unknown joint 'HHH") and text.endswith("HHH' for robot nao")
    name = "walking-" * 9 + "1.moti"  # 80 characters quoted: as it is
    assert len(name) == 78 and shown(f"cannot read '{name}'") == f"cannot read '{name}'"
    cut = shown(f"cannot read '{name}x'")
    assert len(cut) == len("cannot read ") + 80 and cut.endswith("1.motix'")


def test_shown_keeps_a_path_up_to_240_characters() -> None:
    path = "/home/runner/work/" + "deep/" * 40 + "wave.motion:3:14:"
    assert len(path) < 240 and shown(f"{path} expected") == f"{path} expected"
    cut = shown("/" + "x" * 1000000)
    assert len(cut) == 240 and "..." in cut
