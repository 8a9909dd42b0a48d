"""dev/fuzz.py stays runnable: a few inputs, no disagreement (the real runs are by hand)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest
from conftest import CORPUS, ROOT


def test_fuzz_script_runs_clean(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    if not CORPUS.is_dir():
        pytest.skip(f"Webots corpus not found at {CORPUS}")
    spec = importlib.util.spec_from_file_location("fuzz", ROOT / "dev" / "fuzz.py")
    assert spec is not None and spec.loader is not None
    fuzz = importlib.util.module_from_spec(spec)
    monkeypatch.setitem(sys.modules, "fuzz", fuzz)  # its dataclasses look their module up
    spec.loader.exec_module(fuzz)
    code = fuzz.main(["--count", "300", "--seed", "7", "--out", str(tmp_path)])
    out = capsys.readouterr().out
    assert code == 0, out
    assert "fuzz: done: 300 inputs" in out and "failures: none" in out
    assert fuzz.make_input(fuzz.load_corpus(CORPUS), 7, 5) == fuzz.make_input(
        fuzz.load_corpus(CORPUS), 7, 5
    )
