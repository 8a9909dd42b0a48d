"""Shared fixtures: where the golden data, the Webots corpus and the robot facts live.

The Webots corpus and the robot facts the tests need are vendored, unmodified, in ``tests/data``
(``corpus/webots`` with its MANIFEST.tsv and NOTICE, ``robot_facts`` with its README), so a fresh
clone runs every test. Should they be missing, a test that needs them skips with the reason, except
under ``CI=true``, where it fails: CI never passes by skipping.

A test that needs an extra of the package says which: ``@pytest.mark.needs("sim")`` (or a
module's ``pytestmark``). Where the extra's libraries do not import (a core-only install:
``pip install -e .`` and the test tools), it skips with the extra's name and its ``pip install``;
under ``CI=true`` it fails, as missing data does. Which libraries an extra brings is read from
``motiontool.extras.EXTRAS``, the registry the commands' own messages use.
"""

from __future__ import annotations

import functools
import importlib
import os
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path
from types import ModuleType
from typing import Any, NoReturn

import pytest

from motiontool.extras import EXTRAS, install_hint

TESTS = Path(__file__).parent
ROOT = TESTS.parent
DATA = TESTS / "data"
#: The Webots corpus (27 .motion files, MANIFEST.tsv, NOTICE), vendored from ``SHARED``.
CORPUS = DATA / "corpus" / "webots"
#: The robot facts (nao.json, ur5e.json, README.md) that kinematics/models are generated from.
ROBOT_FACTS = DATA / "robot_facts"
#: Where both came from, beside the repository. Only tests/test_data.py looks there, to check
#: that the vendored copies are still byte-identical; no other test needs it.
SHARED = ROOT.parent / "shared"
#: Under CI=true (GitHub Actions, GitLab, ``.ci/run``) missing test data fails instead of skipping.
IN_CI = os.environ.get("CI", "").strip().lower() == "true"

sys.path.insert(0, str(TESTS))  # the plain-loop oracle
# Every test checks its files afresh: the findings a run stores in ~/.cache/motiontool/lint must
# not stand in for the checks another test exercises (tests/cli/test_findings_cache.py turns the
# cache on in a folder of its own).
os.environ["MOTIONTOOL_NO_CACHE"] = "1"
# What the tool keeps on disk (a robot's kinematic tables, configuration files' tables, bag
# URDFs, batch results) goes to a folder of this test process's own, never the user's cache; a
# test that looks at a cache sets XDG_CACHE_HOME to a folder of its own.
_CACHE = tempfile.TemporaryDirectory(prefix="motiontool-test-cache-")
os.environ["XDG_CACHE_HOME"] = _CACHE.name


def missing_data(reason: str) -> NoReturn:
    """Skip the current test (or, at collection, the module) with ``reason``; fail under CI."""
    if IN_CI:
        pytest.fail(f"{reason} (CI=true: tests do not skip for missing data)", pytrace=False)
    pytest.skip(reason)


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line(
        "markers", "needs(*extras): extras of motiontool the test needs (skipped without them)"
    )


@functools.cache
def extra_missing(extra: str) -> str | None:
    """Why ``extra`` is not usable here (``mujoco: No module named 'mujoco'``), or None.

    Each of its libraries is imported, as the commands import it (a broken install, or a stub
    that raises ImportError, counts as missing), once per test process."""
    if extra not in EXTRAS:
        raise pytest.UsageError(f"needs({extra!r}): no such extra (one of {', '.join(EXTRAS)})")
    if extra == "erd":  # robot files, no module to import (6.x): found as the library finds them
        from motiontool.kinematics.erd import erd_root

        return None if erd_root() is not None else "example-robot-data: no robots folder found"
    for module in EXTRAS[extra][0]:
        try:
            importlib.import_module(module)
        except ImportError as exc:
            return f"{module}: {exc}"
    return None


def skip_without(extra: str) -> None:
    """Skip the current test (or, at collection, the module) where ``extra`` is missing, with the
    extra's name and its ``pip install`` in the reason; fail under CI=true."""
    why = extra_missing(extra)
    if why is None:
        return
    reason = f"needs motiontool[{extra}]: {install_hint(extra)} ({why})"
    if IN_CI:
        pytest.fail(f"{reason} (CI=true: tests do not skip for a missing extra)", pytrace=False)
    pytest.skip(reason, allow_module_level=True)


