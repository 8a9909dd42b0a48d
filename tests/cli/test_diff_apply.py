"""``validate --diff`` is a patch the real tools apply: ``git apply`` and
``patch -p1`` accept it over many files that mix CRLF, no final newline, UTF-8 and bytes that
are not UTF-8, and give the same bytes as ``--fix``."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

HEADER = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch"

FILES: dict[str, bytes] = {
    # CRLF, the fix in the middle, a blank line kept (its fix is unsafe).
    "crlf.motion": HEADER + b"\r\n0,P,2rad,0\r\n100,Q,1,1\r\n\r\n200,R,0,0\r\n",
    # No final newline, the fix on the last line.
    "last.motion": HEADER + b"\n0,P,0,0\n100,Q,1,2rad",
    # No final newline, the last line only context of a fix above it.
    "context.motion": HEADER + b"\n0,P,0,-9999999.9\n100,Q,1,1",
    # A UTF-8 name and pose names, CRLF without a final newline.
    "pos\u00e9s \u00fc.motion": HEADER + "\r\n0,Pos\u00e9,2rad,0\r\n100,\u00dc,1,1".encode(),
    # A pose name that is not UTF-8 (MT208, kept as it is); carriage returns that end no line.
    "latin1.motion": HEADER + b"\n0,Pos\xe9,1.5rad,0\n100,Q\r,1,1\n200,S,0,0\r\r\n",
    # Names git quotes (a tab, a quote, a backslash), and a name that is not UTF-8.
    'tab\t"q"\\.motion': HEADER + b"\n0,P,2rad,0\n",
    "name\udce9.motion": HEADER + b"\n0,P,2rad,0\n",
    # Nothing to fix: no diff.
    "clean.motion": HEADER + b"\n0,P,0,0\n",
}


@pytest.fixture
def repo(tmp_path: Path) -> Path:
    """A git repository holding :data:`FILES` and a copy of them fixed by ``--fix``."""
    work, fixed = tmp_path / "work", tmp_path / "fixed"
    for folder in (work, fixed):
        folder.mkdir()
        for name, data in FILES.items():
            (folder / name).write_bytes(data)
    _motiontool(fixed, "validate", "--fix", *FILES)
    assert (fixed / "last.motion").read_bytes().endswith(b"100,Q,1,2")  # --fix did fix
    subprocess.run(["git", "init", "-q"], cwd=work, check=True)
    return work


def _motiontool(cwd: Path, *args: str) -> subprocess.CompletedProcess[bytes]:
    script = shutil.which("motiontool", path=str(Path(sys.executable).parent))
    assert script is not None, "the installed motiontool script"
    return subprocess.run([script, *args], cwd=cwd, capture_output=True, check=False)


def _diff(work: Path) -> bytes:
    result = _motiontool(work, "validate", "--diff", *sorted(FILES))
    assert result.returncode == 1, result.stderr
    assert result.stderr == b""
    return result.stdout


def _same_as_fixed(work: Path) -> None:
    fixed = work.parent / "fixed"
    for name in FILES:
        assert (work / name).read_bytes() == (fixed / name).read_bytes(), name


def test_the_diff_marks_a_missing_final_newline_and_starts_each_file_on_its_own_line(
    repo: Path,
) -> None:
    patch = _diff(repo)
    assert b"-100,Q,1,2rad\n\\ No newline at end of file\n+100,Q,1,2\n" in patch
    assert b"\n\\ No newline at end of file\n--- a/latin1.motion\n" in patch
    for line in patch.split(b"\n"):
        assert b"--- a/" not in line or line.startswith(b"--- a/"), line
    assert b"clean.motion" not in patch


def test_git_apply_gives_what_fix_writes(repo: Path) -> None:
    (repo.parent / "fix.patch").write_bytes(_diff(repo))
    subprocess.run(["git", "apply", "--check", "../fix.patch"], cwd=repo, check=True)
    subprocess.run(["git", "apply", "../fix.patch"], cwd=repo, check=True)
    _same_as_fixed(repo)


@pytest.mark.skipif(shutil.which("patch") is None, reason="GNU patch is not installed")
def test_patch_p1_gives_what_fix_writes(repo: Path) -> None:
    (repo.parent / "fix.patch").write_bytes(_diff(repo))
    subprocess.run(
        ["patch", "-p1", "--batch", "--quiet", "-i", "../fix.patch"],
        cwd=repo,
        check=True,
        env={**os.environ, "LC_ALL": "C"},
    )
    _same_as_fixed(repo)
