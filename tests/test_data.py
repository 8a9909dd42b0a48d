"""The test data vendored in tests/data: complete, as its manifest lists it, and unmodified.

The Webots corpus (``tests/data/corpus/webots``) and the robot facts (``tests/data/robot_facts``)
are copies of ``../shared/corpus/webots`` and ``../shared/robots``. Where that folder exists (the
machine the copies were taken on) the copies must still be byte-identical; elsewhere (a fresh
clone, CI) those two comparisons skip, and everything else here runs.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import CORPUS, DATA, ROBOT_FACTS, SHARED

ROBOT_FACT_FILES = ("nao.json", "ur5e.json", "README.md")


def _files(folder: Path) -> dict[str, bytes]:
    """Every file below ``folder``: relative POSIX path -> bytes."""
    return {
        p.relative_to(folder).as_posix(): p.read_bytes()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


def _manifest(corpus: Path) -> list[dict[str, str]]:
    header, *rows = (corpus / "MANIFEST.tsv").read_text(encoding="utf-8").splitlines()
    names = header.split("\t")
    return [dict(zip(names, row.split("\t"), strict=True)) for row in rows]


def test_the_vendored_data_lives_under_tests_data() -> None:
    assert CORPUS.is_relative_to(DATA) and ROBOT_FACTS.is_relative_to(DATA)
    assert not CORPUS.is_relative_to(SHARED) and not ROBOT_FACTS.is_relative_to(SHARED)


def test_every_manifest_file_is_present_with_its_size(corpus: Path) -> None:
    rows = _manifest(corpus)
    assert len(rows) == 27
    for row in rows:
        path = corpus / row["path"]
        assert path.is_file(), f"{row['path']} is in MANIFEST.tsv but not in {corpus}"
        assert path.stat().st_size == int(row["bytes"]), row["path"]
        assert len(row["commit"]) == 40 and int(row["commit"], 16) >= 0, row["path"]


def test_the_corpus_holds_nothing_the_manifest_does_not_list(corpus: Path) -> None:
    listed = {row["path"] for row in _manifest(corpus)}
    assert set(_files(corpus)) == listed | {"MANIFEST.tsv", "NOTICE"}


def test_the_vendored_data_carries_its_licence(corpus: Path, robot_facts: Path) -> None:
    assert "Apache License, Version 2.0" in (corpus / "NOTICE").read_text(encoding="utf-8")
    notice = (robot_facts / "NOTICE").read_text(encoding="utf-8")
    assert "Apache License, Version 2.0" in notice and "BSD 3-Clause" in notice
    for name in ROBOT_FACT_FILES:
        assert (robot_facts / name).is_file(), name


def test_the_vendored_corpus_is_byte_identical_to_shared(corpus: Path) -> None:
    upstream = SHARED / "corpus" / "webots"
    if not upstream.is_dir():
        pytest.skip(f"no upstream corpus at {upstream} to compare with (only the vendored copy)")
    assert _files(corpus) == _files(upstream)


def test_the_vendored_robot_facts_are_byte_identical_to_shared(robot_facts: Path) -> None:
    upstream = SHARED / "robots"
    if not upstream.is_dir():
        pytest.skip(
            f"no upstream robot facts at {upstream} to compare with (only the vendored copy)"
        )
    vendored = _files(robot_facts)
    del vendored["NOTICE"]  # written for the copy
    assert vendored == _files(upstream)


MISSING_DATA_TESTS = {
    "test_param.py": """
import pytest
from conftest import corpus_params

@pytest.mark.parametrize("path", corpus_params())
def test_each_corpus_file(path): pass
""",
    "test_fixtures.py": """
def test_corpus(corpus): pass

def test_robot_facts(robot_facts): pass
""",
}

PYTEST_ARGS = ("-p", "no:cacheprovider", "-rs", "-q", "--continue-on-collection-errors")


def _run_without_data(tmp_path: Path, ci: str | None) -> subprocess.CompletedProcess[str]:
    """Run pytest on tests that need the data, beside a copy of conftest.py with no data."""
    shutil.copy(Path(__file__).with_name("conftest.py"), tmp_path / "conftest.py")
    for name, text in MISSING_DATA_TESTS.items():
        (tmp_path / name).write_text(text, encoding="utf-8")
    env = {k: v for k, v in os.environ.items() if k != "CI"}
    if ci is not None:
        env["CI"] = ci
    return subprocess.run(
        [sys.executable, "-m", "pytest", *PYTEST_ARGS, str(tmp_path)],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )


def test_missing_data_skips_with_a_reason_locally(tmp_path: Path) -> None:
    proc = _run_without_data(tmp_path, ci=None)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "3 skipped" in proc.stdout
    assert f"Webots corpus not found at {tmp_path / 'data' / 'corpus' / 'webots'}" in proc.stdout
    assert f"robot facts JSON not found at {tmp_path / 'data' / 'robot_facts'}" in proc.stdout


def test_missing_data_fails_under_ci(tmp_path: Path) -> None:
    proc = _run_without_data(tmp_path, ci="true")
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert "skipped" not in proc.stdout
    assert "3 errors" in proc.stdout  # one at collection, two in fixture setup
    assert "CI=true: tests do not skip for missing data" in proc.stdout