def pytest_runtest_setup(item: pytest.Item) -> None:
    """Skip a test marked ``needs(extra, ...)`` whose extra is missing (fail under CI=true)."""
    for mark in item.iter_markers("needs"):
        for extra in mark.args:
            skip_without(extra)


def import_extra(module: str, extra: str) -> ModuleType:
    """``module`` (``lsprotocol.types``), for a test module that uses an extra's library at its
    top level; where ``extra`` is missing, the test module is skipped (failed under CI=true).
    Everywhere else ``@pytest.mark.needs(extra)`` says it, and the library is imported where
    used."""
    skip_without(extra)
    return importlib.import_module(module)


def dev_module(name: str) -> ModuleType:
    """The script ``dev/NAME.py`` as a module (dev/ is no package): the tests read the lists
    it keeps (``writers``: every output option; ``rules_doc``: the rules page's writer)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(name, ROOT / "dev" / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def calls_of(
    monkeypatch: pytest.MonkeyPatch, owner: object, name: str
) -> list[tuple[tuple[Any, ...], Any]]:
    """Every call of ``owner.name`` from here on, as (its positional arguments, its result);
    the function still runs: what a test counts of the work a check or a reader does."""
    real = getattr(owner, name)
    calls: list[tuple[tuple[Any, ...], Any]] = []

    def recorded(*args: Any, **kwargs: Any) -> Any:
        result = real(*args, **kwargs)
        calls.append((args, result))
        return result

    monkeypatch.setattr(owner, name, recorded)
    return calls


def require(path: Path, what: str) -> Path:
    """``path`` if it exists; otherwise skip with a reason naming it (fail under CI=true)."""
    if not path.exists():
        missing_data(f"{what} not found at {path} (vendored in tests/data; restore it from git)")
    return path


@pytest.fixture(scope="session")
def corpus() -> Path:
    """The vendored Webots corpus folder."""
    return require(CORPUS / "MANIFEST.tsv", "Webots corpus").parent


@pytest.fixture(scope="session")
def robot_facts() -> Path:
    """The vendored robot facts folder (nao.json, ur5e.json)."""
    for name in ("nao.json", "ur5e.json"):
        require(ROBOT_FACTS / name, "robot facts JSON")
    return ROBOT_FACTS


def corpus_files() -> list[Path]:
    return sorted(CORPUS.rglob("*.motion")) if CORPUS.is_dir() else []


def corpus_params() -> list[object]:
    """One parameter per corpus file; without the corpus, one skipped parameter (fails in CI)."""
    files = corpus_files()
    if not files:
        reason = (
            f"Webots corpus not found at {CORPUS} (vendored in tests/data; restore it from git)"
        )
        if IN_CI:  # at collection: the module errors and the run fails
            missing_data(reason)
        return [pytest.param(None, marks=pytest.mark.skip(reason=reason))]
    return [
        pytest.param(f, id=f.name if f.name != "Taichi.motion" else "Taichi-lower") for f in files
    ]


def pre_commit_env(home: Path) -> dict[str, str]:
    """The environment to run pre-commit (and git) in a test repository: this venv's
    ``motiontool`` first on the PATH, pre-commit's cache in ``home``, no user or system git
    configuration."""
    return {
        **os.environ,
        "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}",
        "PRE_COMMIT_HOME": str(home),
        "GIT_CONFIG_GLOBAL": os.devnull,
        "GIT_CONFIG_NOSYSTEM": "1",
    }


def golden(kind: str) -> list[Path]:
    return sorted((DATA / kind).glob("*.motion"))


@pytest.fixture(autouse=True)
def _no_colour_settings_from_the_environment(monkeypatch: pytest.MonkeyPatch) -> None:
    """Outputs are compared as plain text: a NO_COLOR or FORCE_COLOR of the machine running the
    tests must not change them (the colour tests set them where they need them)."""
    monkeypatch.delenv("NO_COLOR", raising=False)
    monkeypatch.delenv("FORCE_COLOR", raising=False)


@pytest.fixture(scope="module")
def one_ray() -> Iterator[None]:
    """Held while a module's tests use Ray: one Ray at a time on this machine, whatever the
    test worker (a local ``ray.init()`` beside a ``ray start`` cluster joins it, and ``ray stop
    --force`` stops every Ray of the user). An exclusive lock on a file, released on exit."""
    import fcntl

    with open(Path(tempfile.gettempdir()) / "motiontool-tests-ray.lock", "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)
