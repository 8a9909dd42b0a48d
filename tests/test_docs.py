"""The repository's documentation stands on its own: no tracked file cites the
notes beside the repository, every ``docs/*.md`` that is cited exists, and what docs/ states
about playing and simulating is what the code and the play tests do."""

from __future__ import annotations

import ast
import re
import subprocess

import pytest
from conftest import ROOT, TESTS, missing_data

from motiontool.motionfmt import read_bytes, sample

DOCS = ROOT / "docs"

CITES_OUTSIDE = re.compile(r"\.\./shared\b|<shared>|\bFORMAT\.md\b|\bSIM-NOTES\b")
"""A citation of the notes outside the repository (case-sensitive: ``webots-format.md`` is ours)."""

EXEMPT = {
    # Compares the vendored test data with its origin beside the repository, on purpose.
    "tests/test_data.py",
    # This file: it spells the patterns.
    "tests/test_docs.py",
}
"""Files that may name the folder beside the repository. ``dev/fuzz.py`` falls back to the corpus
there by path (``ROOT.parent / "shared"``), which cites nothing, so it needs no exemption."""

PENDING: dict[str, str] = {}
"""Lines in kinematics/ and sim/ that may still cite the notes outside the repository (line
stripped -> what it should cite instead): none are left, all re-cite docs/ or tests/data."""

PENDING_FOLDERS = ("kinematics/", "sim/")


def tracked_texts() -> dict[str, list[str]]:
    """The lines of every tracked text file outside tests/data, by path relative to ROOT."""
    try:
        listed = subprocess.run(
            ["git", "-C", str(ROOT), "ls-files", "-z"], capture_output=True, check=True
        ).stdout
    except (OSError, subprocess.CalledProcessError) as exc:
        missing_data(f"the tracked files need a git checkout of the repository ({exc})")
    out: dict[str, list[str]] = {}
    for name in listed.decode("utf-8", "surrogateescape").split("\0"):
        path = ROOT / name
        if not name or name.startswith("tests/data/") or not path.is_file():
            continue
        data = path.read_bytes()
        if b"\0" in data:  # binary
            continue
        out[name] = data.decode("utf-8", "replace").splitlines()
    return out


def citations_outside() -> list[tuple[str, int, str]]:
    """(path, line number, line) of every citation of the notes outside the repository."""
    return [
        (path, number, line)
        for path, lines in tracked_texts().items()
        if path not in EXEMPT
        for number, line in enumerate(lines, 1)
        if CITES_OUTSIDE.search(line)
    ]


def test_no_tracked_file_cites_the_notes_outside_the_repository() -> None:
    stray = [
        f"{path}:{number}: {line.strip()}"
        for path, number, line in citations_outside()
        if not (path.startswith(PENDING_FOLDERS) and line.strip() in PENDING)
    ]
    assert stray == [], (
        "cite docs/webots-format.md (how Webots reads and plays a file) or docs/simulation.md"
        " (what the simulation models) instead:\n" + "\n".join(stray)
    )


def test_every_pending_citation_is_still_there() -> None:
    # Once a pending line is re-cited, its entry goes: the list only shrinks.
    left = {
        line.strip() for path, _, line in citations_outside() if path.startswith(PENDING_FOLDERS)
    }
    assert sorted(set(PENDING) - left) == []


def test_every_cited_doc_exists() -> None:
    cited = re.compile(r"(?<![\w/.-])docs/[\w-]+\.md\b")
    linked = re.compile(r"\]\(([\w-]+\.md)(?:#[\w-]*)?\)")
    missing = []
    for path, lines in tracked_texts().items():
        for number, line in enumerate(lines, 1):
            targets = [ROOT / m for m in cited.findall(line)]
            if path.startswith("docs/"):
                targets += [ROOT / "docs" / m for m in linked.findall(line)]
            missing += [
                f"{path}:{number}: {t.relative_to(ROOT)}" for t in targets if not t.is_file()
            ]
    assert missing == []
    for doc in ("webots-format.md", "simulation.md"):
        assert (DOCS / doc).is_file()


def _blocks(text: str) -> list[str]:
    return re.findall(r"^```text\n(.*?)^```", text, flags=re.MULTILINE | re.DOTALL)


def test_the_worked_example_is_what_the_player_sends() -> None:
    blocks = _blocks((DOCS / "webots-format.md").read_text(encoding="utf-8"))
    (motion_text,) = [b for b in blocks if b.startswith("#WEBOTS_MOTION")]
    (stream_text,) = [b for b in blocks if b.startswith("time_ms,")]
    step = int(re.search(r"played at T = (\d+) ms", (DOCS / "webots-format.md").read_text())[1])
    stream = sample(read_bytes(motion_text.encode()).motion, step)
    header, *rows = stream_text.splitlines()
    assert header.split(",")[1:] == list(stream.joints)
    assert [int(r.split(",")[0]) for r in rows] == stream.elapsed_ms.tolist()
    for row, targets, sent in zip(rows, stream.targets, stream.commanded, strict=True):
        cells = row.split(",")[1:]
        assert [float(c) if c else None for c in cells] == [
            float(v) if s else None for v, s in zip(targets, sent, strict=True)
        ], row


def _corpus_bands() -> dict[str, object]:
    """WALKS and TURNS of tests/sim/test_corpus.py, read without importing it (it needs MuJoCo)."""
    tree = ast.parse((TESTS / "sim" / "test_corpus.py").read_text(encoding="utf-8"))
    return {
        target.id: ast.literal_eval(node.value)
        for node in tree.body
        if isinstance(node, ast.Assign)
        for target in node.targets
        if isinstance(target, ast.Name) and target.id in {"WALKS", "TURNS"}
    }


def _band(quantity: str, band: tuple[float, float], unit: str) -> str:
    return f"{quantity} {band[0]:g}…{band[1]:g}{unit}"


@pytest.mark.parametrize("table", ["WALKS", "TURNS"])
def test_the_documented_bands_are_the_play_tests_bands(table: str) -> None:
    text = (DOCS / "simulation.md").read_text(encoding="utf-8").replace("−", "-")
    rows = {
        cells[1].strip(): cells[2]
        for line in text.splitlines()
        if line.startswith("| ") and len(cells := line.split("|")) > 3
    }
    bands = _corpus_bands()[table]
    assert isinstance(bands, dict) and bands
    for name, band in bands.items():
        if table == "TURNS":
            expected = [_band("yaw", band, "°")]
        else:
            dx, dy = band
            expected = [_band("dx", dx, " m")] + ([_band("dy", dy, " m")] if dy else [])
        for part in expected:
            assert part in rows[name], (name, part, rows[name])


ISSUE_REFERENCE = re.compile(r"\b[Ii]ssues? [0-9]+")
"""A pointer into this project's issue tracker, which a reader of the repository does not have:
code, tests and docs say what they do in their own words (the CHANGELOG may name issues)."""


def test_no_tracked_file_points_into_the_issue_tracker() -> None:
    found = [
        f"{path}:{number}: {line.strip()}"
        for path, lines in tracked_texts().items()
        if path not in ("CHANGELOG.md", "tests/test_docs.py")
        for number, line in enumerate(lines, 1)
        if ISSUE_REFERENCE.search(line)
    ]
    assert found == [], "\n".join(found)
