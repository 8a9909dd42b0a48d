"""Shared fixtures: where the golden data and the Webots corpus live."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

TESTS = Path(__file__).parent
ROOT = TESTS.parent
DATA = TESTS / "data"
SHARED = ROOT.parent / "shared"
CORPUS = SHARED / "corpus" / "webots"

sys.path.insert(0, str(TESTS))  # the plain-loop oracle


def corpus_files() -> list[Path]:
    return sorted(CORPUS.rglob("*.motion")) if CORPUS.is_dir() else []


def corpus_params() -> list[object]:
    files = corpus_files()
    if not files:
        return [
            pytest.param(
                None, marks=pytest.mark.skip(reason=f"Webots corpus not found at {CORPUS}")
            )
        ]
    return [
        pytest.param(f, id=f.name if f.name != "Taichi.motion" else "Taichi-lower") for f in files
    ]


def golden(kind: str) -> list[Path]:
    return sorted((DATA / kind).glob("*.motion"))
